"""dmbd against SciPy on cases of the tests' own: poles, Bode and step responses of
transfer functions of several orders (one with a lightly damped pair), a state-space
model, discrete systems (from an expression in z and from c2d) and interconnections,
all to the 1e-9 relative tolerance of agreement.py."""
import unittest
import warnings

import numpy as np
import scipy.signal as sig

import dmbd
from agreement import RTOL, assert_bode, assert_poles, assert_step, worst_errors


def tearDownModule():
    worst_errors()


# Continuous cases: (name, dmbd system, (num, den) for SciPy), each different in order,
# zeros and damping.
WN, ZETA = 2 * np.pi * 5.0, 0.02  # a lightly damped pair: 5 Hz, 2 % damping
DEN5 = np.real(np.poly([-1.0, -2.0 + 3.0j, -2.0 - 3.0j, -0.5 + 0.8j, -0.5 - 0.8j]))
CONTINUOUS = [
    ("first order", dmbd.TransferFunction([3.0], [0.5, 1.0]), ([3.0], [0.5, 1.0])),
    ("lightly damped pair", dmbd.tf("wn^2/(s^2 + 2*zeta*wn*s + wn^2)", params={"wn": WN, "zeta": ZETA}),
     ([WN**2], [1.0, 2 * ZETA * WN, WN**2])),
    ("third order with a zero", dmbd.tf("4*(s+3)/((s+1)*(s^2+2*s+5))"),
     ([4.0, 12.0], np.polymul([1.0, 1.0], [1.0, 2.0, 5.0]))),
    ("fifth order, two zeros", dmbd.tf([0.5, 2.0, 1.0], DEN5), ([0.5, 2.0, 1.0], DEN5)),
    ("non-minimum phase", dmbd.tf("20*(1 - 0.1*s)/((s+2)*(s+10))"),
     ([-2.0, 20.0], np.polymul([1.0, 2.0], [1.0, 10.0]))),
]


def scipy_bode(num, den, w):
    _, mag, phase = sig.bode((num, den), w=w)
    return mag, phase


def scipy_step(num, den, t):
    _, y = sig.step((num, den), T=t)
    return y


class Continuous(unittest.TestCase):
    def test_poles(self):
        for name, g, (num, den) in CONTINUOUS:
            with self.subTest(name):
                assert_poles(self, dmbd.poles(g), np.roots(den), name)

    def test_zeros(self):
        for name, g, (num, den) in CONTINUOUS:
            with self.subTest(name):
                ref = np.roots(num)
                if len(ref):
                    assert_poles(self, dmbd.zeros(g), ref, name + " (zeros)")
                else:
                    self.assertEqual(len(dmbd.zeros(g)), 0)

    def test_bode(self):
        for name, g, (num, den) in CONTINUOUS:
            with self.subTest(name):
                w = np.logspace(-2, 3, 300)
                mag, phase = dmbd.bode(g, w)
                assert_bode(self, mag, phase, *scipy_bode(num, den, w), name)

    def test_bode_through_the_resonance(self):
        # Dense around the 2 % damped pair's peak, where a pole error shows most.
        _, g, (num, den) = CONTINUOUS[1]
        w = np.linspace(0.9 * WN, 1.1 * WN, 201)
        mag, phase = dmbd.bode(g, w)
        assert_bode(self, mag, phase, *scipy_bode(num, den, w), "resonance")
        peak_db, _ = dmbd.bode(g, [WN * np.sqrt(1 - 2 * ZETA**2)])  # the peak, 1/(2 zeta sqrt(1 - zeta^2))
        self.assertAlmostEqual(peak_db[0], 20 * np.log10(1 / (2 * ZETA * np.sqrt(1 - ZETA**2))), delta=1e-9)

    def test_step(self):
        for name, g, (num, den) in CONTINUOUS:
            with self.subTest(name):
                t = np.linspace(0.0, 8.0, 801)
                assert_step(self, dmbd.step(g, t), scipy_step(num, den, t), name)

    def test_freqresp_is_the_bode_response(self):
        _, g, (num, den) = CONTINUOUS[2]
        w = np.logspace(-1, 2, 50)
        _, h_ref = sig.freqresp((num, den), w=w)
        h = dmbd.freqresp(g, w)
        self.assertLessEqual(np.max(np.abs(h - h_ref) / np.abs(h_ref)), RTOL)


