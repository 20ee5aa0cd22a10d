"""How the Python tests compare dmbd with SciPy (and NumPy), and the worst errors seen.

The tolerance is RTOL = 1e-9, relative:
- poles: each pole p of dmbd against its nearest reference pole r (one to one):
  |p - r| <= RTOL |r|;
- Bode magnitude: the linear magnitudes 10^(dB/20): |m - m_ref| <= RTOL m_ref;
- Bode phase (degrees, after taking out one common multiple of 360 degrees: SciPy
  unwraps from the first frequency, dmbd from DC): |ph - ph_ref| <= RTOL max(|ph_ref|, 1);
- step responses: max_k |y_k - y_ref_k| <= RTOL max_k |y_ref_k|.
Each assertion records its error; the worst of each kind is printed when a test module
ends (worst_errors()).
"""
import sys

import numpy as np

RTOL = 1e-9

_worst = {"poles": 0.0, "bode magnitude": 0.0, "bode phase": 0.0, "step": 0.0}


def _record(kind, err):
    _worst[kind] = max(_worst[kind], float(err))


def pole_error(p, ref):
    """Largest |p - r| / |r| over the reference poles, each matched to its nearest
    remaining pole of p."""
    p = list(np.asarray(p, dtype=complex))
    ref = np.asarray(ref, dtype=complex)
    if len(p) != len(ref):
        raise AssertionError(f"{len(p)} poles, the reference has {len(ref)}: {p} vs {ref}")
    worst = 0.0
    for r in sorted(ref, key=lambda z: -abs(z)):
        k = int(np.argmin([abs(x - r) for x in p]))
        worst = max(worst, abs(p.pop(k) - r) / abs(r))
    return worst


def assert_poles(tc, p, ref, what):
    err = pole_error(p, ref)
    _record("poles", err)
    tc.assertLessEqual(err, RTOL, f"{what}: poles {p} vs {ref}: relative error {err:.3g}")


def assert_bode(tc, mag_db, phase_deg, mag_db_ref, phase_deg_ref, what):
    m, m_ref = 10.0 ** (np.asarray(mag_db) / 20.0), 10.0 ** (np.asarray(mag_db_ref) / 20.0)
    err_m = float(np.max(np.abs(m - m_ref) / m_ref))
    d = np.asarray(phase_deg) - np.asarray(phase_deg_ref)
    d -= 360.0 * np.round(d[0] / 360.0)
    err_p = float(np.max(np.abs(d) / np.maximum(np.abs(phase_deg_ref), 1.0)))
    _record("bode magnitude", err_m)
    _record("bode phase", err_p)
    tc.assertLessEqual(err_m, RTOL, f"{what}: Bode magnitude relative error {err_m:.3g}")
    tc.assertLessEqual(err_p, RTOL, f"{what}: Bode phase relative error {err_p:.3g}")


def assert_step(tc, y, y_ref, what):
    y, y_ref = np.asarray(y), np.asarray(y_ref)
    tc.assertEqual(y.shape, y_ref.shape, f"{what}: step response shapes")
    err = float(np.max(np.abs(y - y_ref)) / np.max(np.abs(y_ref)))
    _record("step", err)
    tc.assertLessEqual(err, RTOL, f"{what}: step response relative error {err:.3g}")


def worst_errors():
    """Prints the worst relative error of each kind (to stderr, for CTest's log)."""
    print("worst relative errors against the references: " +
          ", ".join(f"{k} {v:.2e}" for k, v in _worst.items()), file=sys.stderr)
