"""Certified stability verdicts and poles near the boundary from Python (issue 28,
rows 1, 1b and 3): the verdict of a transfer function's coefficients and factors
exactly as given; golden values from closed forms (ZOH maps p to e^{pT} and keeps the
DC gain)."""
import math
import unittest

import numpy as np

import dmbd


class CertifiedVerdicts(unittest.TestCase):
    def test_zoh_of_two_slow_lags_is_stable_with_its_dc_gain(self):
        # Row 1: was poles [0.999997, 1.0], "marginal", no DC gain.
        gd = dmbd.c2d(dmbd.tf("1/((s+0.01)*(s+0.02))"), 1e-4, "zoh")
        np.testing.assert_allclose(sorted(dmbd.poles(gd).real), [math.exp(-0.02e-4), math.exp(-0.01e-4)],
                                   rtol=0, atol=1e-15)
        self.assertEqual(dmbd.stability(gd), "stable")
        self.assertAlmostEqual(dmbd.dc_gain(gd), 5000.0, delta=5000.0 * 1e-9)

    def test_a_z_polynomial_5e7_inside_the_circle_is_stable(self):
        # Row 1b: was "marginally stable", a pole at exactly 1, DC gain infinite.
        gd = dmbd.c2d(dmbd.tf("1/(s^2+10*s+100)"), 1e-7, "zoh")
        self.assertEqual(dmbd.stability(gd), "stable")
        self.assertAlmostEqual(dmbd.dc_gain(gd), 0.01, delta=0.01 * 1e-12)
        for p in dmbd.poles(gd):
            self.assertAlmostEqual(abs(p), math.exp(-5e-7), delta=1e-15)
        g = dmbd.tf("1/(z^2-1.9999989999994998*z+0.9999990000004998)", ts=1e-7)
        self.assertEqual(dmbd.stability(g), "stable")
        for p in dmbd.poles(g):
            self.assertAlmostEqual(abs(p), 1.0 - 5e-7, delta=1e-9)
        # 1/p(1), p(1) = 9.999778782798785e-13 exactly (fractions).
        self.assertAlmostEqual(dmbd.dc_gain(g), 1000022122209.5028, delta=1000022122209.5028 * 1e-12)

    def test_a_power_of_a_factor_keeps_its_roots(self):
        # Row 3: twenty poles exactly at -1.
        p = dmbd.poles(dmbd.tf("1/(s+1)^20"))
        self.assertEqual(len(p), 20)
        self.assertTrue(all(r == -1.0 for r in p))

    def test_undecided_where_the_enclosure_straddles(self):
        self.assertEqual(dmbd.stability(dmbd.tf("1/(s^2 + 1e-300*s + 1)")), "undecided")
        self.assertEqual(dmbd.stability(dmbd.tf("1/(s^2 + 1)")), "marginal")  # a factor on the axis by its form
        self.assertEqual(dmbd.stability(dmbd.tf("1/((s^2 + 1)^2)")), "unstable")


if __name__ == "__main__":
    unittest.main()
