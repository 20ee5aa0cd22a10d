#!/usr/bin/env python3
"""Independent reference for `dmbd analyze --tf ... --json`.

Every figure dmbd reports is recomputed here with NumPy/SciPy by a different
method and compared to 1e-6 relative:
  poles, zeros      numpy.roots (companion matrix, no polishing)
  DC gain           limit by cancelling exact roots at s = 0 / z = 1
  Bode              scipy.signal.freqs / freqz; phase unwrapped with numpy.unwrap on a
                    dense grid from far below the slowest root (dmbd: per-factor phase)
  step              samples from e^{M dt} of the augmented companion matrix in 40-digit
                    mpmath and its powers (scipy.signal.lsim drifts over long horizons,
                    issue 28); rise, settling and peak located with scipy.optimize.brentq /
                    minimize_scalar on the exact response evaluated with scipy.linalg.expm
                    (mpmath where ||A|| t > 50)
  margins           dense grid scan + brentq on |L| - 1 and Im L (dmbd: polynomial roots)
  bandwidth         dense grid scan + brentq on |G| - |G(0)| 10^(-3/20)
  c2d               scipy.signal.cont2discrete (zoh, bilinear, backward_diff)
Usage: reference_check.py PATH/TO/dmbd
"""
import json
import math
import subprocess
import sys

import mpmath
import numpy as np
from scipy import linalg, optimize, signal

import mp_step  # beside this script

RTOL = 1e-6
failures = []


def close(name, got, ref, scale=None, rtol=RTOL):
    """|got - ref| <= rtol * max(|ref|, scale)."""
    if got is None or ref is None:
        if not (got is None and ref is None):
            failures.append(f"{name}: got {got}, reference {ref}")
        return
    s = max(abs(ref), scale if scale is not None else 0.0)
    if not abs(got - ref) <= rtol * s + 1e-300:
        failures.append(f"{name}: got {got!r}, reference {ref!r} (rel err {abs(got - ref) / max(s, 1e-300):.2e})")


def close_vec(name, got, ref, rtol=RTOL):
    got, ref = np.asarray(got, float), np.asarray(ref, float)
    if got.shape != ref.shape:
        failures.append(f"{name}: shape {got.shape} vs reference {ref.shape}")
        return
    scale = np.max(np.abs(ref)) if ref.size else 0.0
    for k, (g, r) in enumerate(zip(got, ref)):
        close(f"{name}[{k}]", g, r, scale=scale, rtol=rtol)


def match_roots(name, got, ref, rtol=RTOL):
    got = [complex(a, b) for a, b in got]
    ref = list(ref)
    if len(got) != len(ref):
        failures.append(f"{name}: {len(got)} roots, reference {len(ref)}: {got} vs {ref}")
        return
    scale = max([abs(r) for r in ref] + [1e-300])
    for r in ref:
        k = int(np.argmin([abs(g - r) for g in got]))
        err = abs(got[k] - r)
        # Relative to the root itself, or to the largest root for roots near zero.
        if not err <= rtol * max(abs(r), 1e-3 * scale):
            failures.append(f"{name}: root {r} matched {got[k]} (err {err:.2e})")
        got.pop(k)


def strip_zero_roots(p, x0):
    """Remove every exact-ish root at x0 (0 or 1) of a descending coefficient list."""
    p = np.trim_zeros(np.asarray(p, float), "f")
    m = 0
    while len(p) > 1:
        scale = np.sum(np.abs(p) * np.abs(x0) ** np.arange(len(p) - 1, -1, -1))
        if abs(np.polyval(p, x0)) > 1e-12 * scale:
            break
        p, _ = np.polydiv(p, [1.0, -x0])
        m += 1
    return p, m


def dc_gain(num, den, discrete):
    x0 = 1.0 if discrete else 0.0
    n, mn = strip_zero_roots(num, x0)
    d, md = strip_zero_roots(den, x0)
    if not np.any(n):
        return 0.0
    if md > mn:
        return None
    if mn > md:
        return 0.0
    return float(np.polyval(n, x0) / np.polyval(d, x0))


def response(num, den, w, ts):
    if ts:
        # freqz takes coefficients of z^-1: pad the numerator to the denominator's length.
        num = np.concatenate([np.zeros(max(0, len(den) - len(num))), num])
        return signal.freqz(num, den, worN=w * ts)[1]
    return signal.freqs(num, den, worN=w)[1]


def low_frequency_phase(num, den, ts):
    x0 = 1.0 if ts else 0.0
    n, mn = strip_zero_roots(num, x0)
    d, md = strip_zero_roots(den, x0)
    k0 = np.polyval(n, x0) / np.polyval(d, x0)
    return (mn - md) * 90.0 + (-180.0 if k0 < 0 else 0.0)


