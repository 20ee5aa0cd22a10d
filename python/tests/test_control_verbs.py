"""python-control's verbs (docs/python.md, "python-control's verbs") against SciPy and
NumPy, like for like: forced/step/impulse/initial responses against scipy.signal.lsim,
dlsim and impulse with the same hold; lqr/dlqr against scipy.linalg.solve_continuous_are
and solve_discrete_are; place by the eigenvalues of A - BK (and the unique single-input
gain against scipy.signal.place_poles); Nyquist points against scipy.signal.freqresp and
the encirclement count against the winding of a dense SciPy curve; root loci against
numpy.roots of den + k num; margins at their crossings against SciPy's response there and
a closed form; the result objects' shapes and tuple unpacking as python-control's.
Relative tolerance RTOL = 1e-9 unless a test says otherwise; the worst errors are printed
when the module ends."""
import contextlib
import io
import unittest
import warnings

import numpy as np
import scipy.linalg as sl
import scipy.optimize as so
import scipy.signal as sig

import dmbd

RTOL = 1e-9
_worst = {}


def record(kind, err):
    _worst[kind] = max(_worst.get(kind, 0.0), float(err))
    return err


def tearDownModule():
    print("\nworst relative errors against SciPy/NumPy: " +
          ", ".join(f"{k} {v:.2g}" for k, v in sorted(_worst.items())))


def rel(a, ref):
    """max |a - ref| / max |ref| (arrays of the same shape)."""
    a, ref = np.asarray(a), np.asarray(ref)
    assert a.shape == ref.shape, (a.shape, ref.shape)
    return float(np.max(np.abs(a - ref)) / max(np.max(np.abs(ref)), 1e-300))


def root_error(p, ref):
    """Each reference root matched to its nearest remaining root: the largest |p - r| / max(|r|, 1)."""
    p = list(np.asarray(p, dtype=complex))
    worst = 0.0
    for r in sorted(np.asarray(ref, dtype=complex), key=lambda z: -abs(z)):
        k = int(np.argmin([abs(x - r) for x in p]))
        worst = max(worst, abs(p.pop(k) - r) / max(abs(r), 1.0))
    return worst


# A 4-state, 2-input, 2-output model (lightly damped pair, a real pole, coupling, D != 0).
A4 = np.array([[0.0, 1.0, 0.0, 0.0], [-4.0, -0.4, 1.0, 0.0], [0.0, 0.0, -2.0, 1.0], [0.5, 0.0, 0.0, -3.0]])
B4 = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 0.5], [0.0, 1.0]])
C4 = np.array([[1.0, 0.0, 0.5, 0.0], [0.0, 0.0, 0.0, 2.0]])
D4 = np.array([[0.0, 0.1], [0.0, 0.0]])
SYS4 = dmbd.ss(A4, B4, C4, D4)


