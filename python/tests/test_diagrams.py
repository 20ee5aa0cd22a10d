"""Diagrams from Python: a diagram file loaded, linearised between two signals and
compared with its transfer functions computed by hand; a malformed one raises
DiagramError with the file:line:column message."""
import pathlib
import re
import unittest

import numpy as np

import dmbd

DATA = pathlib.Path(__file__).resolve().parent / "data"
EXAMPLES = pathlib.Path(__file__).resolve().parents[2] / "examples"


def coefficients_close(tc, g, num, den, what):
    """g's num/den against the hand-computed ones (den monic), 1e-12 relative to the
    largest coefficient."""
    for got, ref, part in ((g.num, num, "num"), (g.den, den, "den")):
        got, ref = np.trim_zeros(np.asarray(got), "f"), np.asarray(ref, dtype=float)
        tc.assertEqual(len(got), len(ref), f"{what}: {part} {got} vs {ref}")
        tc.assertLessEqual(np.max(np.abs(got - ref)), 1e-12 * np.max(np.abs(ref)), f"{what}: {part} {got} vs {ref}")


class PiLoop(unittest.TestCase):
    # C = (Kp s + Ki)/s = (2 s + 3)/s, P = 1/(s^2 + 3 s + 2), unity negative feedback:
    #   r -> y:        C P / (1 + C P) = (2 s + 3) / (s^3 + 3 s^2 + 4 s + 3)
    #   r -> err.out:  1 / (1 + C P)   = (s^3 + 3 s^2 + 2 s) / (s^3 + 3 s^2 + 4 s + 3)
    #   loop at plant.out: L = C P     = (2 s + 3) / (s^3 + 3 s^2 + 2 s)
    CLOSED_DEN = [1.0, 3.0, 4.0, 3.0]

    def setUp(self):
        self.d = dmbd.load_diagram(DATA / "pi_loop.yaml")

    def test_description(self):
        d = self.d
        self.assertEqual(d.name, "pi_loop")
        self.assertEqual((d.inputs, d.outputs), (["r"], ["y"]))
        self.assertEqual(d.blocks, ["err", "C", "plant"])
        self.assertEqual(d.parameters, {"Kp": 2.0, "Ki": 3.0})
        self.assertFalse(d.is_discrete)
        self.assertIn("plant.out", d.signals)

    def test_linearize_closed_loop(self):
        sys = self.d.linearize("r", "y")
        self.assertIsInstance(sys, dmbd.StateSpace)
        self.assertEqual(sys.num_states, 3)
        coefficients_close(self, dmbd.tf(sys), [2.0, 3.0], self.CLOSED_DEN, "r -> y")
        coefficients_close(self, self.d.transfer("r", "y"), [2.0, 3.0], self.CLOSED_DEN, "transfer r -> y")
        np.testing.assert_allclose(np.sort_complex(dmbd.poles(sys)), np.sort_complex(np.roots(self.CLOSED_DEN)), rtol=1e-12)

    def test_sensitivity(self):
        coefficients_close(self, dmbd.tf(self.d.linearize("r", "err.out")), [1.0, 3.0, 2.0, 0.0], self.CLOSED_DEN, "r -> err")

    def test_loop_transfer(self):
        L = self.d.loop_transfer("plant.out")
        coefficients_close(self, dmbd.tf(L), [2.0, 3.0], [1.0, 3.0, 2.0, 0.0], "loop at plant.out")

    def test_margins_of_the_loop_transfer(self):
        # L = (2 s + 3)/(s (s + 1)(s + 2)): the gain crossover solves
        # |2 jw + 3|^2 = w^2 |(jw + 1)(jw + 2)|^2, i.e. x^3 + 5 x^2 - 9 = 0 with x = w^2.
        x = max(r.real for r in np.roots([1.0, 5.0, 0.0, -9.0]) if abs(r.imag) < 1e-12 and r.real > 0)
        wc = np.sqrt(x)
        pm = 180.0 + np.degrees(np.arctan2(2 * wc, 3.0) - np.pi / 2 - np.arctan(wc) - np.arctan(wc / 2))
        m = dmbd.margins(self.d.loop_transfer("plant.out"))
        self.assertAlmostEqual(m["gain_crossover_rad_s"], wc, delta=1e-9 * wc)
        self.assertAlmostEqual(m["phase_margin_deg"], pm, delta=1e-9 * pm)

    def test_margins_of_the_loop_as_a_transfer_function(self):
        # The same margins from the transfer function's coefficients.
        x = max(r.real for r in np.roots([1.0, 5.0, 0.0, -9.0]) if abs(r.imag) < 1e-12 and r.real > 0)
        wc = np.sqrt(x)
        pm = 180.0 + np.degrees(np.arctan2(2 * wc, 3.0) - np.pi / 2 - np.arctan(wc) - np.arctan(wc / 2))
        m = dmbd.margins(dmbd.tf(self.d.loop_transfer("plant.out")))
        self.assertAlmostEqual(m["gain_crossover_rad_s"], wc, delta=1e-9 * wc)
        self.assertAlmostEqual(m["phase_margin_deg"], pm, delta=1e-9 * pm)

    def test_parameters_override(self):
        # Kp = 1, Ki = 3: (s + 3) / (s^3 + 3 s^2 + 3 s + 3)
        d = self.d.with_parameters({"Kp": 1.0})
        self.assertEqual(d.parameters["Kp"], 1.0)
        coefficients_close(self, d.transfer("r", "y"), [1.0, 3.0], [1.0, 3.0, 3.0, 3.0], "Kp = 1")
        d2 = dmbd.load_diagram(str(DATA / "pi_loop.yaml"), params={"Ki": 0.5})
        coefficients_close(self, d2.transfer("r", "y"), [2.0, 0.5], [1.0, 3.0, 4.0, 0.5], "Ki = 0.5")

    def test_unknown_signal(self):
        with self.assertRaisesRegex(dmbd.InputError, "nosuch"):
            self.d.linearize("r", "nosuch.out")

    def test_example_diagram_matches_the_cli_transfer(self):
        # The paper's force loop: linearize's model and the structural transfer agree.
        d = dmbd.load_diagram(EXAMPLES / "diagrams" / "force_dob.yaml")
        sys = d.linearize("F_d", "F")
        g = d.transfer("F_d", "F")
        w = np.logspace(0, 3, 30)
        np.testing.assert_allclose(dmbd.freqresp(sys, w), dmbd.freqresp(g, w), rtol=1e-7)


class Malformed(unittest.TestCase):
    def test_diagram_error_carries_file_line_column(self):
        path = str(DATA / "bad_diagram.yaml")
        with self.assertRaises(dmbd.DiagramError) as cm:
            dmbd.load_diagram(path)
        e = cm.exception
        self.assertIsInstance(e, dmbd.InputError)
        self.assertIsInstance(e, ValueError)
        self.assertRegex(str(e), re.escape(path) + r":7:\d+: error: .*gian")
        self.assertEqual([(f, line) for f, line, _, _ in e.diagnostics], [(path, 7)])

    def test_endless_device_is_refused_at_once(self):
        # issue 28 row 8: a bounded read; /dev/zero is not text at its first byte
        with self.assertRaisesRegex(dmbd.DiagramError, r"/dev/zero:1:1: .*the file is not text: byte 1 is 0x00"):
            dmbd.load_diagram("/dev/zero")

    def test_missing_file(self):
        with self.assertRaisesRegex(dmbd.DiagramError, "No such file or directory"):
            dmbd.load_diagram(DATA / "no_such_diagram.yaml")


if __name__ == "__main__":
    unittest.main()