def dense_grid(num, den, ts, w_hi):
    roots = [abs(r) for r in np.concatenate([np.roots(num), np.roots(den)]) if abs(r) > 0]
    if ts:
        roots = [abs(np.log(complex(r))) / ts for r in roots if abs(r) > 0]
        roots = [r for r in roots if r > 0]
    lo = (min(roots) if roots else 1.0) * 1e-5
    hi = max([w_hi] + [r * 1e3 for r in roots])
    if ts:
        hi = min(hi, math.pi / ts * (1 - 1e-9))
    return np.logspace(np.log10(lo), np.log10(hi), 200000)


def phase_reference(num, den, ts, w_query):
    grid = dense_grid(num, den, ts, max(w_query))
    grid = np.unique(np.concatenate([grid, w_query]))
    h = response(num, den, grid, ts)
    ph = np.degrees(np.unwrap(np.angle(h)))
    start = low_frequency_phase(num, den, ts)
    ph += 360.0 * round((start - ph[0]) / 360.0)
    return np.interp(w_query, grid, ph)


def margins_reference(num, den, ts):
    w = dense_grid(num, den, ts, 1.0)
    h = response(num, den, w, ts)
    f_mag = lambda x: abs(response(num, den, np.array([x]), ts)[0]) - 1.0
    f_im = lambda x: response(num, den, np.array([x]), ts)[0].imag
    gcs, pcs = [], []
    m = np.abs(h) - 1.0
    for k in np.nonzero(np.sign(m[:-1]) != np.sign(m[1:]))[0]:
        if max(abs(m[k]), abs(m[k + 1])) < 1e-12:
            continue  # |L| = 1 to rounding (e.g. a unit-DC-gain filter at w -> 0): no crossing
        if np.sign(f_mag(w[k])) == np.sign(f_mag(w[k + 1])):
            continue
        wc = optimize.brentq(f_mag, w[k], w[k + 1], xtol=1e-15, rtol=1e-15)
        hc = response(num, den, np.array([wc]), ts)[0]
        ph = phase_reference(num, den, ts, np.array([wc]))[0]
        pm = math.remainder(180.0 + ph, 360.0)
        gcs.append((wc, pm if pm > -180 else pm + 360))
    im = h.imag
    for k in np.nonzero(np.sign(im[:-1]) != np.sign(im[1:]))[0]:
        if np.sign(f_im(w[k])) == np.sign(f_im(w[k + 1])):
            continue
        wp = optimize.brentq(f_im, w[k], w[k + 1], xtol=1e-15, rtol=1e-15)
        hp = response(num, den, np.array([wp]), ts)[0]
        if hp.real < 0:
            pcs.append((wp, -20 * math.log10(abs(hp))))
    dc = dc_gain(num, den, bool(ts))
    if dc is not None and dc < 0:
        pcs.append((0.0, -20 * math.log10(abs(dc))))
    if ts:
        hn = np.polyval(num, -1.0) / np.polyval(den, -1.0)
        if hn < 0:
            pcs.append((math.pi / ts, -20 * math.log10(abs(hn))))
    gc = min(gcs, key=lambda c: abs(c[1])) if gcs else None
    pc = min(pcs, key=lambda c: abs(c[1])) if pcs else None
    return gc, pc


def bandwidth_reference(num, den, ts):
    dc = dc_gain(num, den, bool(ts))
    if dc is None or dc == 0:
        return None
    level = abs(dc) * 10 ** (-3 / 20)
    w = dense_grid(num, den, ts, 1.0)
    m = np.abs(response(num, den, w, ts)) - level
    idx = np.nonzero((m[:-1] >= 0) & (m[1:] < 0))[0]
    if not len(idx):
        return None
    f = lambda x: abs(response(num, den, np.array([x]), ts)[0]) - level
    return optimize.brentq(f, w[idx[0]], w[idx[0] + 1], xtol=1e-15, rtol=1e-15)


def step_samples_mp(num, den, t):
    """Step response at equally spaced t from mpmath at 40 digits (mp_step.py)."""
    return np.array(mp_step.step_samples(num, den, t, 40))