class StateSpaceModel(unittest.TestCase):
    """A 4-state, 2-input, 2-output model from arrays."""

    A = np.array([[-1.0, 2.0, 0.0, 0.5], [-2.0, -1.0, 0.3, 0.0], [0.0, 0.0, -3.0, 1.0], [0.2, 0.0, -1.0, -0.4]])
    B = np.array([[1.0, 0.0], [0.0, 0.5], [1.0, 1.0], [0.0, 2.0]])
    C = np.array([[1.0, 0.0, 0.0, 1.0], [0.0, 1.0, 1.0, 0.0]])
    D = np.array([[0.0, 0.1], [0.0, 0.0]])

    def setUp(self):
        self.sys = dmbd.ss(self.A, self.B, self.C, self.D)

    def test_poles_are_the_eigenvalues(self):
        assert_poles(self, dmbd.poles(self.sys), np.linalg.eigvals(self.A), "4-state model")

    def test_each_channel(self):
        w = np.logspace(-2, 2, 200)
        t = np.linspace(0.0, 10.0, 1001)
        for i in range(2):
            for j in range(2):
                with self.subTest(output=i, input=j):
                    ref = sig.StateSpace(self.A, self.B[:, [j]], self.C[[i], :], self.D[i:i + 1, j:j + 1])
                    _, y_ref = sig.step(ref, T=t)
                    assert_step(self, dmbd.step(self.sys[i, j], t), y_ref, f"channel {i},{j}")
                    # Reference: C (jwI - A)^-1 B + D solved directly (NumPy).
                    h = np.array([self.C[i] @ np.linalg.solve(1j * x * np.eye(4) - self.A, self.B[:, j]) + self.D[i, j]
                                  for x in w])
                    mag, phase = dmbd.bode(self.sys[i, j], w)
                    assert_bode(self, mag, phase, 20 * np.log10(np.abs(h)), np.rad2deg(np.unwrap(np.angle(h))),
                                f"channel {i},{j}")

    def test_mimo_frequency_response(self):
        w = np.array([0.1, 1.0, 10.0])
        h = dmbd.freqresp(self.sys, w)
        self.assertEqual(h.shape, (3, 2, 2))
        for k, x in enumerate(w):
            ref = self.C @ np.linalg.solve(1j * x * np.eye(4) - self.A, self.B) + self.D
            self.assertLessEqual(np.max(np.abs(h[k] - ref)) / np.max(np.abs(ref)), RTOL)


class Discrete(unittest.TestCase):
    TS = 0.01

    def check(self, g, ref, name):
        """Poles, Bode up to Nyquist and the step response of a discrete system against a
        SciPy dlti: given as a transfer function, its roots, dbode and dstep; given in
        state space (cont2discrete's own form), the eigenvalues of A, the response
        C (zI - A)^-1 B + D solved directly (NumPy) and dstep."""
        ts = g.ts
        w = np.logspace(-1, np.log10(0.99 * np.pi / ts), 200)
        if isinstance(ref, sig.TransferFunction):
            ref_poles = np.roots(ref.den)
            _, mag_ref, phase_ref = sig.dbode(ref, w=w * ts)  # SciPy takes rad/sample
        else:
            ref_poles = np.linalg.eigvals(ref.A)
            n = ref.A.shape[0]
            h = np.array([(ref.C @ np.linalg.solve(np.exp(1j * x * ts) * np.eye(n) - ref.A, ref.B) + ref.D)[0, 0]
                          for x in w])
            mag_ref, phase_ref = 20 * np.log10(np.abs(h)), np.rad2deg(np.unwrap(np.angle(h)))
        assert_poles(self, dmbd.poles(g), ref_poles, name)
        mag, phase = dmbd.bode(g, w)
        assert_bode(self, mag, phase, mag_ref, phase_ref, name)
        n = 300
        _, (y_ref,) = sig.dstep(ref, n=n)
        assert_step(self, dmbd.step(g, np.arange(n) * ts), y_ref[:, 0], name)

    def test_expression_in_z(self):
        g = dmbd.tf("(0.1*z + 0.05)/(z^2 - 1.5*z + 0.7)", ts=self.TS)
        self.assertTrue(g.is_discrete)
        self.check(g, sig.dlti([0.1, 0.05], [1.0, -1.5, 0.7], dt=self.TS), "expression in z")

    def test_c2d_against_cont2discrete(self):
        # SciPy discretises in state space; its transfer-function result goes back
        # through ss2tf, which loses digits (it warns of badly conditioned coefficients),
        # so the reference is its state-space result, and the coefficients are compared
        # to the digits that round trip keeps. A discrete transfer function held as
        # coefficients, with its poles within 0.02 of z = 1, is itself good to about
        # 1e-10 near DC (den(z) cancels there): dmbd's c2d of this system is 7e-11
        # (Tustin) and 1.6e-10 (backward Euler) from the exact discretisation, hence the
        # worst agreement of this file, still within RTOL.
        _, g, (num, den) = CONTINUOUS[2]
        for method, scipy_method in [("zoh", "zoh"), ("tustin", "bilinear"), ("backward-euler", "backward_diff")]:
            with self.subTest(method):
                gd = dmbd.c2d(g, self.TS, method)
                self.assertIsInstance(gd, dmbd.TransferFunction)
                self.assertEqual(gd.ts, self.TS)
                ad, bd, cd, dd, _ = sig.cont2discrete(sig.tf2ss(num, den), self.TS, method=scipy_method)
                self.check(gd, sig.dlti(ad, bd, cd, dd, dt=self.TS), "c2d " + method)
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore", sig.BadCoefficients)
                    num_d, den_d, _ = sig.cont2discrete((num, den), self.TS, method=scipy_method)
                np.testing.assert_allclose(gd.den, den_d, rtol=1e-8)
                np.testing.assert_allclose(gd.num, np.trim_zeros(np.ravel(num_d), "f"), rtol=1e-6, atol=1e-12)

    def test_c2d_of_a_state_space_model(self):
        sys = dmbd.ss(StateSpaceModel.A, StateSpaceModel.B, StateSpaceModel.C, StateSpaceModel.D)
        for method, scipy_method in [("zoh", "zoh"), ("tustin", "bilinear")]:
            with self.subTest(method):
                ad, bd, cd, dd, _ = sig.cont2discrete((sys.A, sys.B, sys.C, sys.D), self.TS, method=scipy_method)
                sd = dmbd.c2d(sys, self.TS, method)
                self.assertIsInstance(sd, dmbd.StateSpace)
                self.assertEqual(sd.ts, self.TS)
                assert_poles(self, dmbd.poles(sd), np.linalg.eigvals(ad), "c2d " + method)
                self.check(sd[0, 0], sig.dlti(ad, bd[:, [0]], cd[[0], :], dd[:1, :1], dt=self.TS),
                           "c2d (state space) " + method)