class TimeResponses(unittest.TestCase):
    T = np.linspace(0.0, 6.0, 601)

    def test_forced_response_is_lsim_with_linear_input(self):
        U = np.vstack([np.sin(1.3 * self.T), np.where(self.T > 2.0, 1.0, 0.0) * self.T])
        X0 = np.array([0.5, -1.0, 0.2, 0.0])
        r = dmbd.forced_response(SYS4, self.T, U, X0)
        _, y_ref, x_ref = sig.lsim((A4, B4, C4, D4), U.T, self.T, X0, interp=True)
        self.assertLessEqual(record("forced_response outputs", rel(r.outputs, y_ref.T)), RTOL)
        self.assertLessEqual(record("forced_response states", rel(r.states, x_ref.T)), RTOL)
        np.testing.assert_array_equal(r.inputs, U)
        t, y = r  # python-control's legacy unpacking
        self.assertIs(t, r.time)
        self.assertEqual(y.shape, (2, 601))

    def test_discrete_forced_response_is_dlsim(self):
        ts = 0.05
        sysd = dmbd.c2d(SYS4, ts, "zoh")
        T = np.arange(120) * ts
        U = np.vstack([np.cos(T), np.ones_like(T)])
        r = dmbd.forced_response(sysd, T, U, 0.1)
        _, y_ref, x_ref = sig.dlsim((sysd.A, sysd.B, sysd.C, sysd.D, ts), U.T, T, np.full(4, 0.1))
        self.assertLessEqual(record("discrete forced_response", rel(r.outputs, y_ref.T)), RTOL)
        self.assertLessEqual(rel(r.states, x_ref.T), RTOL)
        r2 = dmbd.forced_response(sysd, U=U, X0=0.1)  # T from U's length and ts
        np.testing.assert_array_equal(r2.outputs, r.outputs)

    def test_siso_transfer_function_shapes_and_return_x(self):
        g = dmbd.tf("4*(s+3)/((s+1)*(s^2+2*s+5))")
        u = np.sin(2.0 * self.T)
        r = dmbd.forced_response(g, self.T, u, return_x=True)
        _, y_ref, _ = sig.lsim(([4.0, 12.0], np.polymul([1.0, 1.0], [1.0, 2.0, 5.0])), u, self.T, interp=True)
        self.assertEqual(r.outputs.shape, (601,))
        self.assertEqual(r.inputs.shape, (601,))
        self.assertEqual(r.states.shape, (3, 601))
        self.assertLessEqual(record("forced_response outputs", rel(r.outputs, y_ref)), RTOL)
        t, y, x = r
        self.assertEqual((len(r), x.shape), (3, (3, 601)))
        self.assertEqual(r(squeeze=False).outputs.shape, (1, 601))  # python-control's response(squeeze=...)
        self.assertEqual(len(r(return_x=False)), 2)
        self.assertEqual(dmbd.forced_response(g, self.T, u, squeeze=False).outputs.shape, (1, 601))

    def test_step_response_of_every_input(self):
        r = dmbd.step_response(SYS4, self.T)
        self.assertEqual(r.outputs.shape, (2, 2, 601))
        self.assertEqual(r.states.shape, (4, 2, 601))
        self.assertEqual(r.ntraces, 2)
        for i in range(2):
            U = np.zeros((601, 2))
            U[:, i] = 1.0
            _, y_ref, _ = sig.lsim((A4, B4, C4, D4), U, self.T)
            self.assertLessEqual(record("step_response", rel(r.outputs[:, i, :], y_ref.T)), RTOL)
        one = dmbd.step_response(SYS4, self.T, input=1, output=0)
        self.assertEqual(one.outputs.shape, (601,))
        np.testing.assert_array_equal(one.outputs, r.outputs[0, 1])

    def test_siso_step_is_scipy_step(self):
        num, den = [2.0, 1.0], [1.0, 0.6, 4.0]
        t, y = dmbd.step_response(dmbd.tf(num, den), self.T)
        _, y_ref = sig.step((num, den), T=self.T)
        self.assertEqual(y.shape, (601,))
        self.assertLessEqual(record("step_response", rel(y, y_ref)), RTOL)

    def test_impulse_response(self):
        num, den = [2.0, 1.0], [1.0, 0.6, 4.0]
        t, y = dmbd.impulse_response(dmbd.tf(num, den), self.T)
        _, y_ref = sig.impulse((num, den), T=self.T)
        self.assertLessEqual(record("impulse_response", rel(y, y_ref)), RTOL)
        # D != 0: the delta is left out with a warning (python-control's convention).
        with self.assertWarnsRegex(UserWarning, "direct feedthrough"):
            r = dmbd.impulse_response(SYS4, self.T)
        _, y_ref, _ = sig.lsim((A4, B4, C4, D4), np.zeros((601, 2)), self.T, X0=B4[:, 1])
        self.assertLessEqual(record("impulse_response", rel(r.outputs[:, 1, :], y_ref.T)), RTOL)
        # Discrete: the pulse of area 1 (1/dt at k = 0) is scipy's unit pulse over dt.
        ts = 0.1
        gd = dmbd.c2d(dmbd.tf(num, den), ts, "zoh")
        T = np.arange(50) * ts
        t, y = dmbd.impulse_response(gd, T)
        _, (y_ref,) = sig.dimpulse((gd.num, gd.den, ts), t=T)
        self.assertLessEqual(record("impulse_response", rel(y, y_ref[:, 0] / ts)), RTOL)

    def test_initial_response(self):
        X0 = np.array([1.0, 0.0, -0.5, 0.3])
        r = dmbd.initial_response(SYS4, self.T, X0)
        _, y_ref, x_ref = sig.lsim((A4, B4, C4, D4), np.zeros((601, 2)), self.T, X0)
        self.assertIsNone(r.inputs)
        self.assertLessEqual(record("initial_response", rel(r.outputs, y_ref.T)), RTOL)
        self.assertEqual(dmbd.initial_response(SYS4, self.T, X0, output=1).outputs.shape, (601,))

    def test_default_times_and_mistakes(self):
        g = dmbd.tf("1/(s+1)")
        t, y = dmbd.step_response(g)
        self.assertEqual(len(t), 1000)
        self.assertAlmostEqual(t[-1], dmbd.step_horizon(g), places=12)
        t, y = dmbd.step_response(g, 3.0, T_num=31)
        self.assertEqual((len(t), t[-1]), (31, 3.0))
        # NumPy scalars are numbers as for python-control.
        np.testing.assert_array_equal(dmbd.step_response(g, np.int64(3), T_num=31).outputs, y)
        np.testing.assert_array_equal(dmbd.initial_response(SYS4, self.T, np.int64(1)).outputs,
                                      dmbd.initial_response(SYS4, self.T, 1.0).outputs)
        gd = dmbd.c2d(g, 0.1, "zoh")
        t, y = dmbd.step_response(gd, 1.0)
        np.testing.assert_allclose(t, np.arange(11) * 0.1, rtol=0, atol=1e-15)
        with self.assertRaisesRegex(dmbd.InputError, "forced_response: T: time values must be equally spaced"):
            dmbd.forced_response(g, [0.0, 0.1, 0.3], 1.0)
        with self.assertRaisesRegex(dmbd.InputError, "forced_response: U: expected shape"):
            dmbd.forced_response(SYS4, self.T, np.ones(601))
        with self.assertRaisesRegex(dmbd.InputError, "sample time"):
            dmbd.forced_response(gd, np.arange(5) * 0.2, 1.0)