def step_reference(num, den, t):
    a, b, c, d = signal.tf2ss(num, den)
    y = step_samples_mp(num, den, t)
    n = a.shape[0]
    norm_a = np.max(np.sum(np.abs(a), axis=0)) if n else 0.0

    def y_at(tt):
        if tt <= 0:
            return float(d[0, 0])
        if tt * norm_a > 50:  # long or stiff: SciPy's expm loses digits there (issue 28)
            return float(step_samples_mp(num, den, [0.0, tt])[1])
        big = np.zeros((n + 1, n + 1))
        big[:n, :n] = a * tt
        big[:n, n:] = b * tt
        e = linalg.expm(big)
        return float((c @ e[:n, n:])[0, 0] + d[0, 0])

    stable = np.all(np.real(np.linalg.eigvals(a)) < 0) if n else True
    info = {"rise_time_s": None, "settling_time_s": None, "overshoot_pct": None, "final_value": None}
    if not stable:
        return y, info
    final = dc_gain(num, den, False)
    info["final_value"] = final
    yn = y / final

    def first_cross(level):
        k = int(np.argmax(yn >= level))
        if yn[k] < level:
            return None
        if k == 0:
            return t[0]
        return optimize.brentq(lambda tt: y_at(tt) / final - level, t[k - 1], t[k], xtol=1e-15, rtol=1e-15)

    t10, t90 = first_cross(0.1), first_cross(0.9)
    if t10 is not None and t90 is not None:
        info["rise_time_s"] = t90 - t10
    outside = np.nonzero(np.abs(yn - 1) > 0.02)[0]
    if not len(outside):
        info["settling_time_s"] = t[0]
    elif outside[-1] + 1 < len(t):
        k = outside[-1]
        side = 0.02 if yn[k] > 1 else -0.02
        info["settling_time_s"] = optimize.brentq(lambda tt: y_at(tt) / final - 1 - side, t[k], t[k + 1],
                                                  xtol=1e-15, rtol=1e-15)
    kp = int(np.argmax(yn))
    yp = y[kp]
    if 0 < kp < len(t) - 1:
        res = optimize.minimize_scalar(lambda tt: -y_at(tt) / final, bounds=(t[kp - 1], t[kp + 1]),
                                       method="bounded", options={"xatol": 1e-14 * t[kp]})
        yp = max(yp / final, -res.fun) * final
    info["overshoot_pct"] = max(0.0, (yp - final) / final * 100)
    return y, info


def zoh_reference_mp(num, den, ts):
    """Exact ZOH equivalent in 50-digit arithmetic from partial fractions:
    G(z) = G(0) + (z - 1) sum_i r_i / (z - e^{p_i T}),  r_i = N(p_i) / (p_i D'(p_i)).
    (scipy's cont2discrete converts back with det(zI-A+BC) - det(zI-A), which loses
    the small numerator of a slow high-order system: it is not a 1e-6 reference there.)
    Needs distinct non-zero poles, true for the cases below."""
    mpmath.mp.dps = 50
    n = [mpmath.mpf(float(c)) for c in num]
    d = [mpmath.mpf(float(c)) for c in den]
    poles = mpmath.polyroots(d, maxsteps=200, extraprec=200)
    dd = [c * (len(d) - 1 - k) for k, c in enumerate(d[:-1])]
    g0 = mpmath.polyval(n, 0) / mpmath.polyval(d, 0)
    q = [mpmath.exp(p * ts) for p in poles]
    res = [mpmath.polyval(n, p) / (p * mpmath.polyval(dd, p)) for p in poles]

    def poly_from_roots(roots):
        c = [mpmath.mpc(1)]
        for r in roots:
            c = [a - r * b for a, b in zip(c + [0], [0] + c)]
        return c

    den_z = poly_from_roots(q)
    num_z = [g0 * c for c in den_z]
    for i, r in enumerate(res):
        term = poly_from_roots([1] + q[:i] + q[i + 1:])
        num_z = [a + r * b for a, b in zip(num_z, term)]
    num_z = [float(mpmath.re(c)) for c in num_z]
    den_z = [float(mpmath.re(c)) for c in den_z]
    num_z = np.array(num_z)
    while len(num_z) > 1 and abs(num_z[0]) < 1e-30 * np.max(np.abs(num_z)):
        num_z = num_z[1:]  # exactly zero in exact arithmetic (strictly proper G)
    return num_z, np.array(den_z)


def c2d_reference(num, den, ts, method, prewarp_hz):
    if method == "zoh":
        return zoh_reference_mp(num, den, ts)
    if method == "tustin":
        t_eff = ts
        if prewarp_hz:
            w = 2 * math.pi * prewarp_hz
            t_eff = 2 * math.tan(w * ts / 2) / w
        nd, dd, _ = signal.cont2discrete((num, den), t_eff, method="bilinear")
    else:
        nd, dd, _ = signal.cont2discrete((num, den), ts, method={"zoh": "zoh", "backward-euler": "backward_diff"}[method])
    nd = np.atleast_1d(np.squeeze(nd))
    dd = np.atleast_1d(np.squeeze(dd))
    nd, dd = nd / dd[0], dd / dd[0]
    nd = np.trim_zeros(nd, "f") if np.any(nd) else nd
    return nd, dd