class Interconnection(unittest.TestCase):
    """A PI controller in series with a third-order plant, unity negative feedback (closed
    loop: a pair at 16 % damping); the reference is the closed loop by polynomial
    arithmetic (NumPy) and SciPy."""

    def setUp(self):
        self.C = dmbd.tf("(Kp*s + Ki)/s", params={"Kp": 0.2, "Ki": 1.0})
        self.P = dmbd.tf("50/(s^2 + 4*s + 25)/(0.1*s + 1)")
        cn, cd = [0.2, 1.0], [1.0, 0.0]
        pn, pd = [50.0], np.polymul([1.0, 4.0, 25.0], [0.1, 1.0])
        ln, ld = np.polymul(cn, pn), np.polymul(cd, pd)
        self.num, self.den = ln, np.polyadd(ld, ln)

    def compare(self, closed, name):
        assert_poles(self, dmbd.poles(closed), np.roots(self.den), name)
        w = np.logspace(-2, 2, 300)
        mag, phase = dmbd.bode(closed, w)
        assert_bode(self, mag, phase, *scipy_bode(self.num, self.den, w), name)
        t = np.linspace(0.0, 20.0, 2001)
        assert_step(self, dmbd.step(closed, t), scipy_step(self.num, self.den, t), name)

    def test_transfer_functions(self):
        closed = dmbd.feedback(dmbd.series(self.C, self.P))
        self.assertIsInstance(closed, dmbd.TransferFunction)
        self.compare(closed, "feedback(series(C, P))")

    def test_operators(self):
        L = self.P * self.C
        closed = L / (1 + L)  # (Ln Ld) / (Ld (Ld + Ln)): Ld cancels
        self.assertEqual(closed.order, 8)
        self.compare(closed.minreal(), "L / (1 + L), minreal")

    def test_state_space(self):
        closed = dmbd.feedback(dmbd.ss(self.P) * dmbd.ss(self.C), 1.0)
        self.assertIsInstance(closed, dmbd.StateSpace)
        self.assertEqual(closed.num_states, 4)
        self.compare(closed, "feedback(ss(P) * ss(C))")

    def test_parallel(self):
        both = dmbd.parallel(self.C, self.P)
        ref_num = np.polyadd(np.polymul([0.2, 1.0], np.polymul([1.0, 4.0, 25.0], [0.1, 1.0])), np.polymul([50.0], [1.0, 0.0]))
        ref_den = np.polymul([1.0, 0.0], np.polymul([1.0, 4.0, 25.0], [0.1, 1.0]))
        w = np.logspace(-1, 2, 100)
        mag, phase = dmbd.bode(both, w)
        assert_bode(self, mag, phase, *scipy_bode(ref_num, ref_den, w), "parallel(C, P)")


if __name__ == "__main__":
    unittest.main()