class StateFeedback(unittest.TestCase):
    Q = np.diag([10.0, 1.0, 2.0, 1.0])
    R = np.array([[1.0, 0.2], [0.2, 0.5]])
    N = np.array([[0.1, 0.0], [0.0, 0.2], [0.3, 0.0], [0.0, 0.1]])

    def check_gains(self, K, S, E, S_ref, K_ref, A, B, kind):
        self.assertLessEqual(record(kind + " S", rel(S, S_ref)), RTOL)
        self.assertLessEqual(record(kind + " K", rel(K, K_ref)), RTOL)
        self.assertLessEqual(record(kind + " E", root_error(E, np.linalg.eigvals(A - B @ K_ref))), RTOL)

    def test_lqr_is_scipy_care(self):
        for N in (None, self.N):
            K, S, E = dmbd.lqr(A4, B4, self.Q, self.R) if N is None else dmbd.lqr(A4, B4, self.Q, self.R, N)
            S_ref = sl.solve_continuous_are(A4, B4, self.Q, self.R, s=N)
            K_ref = np.linalg.solve(self.R, B4.T @ S_ref + (0 if N is None else N.T))
            self.check_gains(K, S, E, S_ref, K_ref, A4, B4, "lqr")
            self.assertEqual((K.shape, S.shape, E.shape), ((2, 4), (4, 4), (4,)))
        K2, S2, E2 = dmbd.lqr(SYS4, self.Q, self.R)
        np.testing.assert_array_equal(K2, dmbd.lqr(A4, B4, self.Q, self.R)[0])

    def test_dlqr_is_scipy_dare(self):
        sysd = dmbd.c2d(SYS4, 0.1, "zoh")
        Ad, Bd = sysd.A, sysd.B
        for N in (None, self.N):
            K, S, E = dmbd.dlqr(Ad, Bd, self.Q, self.R) if N is None else dmbd.dlqr(Ad, Bd, self.Q, self.R, N)
            S_ref = sl.solve_discrete_are(Ad, Bd, self.Q, self.R, s=N)
            K_ref = np.linalg.solve(self.R + Bd.T @ S_ref @ Bd, Bd.T @ S_ref @ Ad + (0 if N is None else N.T))
            self.check_gains(K, S, E, S_ref, K_ref, Ad, Bd, "dlqr")
        np.testing.assert_array_equal(dmbd.lqr(sysd, self.Q, self.R)[0], dmbd.dlqr(Ad, Bd, self.Q, self.R)[0])
        with self.assertRaisesRegex(dmbd.InputError, "dlqr: the system is continuous"):
            dmbd.dlqr(SYS4, self.Q, self.R)

    def test_double_integrator_closed_form(self):
        K, S, E = dmbd.lqr([[0, 1], [0, 0]], [0, 1], np.eye(2), 1.0)
        np.testing.assert_allclose(K, [[1.0, np.sqrt(3.0)]], rtol=1e-14)
        np.testing.assert_allclose(S, [[np.sqrt(3.0), 1.0], [1.0, np.sqrt(3.0)]], rtol=1e-14)

    def test_place_several_inputs(self):
        p = [-1.0 + 2.0j, -1.0 - 2.0j, -3.0, -4.0]
        K = dmbd.place(A4, B4, p)
        self.assertEqual(K.shape, (2, 4))
        self.assertLessEqual(record("place eig(A - BK)", root_error(np.linalg.eigvals(A4 - B4 @ K), p)), RTOL)

    def test_place_single_input_is_the_unique_gain(self):
        b = B4[:, :1]
        p = [-1.0, -2.0, -1.5 + 1.0j, -1.5 - 1.0j]
        K = dmbd.place(A4, b, p)
        K_ref = sig.place_poles(A4, b, p).gain_matrix
        self.assertLessEqual(record("place single input K", rel(K, K_ref)), RTOL)
        self.assertLessEqual(record("place eig(A - BK)", root_error(np.linalg.eigvals(A4 - b @ K), p)), RTOL)
        # A repeated pole with one input (SciPy refuses it): (s + 2)^4 on a chain of integrators.
        chain = np.diag(np.ones(3), 1)
        K = dmbd.place(chain, [0, 0, 0, 1], [-2, -2, -2, -2])
        np.testing.assert_allclose(K, [[16.0, 32.0, 24.0, 8.0]], rtol=1e-12)

    def test_mistakes(self):
        with self.assertRaisesRegex(dmbd.InputError, "lqr: R: expected a positive definite matrix"):
            dmbd.lqr(A4, B4, self.Q, -self.R)
        with self.assertRaisesRegex(dmbd.InputError, "lqr: no stabilising solution"):
            dmbd.lqr(np.diag([1.0, -1.0]), [0.0, 1.0], np.eye(2), 1.0)
        with self.assertRaisesRegex(dmbd.InputError, "place: .*not controllable"):
            dmbd.place(np.diag([1.0, 2.0]), [1.0, 0.0], [-1.0, -2.0])
        with self.assertRaisesRegex(dmbd.InputError, "place: poles: the complex pole"):
            dmbd.place(A4, B4, [-1 + 1j, -2, -3, -4])