CASES = [
    # (label, dmbd arguments)
    ("lag", ["--tf", "1/(s+1)", "--freq-range", "0.001:100:25", "--step", "10:801", "--c2d", "zoh", "--ts", "0.01"]),
    ("lead", ["--tf", "10*(s+1)/(s+10)", "--freq", "0.01,0.1,0.5,1,3,10,100", "--step", "2:501",
              "--c2d", "tustin", "--ts", "0.005"]),
    ("resonance", ["--tf", "w^2/(s^2 + 2*0.02*w*s + w^2)", "--param", "w=2*pi*50", "--freq-range", "1:1000:61",
                   "--step", "0.5:4001", "--c2d", "tustin", "--ts", "0.001", "--prewarp", "50"]),
    ("non-minimum-phase", ["--tf", "(1 - s/2)/((s+1)*(s/5+1))", "--freq-range", "0.01:100:31", "--step", "8:1601",
                           "--c2d", "backward-euler", "--ts", "0.01"]),
    ("integrator loop", ["--tf", "10/(s*(s+1)*(s/5+1))", "--freq-range", "0.01:10:31"]),
    ("double integrator + lead", ["--tf", "20*(s+1)/(s^2*(s/20+1))", "--freq-range", "0.01:100:31"]),
    ("paper Q filter 60 Hz (eq. frc_ctrl)", ["--tf", "1/((s/wc)^2 + sqrt(2)*s/wc + 1)", "--param", "fc=60",
                                             "--param", "wc=2*pi*fc", "--freq", "1,10,60,100,499",
                                             "--step", "0.05:1001", "--c2d", "tustin", "--ts", "0.001"]),
    ("order 8 real poles", ["--tf", "40320/((s+1)*(s+2)*(s+3)*(s+4)*(s+5)*(s+6)*(s+7)*(s+8))",
                            "--freq-range", "0.01:100:41", "--step", "15:3001", "--c2d", "zoh", "--ts", "0.02"]),
    ("order 8 mixed", ["--tf", "(s^2 + 0.4*s + 4)*(s - 3)/((s^2 + 0.2*s + 1)*(s^2 + 1.2*s + 9)*(s^2 + 3*s + 25)*(s+0.5)*(s+6))",
                       "--freq-range", "0.01:100:41", "--step", "60:6001", "--c2d", "zoh", "--ts", "0.05"]),
    ("stiff actuator-like", ["--tf", "k/((m*s^2 + b*s + kr)*(s/2000 + 1))", "--param", "m=701.3", "--param", "b=1.6e4",
                             "--param", "kr=9.5e6", "--param", "k=9.5e6", "--freq-range", "0.1:1000:41",
                             "--step", "0.5:5001", "--c2d", "zoh", "--ts", "0.0005"]),
    ("PD x plant loop", ["--tf", "(P + D*s)*1/(s*(s/30 + 1)*(s/300 + 1))", "--param", "P=40", "--param", "D=2",
                         "--freq-range", "0.1:1000:41"]),
    ("negative DC gain", ["--tf", "-2/(s+1)", "--freq", "0.1,1,10", "--step", "6:601"]),
    ("discrete in z", ["--tf", "0.1*(z + 0.5)/((z - 0.9)*(z - 0.5))", "--ts", "0.001", "--freq-range", "0.1:499:31"]),
    ("discrete loop", ["--tf", "0.05*(z+1)/((z-1)*(z-0.6))", "--ts", "0.01", "--freq-range", "0.01:49:31"]),
    # Issue 28, rows 2, 2b and 3 (frequency part).
    ("issue 28 row 2: lag over 1e15 s", ["--tf", "1/(s+1)", "--step", "1e15:3"]),
    ("issue 28 row 2b: stiff", ["--tf", "1e6/((s+1e-6)*(s+1e6))", "--step", "1e7:11"]),
    ("issue 28 row 3: 20-fold pole", ["--tf", "1/(s+1)^20", "--freq", "0.001,0.0252077,0.0298356,0.1,1"]),
    ("lag with delay (Pade 3 expanded)", ["--tf", "(1 - s*T/2 + (s*T)^2/10 - (s*T)^3/120)/((1 + s*T/2 + (s*T)^2/10 + (s*T)^3/120)*(s+1))",
                                          "--param", "T=0.2", "--freq-range", "0.01:100:31", "--step", "10:2001"]),
]


