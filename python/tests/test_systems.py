"""Transfer functions and state space from Python: construction from expressions and
arrays, properties, interconnection and operators, margins and step figures against
hand-computed values."""
import math
import unittest

import numpy as np

import dmbd


class Construction(unittest.TestCase):
    def test_expression_and_coefficients_agree(self):
        g = dmbd.tf("2/(s^2 + 3*s + 2)")
        h = dmbd.TransferFunction([2.0], [1.0, 3.0, 2.0])
        np.testing.assert_allclose(g.num, h.num, rtol=1e-15)
        np.testing.assert_allclose(g.den, [1.0, 3.0, 2.0], rtol=1e-15)
        self.assertEqual((g.order, g.relative_degree, g.is_proper, g.is_strictly_proper), (2, 2, True, True))
        self.assertEqual(g.ts, 0.0)
        self.assertFalse(g.is_discrete)
        self.assertAlmostEqual(g.dc_gain(), 1.0, places=15)
        self.assertTrue(g.is_stable())
        self.assertEqual(repr(h), "TransferFunction([2.0], [1.0, 3.0, 2.0])")

    def test_denominator_made_monic(self):
        g = dmbd.TransferFunction([3.0], [0.5, 1.0])
        np.testing.assert_allclose(g.den, [1.0, 2.0])
        np.testing.assert_allclose(g.num, [6.0])

    def test_parameters(self):
        g = dmbd.tf("1/(s/wc + 1)", params={"wc": 10.0})
        np.testing.assert_allclose(g.poles(), [-10.0])

    def test_evaluation_at_points(self):
        g = dmbd.tf("1/(s + 1)")
        self.assertAlmostEqual(g(1j), 1 / (1 + 1j))
        vals = g(np.array([[0.0, 1j], [2.0, -3.0 + 0j]]))
        self.assertEqual(vals.shape, (2, 2))
        np.testing.assert_allclose(vals, 1 / (np.array([[0.0, 1j], [2.0, -3.0]]) + 1))

    def test_state_space_from_arrays(self):
        sys = dmbd.ss([[0.0, 1.0], [-2.0, -3.0]], [0.0, 1.0], [1.0, 0.0])
        self.assertEqual((sys.num_states, sys.num_inputs, sys.num_outputs), (2, 1, 1))
        self.assertEqual(sys.B.shape, (2, 1))
        self.assertEqual(sys.C.shape, (1, 2))
        np.testing.assert_array_equal(sys.D, [[0.0]])
        g = dmbd.tf(sys)
        np.testing.assert_allclose(g.num, [1.0], atol=1e-14)
        np.testing.assert_allclose(g.den, [1.0, 3.0, 2.0], rtol=1e-12)
        np.testing.assert_allclose(sys(1j), [[1 / ((1j) ** 2 + 3j + 2)]])
        np.testing.assert_allclose(sys.dc_gain(), [[0.5]])

    def test_state_space_from_a_transfer_function(self):
        g = dmbd.tf("(s + 4)/(s^2 + 2*s + 10)")
        sys = dmbd.ss(g)
        self.assertEqual(sys.num_states, 2)
        w = np.logspace(-1, 2, 20)
        np.testing.assert_allclose(dmbd.freqresp(sys, w), dmbd.freqresp(g, w), rtol=1e-12)

    def test_select_and_index(self):
        sys = dmbd.ss(np.diag([-1.0, -2.0]), np.eye(2), np.eye(2))
        self.assertAlmostEqual(dmbd.dc_gain(sys[1, 1]), 0.5)
        self.assertEqual(dmbd.dc_gain(sys[0, 1]), 0.0)
        np.testing.assert_allclose(dmbd.dc_gain(sys), [[1.0, 0.0], [0.0, 0.5]])
        with self.assertRaises(IndexError):
            sys[2, 0]

    def test_infinite_dc_gain_is_none(self):
        self.assertIsNone(dmbd.tf("1/s").dc_gain())
        self.assertIsNone(dmbd.dc_gain(dmbd.tf("1/(s*(s+1))")))