class FrequencyVerbs(unittest.TestCase):
    NUM, DEN = [1.0], [1.0, 3.0, 2.0, 0.0]  # 1/(s (s+1) (s+2))

    def test_margin_closed_form_and_scipy(self):
        g = dmbd.tf(self.NUM, self.DEN)
        gm, pm, wcg, wcp = dmbd.margin(g)
        # Phase -180 at w^2 = 2, where |L| = 1/6: gm = 6 (a ratio).
        self.assertAlmostEqual(gm, 6.0, delta=1e-12)
        self.assertAlmostEqual(wcg, np.sqrt(2.0), delta=1e-12)
        _, h = sig.freqresp((self.NUM, self.DEN), [wcg, wcp])
        self.assertLessEqual(abs(np.abs(h[1]) - 1.0), 1e-12)  # |L(j wcp)| = 1
        self.assertLessEqual(abs(pm - (180.0 + np.degrees(np.angle(h[1])))), 1e-9)
        gm6, pm6, sm, wpc, wgc, wms = dmbd.stability_margins(g)
        self.assertEqual((gm6, pm6, wpc, wgc), (gm, pm, wcg, wcp))
        # sm: SciPy's response minimised by SciPy's bounded scalar search.
        f = lambda w: abs(1.0 + sig.freqresp((self.NUM, self.DEN), [w])[1][0])
        ref = so.minimize_scalar(f, bounds=(0.3, 3.0), method="bounded", options={"xatol": 1e-10})
        self.assertLessEqual(record("stability margin sm", abs(sm - ref.fun) / ref.fun), RTOL)
        self.assertAlmostEqual(wms, ref.x, delta=1e-5)  # a flat minimum: its place to sqrt(eps)

    def test_no_crossover_and_all_crossings(self):
        gm, pm, wcg, wcp = dmbd.margin(dmbd.tf("0.5/(s+1)"))
        self.assertEqual((gm, pm), (np.inf, np.inf))
        self.assertTrue(np.isnan(wcg) and np.isnan(wcp))
        gms, pms, sms, wpcs, wgcs, wmss = dmbd.stability_margins(dmbd.tf(self.NUM, self.DEN), returnall=True)
        self.assertEqual((len(gms), len(pms)), (1, 1))
        with self.assertRaisesRegex(dmbd.InputError, "margin: needs one input and one output"):
            dmbd.margin(SYS4)

    def test_nyquist_points_and_count(self):
        num, den = [10.0], np.poly([-1.0, -1.0, -1.0])
        w = np.linspace(0.0, 20.0, 401)
        r = dmbd.nyquist_response(dmbd.tf(num, den), w)
        _, h = sig.freqresp((num, den), w)
        self.assertLessEqual(record("nyquist points", rel(r.response, h)), RTOL)
        np.testing.assert_array_equal(r.contour, 1j * w)
        # python-control's count from a dense SciPy curve: the winding of 1 + L over 0..inf.
        wd = np.concatenate([[0.0], np.logspace(-3, 4, 20000)])
        _, hd = sig.freqresp((num, den), wd)
        winding = np.sum(np.diff(-np.unwrap(np.angle(hd + 1.0)))) / np.pi
        self.assertEqual(r.count, int(np.round(winding)))
        self.assertEqual(r.count, 2)  # k = 10 > 8: two closed-loop poles in the right half plane
        (count,) = r
        count, contour = dmbd.nyquist_response(dmbd.tf(num, den), w, return_contour=True)
        self.assertEqual((count, len(contour)), (2, 401))

    def test_discrete_nyquist_and_warning(self):
        ts = 0.05
        gd = dmbd.c2d(dmbd.tf("5/((s+1)*(s+2))"), ts, "zoh")
        w = np.linspace(0.0, np.pi / ts, 300)
        r = dmbd.nyquist_response(gd, w)
        _, h = sig.dfreqresp((gd.num, gd.den, ts), w * ts)
        self.assertLessEqual(record("nyquist points", rel(r.response, h)), RTOL)
        self.assertEqual(r.count, 0)
        with self.assertWarnsRegex(UserWarning, "criterion"):  # a range that misses the crossing
            dmbd.nyquist_response(dmbd.tf([10.0], np.poly([-1.0, -1.0, -1.0])), [0.0, 0.5])

    def test_root_locus_is_numpy_roots(self):
        num, den = [1.0, 3.0], np.polymul([1.0, 1.0], [1.0, 0.4, 4.0])
        gains = np.linspace(0.0, 10.0, 41)
        for sys in (dmbd.tf(num, den), dmbd.ss(dmbd.tf(num, den))):
            d = dmbd.root_locus_map(sys, gains)
            self.assertEqual(d.loci.shape, (41, 3))
            worst = max(root_error(d.loci[i], np.roots(np.polyadd(den, k * np.asarray(num))))
                        for i, k in enumerate(gains))
            self.assertLessEqual(record("root locus", worst), RTOL)
        np.testing.assert_array_equal(d.gains, gains)
        poles, zeros = dmbd.pole_zero_map(dmbd.tf(num, den))
        self.assertLessEqual(root_error(poles, np.roots(den)), RTOL)
        self.assertLessEqual(root_error(zeros, np.roots(num)), RTOL)
        self.assertEqual(len(dmbd.root_locus_map(dmbd.tf(num, den)).gains), 201)

    def test_damp_and_dcgain(self):
        g = dmbd.tf("3/(s^2 + s + 4)")
        wn, zeta, p = dmbd.damp(g, doprint=False)
        np.testing.assert_allclose(wn, [2.0, 2.0], rtol=1e-15)
        np.testing.assert_allclose(zeta, [0.25, 0.25], rtol=1e-14)
        gd = dmbd.c2d(g, 0.1, "zoh")
        wn_d, zeta_d, _ = dmbd.damp(gd, doprint=False)  # s = log(z)/dt: the continuous pair again
        np.testing.assert_allclose(wn_d, [2.0, 2.0], rtol=1e-12)
        np.testing.assert_allclose(zeta_d, [0.25, 0.25], rtol=1e-12)
        self.assertEqual(dmbd.dcgain(g), 0.75)
        self.assertEqual(dmbd.dcgain(dmbd.tf("-1/(s*(s+1))")), -np.inf)
        # The printed table shows the returned damping: -1 for an unstable real pole.
        out = io.StringIO()
        with contextlib.redirect_stdout(out):
            _, zeta_u, p_u = dmbd.damp(dmbd.tf("1/((s - 2)*(s + 3))"))
        rows = [line.split() for line in out.getvalue().splitlines()[1:]]
        self.assertEqual(sorted(float(r[1]) for r in rows), sorted(zeta_u))
        self.assertIn(-1.0, [float(r[1]) for r in rows])
        self.assertLessEqual(rel(dmbd.dcgain(SYS4), D4 - C4 @ np.linalg.solve(A4, B4)), 1e-14)