# The double coefficients of (s + 1)^20 fix its roots only to about eps^(1/20) = 0.17
# relative: two root finders scatter them differently, and neither is the reference for
# the responses, which are compared from the coefficients.
ROOTS_NOT_COMPARED = {"issue 28 row 3: 20-fold pole"}


def check(label, args, exe):
    out = subprocess.run([exe, "analyze", "--json"] + args, capture_output=True, text=True)
    if out.returncode != 0:
        failures.append(f"{label}: dmbd exited {out.returncode}: {out.stderr.strip()}")
        return
    r = json.loads(out.stdout)
    num, den, ts = np.array(r["num"], float), np.array(r["den"], float), r["ts"]
    pre = f"{label}: "
    # The coefficients themselves come from dmbd's parser; check them against a
    # second evaluation of the same expression only through the responses below,
    # which use numpy on these coefficients.
    if label not in ROOTS_NOT_COMPARED:
        match_roots(pre + "poles", r["poles"], np.roots(den))
        match_roots(pre + "zeros", r["zeros"], np.roots(num) if len(num) > 1 else [])
    close(pre + "dc_gain", r["dc_gain"], dc_gain(num, den, bool(ts)))
    poles = np.roots(den)
    stable = bool(np.all(np.abs(poles) < 1) if ts else np.all(np.real(poles) < 0))
    if r["stable"] != stable:
        failures.append(f"{pre}stable: got {r['stable']}, reference {stable}")
    if "bode" in r:
        w = 2 * np.pi * np.array(r["bode"]["freq_hz"])
        h = response(num, den, w, ts)
        close_vec(pre + "mag_db", r["bode"]["mag_db"], 20 * np.log10(np.abs(h)), rtol=RTOL)
        ph_ref = phase_reference(num, den, ts, w)
        for k, (g, p) in enumerate(zip(r["bode"]["phase_deg"], ph_ref)):
            close(f"{pre}phase_deg[{k}] at {w[k] / 2 / np.pi:.4g} Hz", g, p, scale=1.0)
    gc, pc = margins_reference(num, den, ts)
    close(pre + "gain_crossover_hz", r["gain_crossover_hz"], gc[0] / 2 / np.pi if gc else None)
    close(pre + "phase_margin_deg", r["phase_margin_deg"], gc[1] if gc else None, scale=1.0)
    close(pre + "phase_crossover_hz", r["phase_crossover_hz"], pc[0] / 2 / np.pi if pc else None, scale=1e-9)
    close(pre + "gain_margin_db", r["gain_margin_db"], pc[1] if pc else None, scale=1.0)
    bw = bandwidth_reference(num, den, ts)
    close(pre + "bandwidth_hz", r["bandwidth_hz"], bw / 2 / np.pi if bw else None)
    if "step" in r:
        t = np.array(r["step"]["t"])
        y_ref, info = step_reference(num, den, t)
        close_vec(pre + "step.y", r["step"]["y"], y_ref)
        for key in ("rise_time_s", "settling_time_s", "overshoot_pct", "final_value"):
            close(pre + "step." + key, r["step"][key], info[key], scale=1e-9 if key != "overshoot_pct" else 1e-6)
    if "discrete" in r:
        d = r["discrete"]
        nd, dd = c2d_reference(num, den, d["ts"], d["method"], d.get("prewarp_hz", 0.0))
        close_vec(pre + "c2d num", d["num"], nd)
        close_vec(pre + "c2d den", d["den"], dd)
        # The exact images of the continuous poles (better conditioned than the roots
        # of the discrete denominator, whose poles cluster near z = 1).
        p = np.roots(den)
        t = d["ts"]
        if d["method"] == "zoh":
            pd = np.exp(p * t)
        elif d["method"] == "tustin":
            a = t / 2
            if d.get("prewarp_hz"):
                w = 2 * math.pi * d["prewarp_hz"]
                a = math.tan(w * t / 2) / w
            pd = (1 + a * p) / (1 - a * p)
        else:
            pd = 1 / (1 - t * p)
        match_roots(pre + "c2d poles", d["poles"], pd)


def main():
    exe = sys.argv[1]
    for label, args in CASES:
        before = len(failures)
        check(label, args, exe)
        print(f"{'ok  ' if len(failures) == before else 'FAIL'} {label}")
    for f in failures:
        print("  " + f)
    print(f"{len(CASES) - len({f.split(':')[0] for f in failures})} passed, "
          f"{len({f.split(':')[0] for f in failures})} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