class Interconnection(unittest.TestCase):
    def test_series_parallel_feedback_of_transfer_functions(self):
        a, b = dmbd.tf("1/(s+1)"), dmbd.tf("2/(s+3)")
        np.testing.assert_allclose(dmbd.series(a, b).den, [1.0, 4.0, 3.0])
        np.testing.assert_allclose(dmbd.parallel(a, b).num, [3.0, 5.0])
        closed = dmbd.feedback(a, b)  # a / (1 + a b) = (s + 3) / (s^2 + 4 s + 5)
        np.testing.assert_allclose(closed.num, [1.0, 3.0])
        np.testing.assert_allclose(closed.den, [1.0, 4.0, 5.0])
        positive = dmbd.feedback(a, b, sign=+1)  # (s + 3) / (s^2 + 4 s + 1)
        np.testing.assert_allclose(positive.den, [1.0, 4.0, 1.0])

    def test_operators_with_numbers(self):
        g = dmbd.tf("1/(s+1)")
        np.testing.assert_allclose((2 * g).num, [2.0])
        np.testing.assert_allclose((g + 1).num, [1.0, 2.0])
        np.testing.assert_allclose((1 - g).num, [1.0, 0.0])
        np.testing.assert_allclose((g ** 2).den, [1.0, 2.0, 1.0])
        np.testing.assert_allclose((-g).num, [-1.0])
        np.testing.assert_allclose((1 / g).num, [1.0, 1.0])

    def test_mixed_operands_give_state_space(self):
        g = dmbd.tf("1/(s+1)")
        sys = dmbd.ss(dmbd.tf("1/(s+2)"))
        for combined in (g * sys, sys * g, g + sys, sys - g, dmbd.series(g, sys), dmbd.feedback(sys, g)):
            self.assertIsInstance(combined, dmbd.StateSpace)
        w = np.array([0.3, 3.0])
        np.testing.assert_allclose(dmbd.freqresp(g * sys, w), 1 / ((1j * w + 1) * (1j * w + 2)), rtol=1e-12)
        np.testing.assert_allclose(dmbd.freqresp(sys - g, w), 1 / (1j * w + 2) - 1 / (1j * w + 1), rtol=1e-12)

    def test_series_order_of_state_space(self):
        # u -> first -> second: y = second(first(u)); with a 2-output first, the sizes
        # only fit one way round.
        first = dmbd.ss(-1.0, 1.0, [[1.0], [2.0]])
        second = dmbd.ss(-2.0, [[1.0, 1.0]], 1.0)
        sys = dmbd.series(first, second)
        self.assertEqual((sys.num_inputs, sys.num_outputs), (1, 1))
        self.assertAlmostEqual(dmbd.dc_gain(sys), 1.5)
        self.assertAlmostEqual(dmbd.dc_gain(second * first), 1.5)

    def test_append(self):
        sys = dmbd.append(dmbd.tf("1/(s+1)"), dmbd.tf("3/(s+3)"))
        np.testing.assert_allclose(sys.dc_gain(), np.eye(2), atol=1e-15)

    def test_minimal_refuses_a_tolerance_that_is_not_a_finite_number_at_least_0(self):
        # Issue 28, row 11: NaN and inf gave the zero system (DC gain 0).
        g = dmbd.ss([[-1.0]], [1.0], [1.0])
        for tol in (float("nan"), float("inf"), -1e-9):
            with self.assertRaisesRegex(dmbd.InputError, "minimal: the tolerance 'tol' must be a finite number >= 0"):
                g.minimal(tol)
        self.assertEqual(g.minimal().num_states, 1)
        self.assertAlmostEqual(dmbd.dc_gain(g.minimal()), 1.0, places=14)

    def test_sample_times_must_agree(self):
        with self.assertRaises(dmbd.InputError):
            dmbd.tf("1/(z - 0.5)", ts=0.1) * dmbd.tf("1/(z - 0.5)", ts=0.2)