class Interconnection(unittest.TestCase):
    def test_python_control_conventions(self):
        a, b, c = dmbd.tf("1/(s+1)"), dmbd.tf("2/(s+3)"), dmbd.tf("(s+1)/(s+5)")
        s3 = dmbd.series(a, b, c)
        for w in (0.3, 2.0):
            self.assertAlmostEqual(abs(s3(1j * w) - a(1j * w) * b(1j * w) * c(1j * w)), 0.0, delta=1e-15)
            self.assertAlmostEqual(abs(dmbd.parallel(a, b, c)(1j * w) - (a(1j * w) + b(1j * w) + c(1j * w))), 0.0,
                                   delta=1e-15)
        f = dmbd.feedback(sys1=a, sys2=b, sign=-1)
        self.assertAlmostEqual(abs(f(0.5j) - a(0.5j) / (1 + a(0.5j) * b(0.5j))), 0.0, delta=1e-15)
        self.assertIs(dmbd.series(a), a)
        # A number around a square MIMO model: that gain on every channel.
        sq = dmbd.ss(A4, B4, C4)
        cl = dmbd.feedback(sq, 2.0)
        ref = dmbd.feedback(sq, dmbd.ss(np.zeros((0, 0)), np.zeros((0, 2)), np.zeros((2, 0)), 2.0 * np.eye(2)))
        np.testing.assert_array_equal(cl.A, ref.A)


if __name__ == "__main__":
    unittest.main()
