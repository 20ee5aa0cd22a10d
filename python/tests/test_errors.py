"""The library's errors as Python exceptions: the hierarchy under dmbd.InputError (a
ValueError), each carrying the library's message unchanged, with its extra fields."""
import unittest

import numpy as np

import dmbd


class Hierarchy(unittest.TestCase):
    def test_every_kind_is_an_input_error(self):
        self.assertTrue(issubclass(dmbd.InputError, ValueError))
        for kind in (dmbd.OutputError, dmbd.ExpressionError, dmbd.DiagramError, dmbd.ModelError, dmbd.DivergenceError):
            self.assertTrue(issubclass(kind, dmbd.InputError), kind)
        self.assertEqual(dmbd.DiagramError.__module__, "dmbd")


class Messages(unittest.TestCase):
    def test_expression_error_names_the_column(self):
        with self.assertRaises(dmbd.ExpressionError) as cm:
            dmbd.tf("1/(s + 2*)")
        e = cm.exception
        self.assertEqual(e.column, 10)
        self.assertTrue(str(e).startswith("tf '1/(s + 2*)': column 10: "), str(e))

    def test_unknown_parameter(self):
        with self.assertRaisesRegex(dmbd.ExpressionError, "wc"):
            dmbd.tf("1/(s/wc + 1)")

    def test_variable_and_sample_time(self):
        with self.assertRaisesRegex(dmbd.InputError, "needs a sample time"):
            dmbd.tf("1/(z - 0.5)")
        with self.assertRaisesRegex(dmbd.InputError, "uses both s and z"):
            dmbd.tf("s/z", ts=0.1)
        with self.assertRaisesRegex(dmbd.InputError, "continuous"):
            dmbd.tf("1/(s+1)", ts=0.1)

    def test_library_checks_arrive_unchanged(self):
        with self.assertRaisesRegex(dmbd.InputError, "tustin"):
            dmbd.c2d(dmbd.tf("1/(s+1)"), 0.1, "trapezoid")
        with self.assertRaises(dmbd.InputError):
            dmbd.ss(np.eye(2), np.ones((3, 1)), np.ones((1, 2)))  # B has 3 rows, A 2
        with self.assertRaisesRegex(dmbd.InputError, "one input and one output"):
            dmbd.bode(dmbd.ss(np.eye(2) * -1, np.eye(2), np.eye(2)), [1.0])
        with self.assertRaisesRegex(dmbd.InputError, "proper"):
            dmbd.step(dmbd.tf("s^2/(s+1)"), np.linspace(0, 1, 11))

    def test_type_errors(self):
        with self.assertRaises(TypeError):
            dmbd.poles("1/(s+1)")
        with self.assertRaises(TypeError):
            dmbd.TransferFunction(["a"], [1.0])
        with self.assertRaises(TypeError):
            dmbd.TransferFunction([1j], [1.0, 1.0])


if __name__ == "__main__":
    unittest.main()