class Analysis(unittest.TestCase):
    def test_margins_by_hand(self):
        # L = 2/(s (s+1) (s+2)): the phase crosses -180 deg at w = sqrt(2), where
        # |L| = 2/6, so the gain margin is 20 log10(3); the gain crossover solves
        # x (x+1) (x+4) = 4 with x = w^2.
        m = dmbd.margins(dmbd.tf("2/(s*(s+1)*(s+2))"))
        self.assertAlmostEqual(m["phase_crossover_rad_s"], math.sqrt(2.0), delta=1e-9 * math.sqrt(2.0))
        self.assertAlmostEqual(m["gain_margin_db"], 20 * math.log10(3.0), delta=1e-9 * 20 * math.log10(3.0))
        x = max(r.real for r in np.roots([1.0, 5.0, 4.0, -4.0]) if abs(r.imag) < 1e-12 and r.real > 0)
        wc = math.sqrt(x)
        pm = 180.0 + math.degrees(-math.pi / 2 - math.atan(wc) - math.atan(wc / 2))
        self.assertAlmostEqual(m["gain_crossover_rad_s"], wc, delta=1e-9 * wc)
        self.assertAlmostEqual(m["phase_margin_deg"], pm, delta=1e-9 * pm)
        self.assertEqual(len(m["gain_crossovers"]), 1)
        self.assertAlmostEqual(m["gain_crossovers"][0]["phase_margin_deg"], pm, delta=1e-9 * pm)
        self.assertEqual(len(m["phase_crossovers"]), 1)

    def test_no_crossover_is_none(self):
        m = dmbd.margins(dmbd.tf("0.5/(s+1)"))
        self.assertIsNone(m["gain_margin_db"])
        self.assertIsNone(m["phase_margin_deg"])
        self.assertEqual(m["gain_crossovers"], [])

    def test_step_figures_of_a_second_order_system(self):
        zeta, wn = 0.5, 4.0
        g = dmbd.tf("wn^2/(s^2 + 2*zeta*wn*s + wn^2)", params={"wn": wn, "zeta": zeta})
        info = dmbd.step_info(g)
        overshoot = 100 * math.exp(-zeta * math.pi / math.sqrt(1 - zeta**2))
        self.assertAlmostEqual(info["overshoot_pct"], overshoot, delta=1e-6 * overshoot)
        self.assertAlmostEqual(info["peak_time_s"], math.pi / (wn * math.sqrt(1 - zeta**2)), delta=1e-6)
        self.assertAlmostEqual(info["final_value"], 1.0, places=12)
        self.assertGreater(dmbd.step_horizon(g), info["settling_time_s"])

    def test_step_needs_equally_spaced_times(self):
        g = dmbd.tf("1/(s+1)")
        with self.assertRaisesRegex(dmbd.InputError, "equally spaced"):
            dmbd.step(g, [0.0, 0.1, 0.3])
        with self.assertRaisesRegex(dmbd.InputError, "multiples"):
            dmbd.step(dmbd.tf("0.5/(z - 0.5)", ts=0.1), np.linspace(0.0, 1.0, 7))

    def test_stability_and_bandwidth(self):
        self.assertEqual(dmbd.stability(dmbd.tf("1/(s+1)")), "stable")
        self.assertEqual(dmbd.stability(dmbd.tf("1/(s*(s+1))")), "marginal")
        self.assertEqual(dmbd.stability(dmbd.tf("1/(s-1)")), "unstable")
        self.assertEqual(dmbd.stability(dmbd.tf("1/(z - 1.5)", ts=0.1)), "unstable")
        # |G| = 10^(-3/20) at w = 10 sqrt(10^(3/10) - 1) (-3 dB exactly, not half power)
        wb = 10.0 * math.sqrt(10 ** 0.3 - 1.0)
        self.assertAlmostEqual(dmbd.bandwidth(dmbd.tf("1/(s/10 + 1)")), wb, delta=1e-9 * wb)
        self.assertIsNone(dmbd.bandwidth(dmbd.tf("1/s")))

    def test_frequency_grid_covers_the_poles(self):
        w = dmbd.frequency_grid(dmbd.tf("1/((s+1)*(s+100))"), 50)
        self.assertEqual(len(w), 50)
        self.assertLessEqual(w[0], 0.01 + 1e-12)
        self.assertGreaterEqual(w[-1], 1e4 - 1e-8)

    def test_c2d_keeps_the_type_and_maps_the_poles(self):
        g = dmbd.tf("1/(s+2)")
        gd = dmbd.c2d(g, 0.1, "zoh")
        np.testing.assert_allclose(dmbd.poles(gd), [math.exp(-0.2)], rtol=1e-14)
        np.testing.assert_allclose(dmbd.poles(dmbd.d2c(gd, "zoh")), [-2.0], rtol=1e-12)
        sd = dmbd.c2d(dmbd.ss(g), 0.1, "tustin", prewarp_rad_s=2.0)
        self.assertIsInstance(sd, dmbd.StateSpace)
        self.assertEqual(sd.ts, 0.1)


if __name__ == "__main__":
    unittest.main()
