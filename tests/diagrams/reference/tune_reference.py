#!/usr/bin/env python3
"""Reference implementation of the paper's gain-selection procedure (Sec. III-C) on the
hand-derived closed loops of paper_loops.py; the gains shipped in examples/diagrams/
are its result.  The C++ tuner (`dmbd tune` / library) implements the same steps and
is compared against this script.

Controllers 1 and 2 (position PD, no inner force loop), P_q in N/rad, D_q in N s/rad:
  1. D_max: the largest D_q for which the loop with P_q = 0 is stable, its root at the
     origin (the load position integrator, exact for P_q = 0) set aside; bisection to
     1e-9 relative between powers of 2 (equivalently the gain margin of the derivative
     loop D s/(tau_q s + 1) G_q(s) e^{-Ts}).
  2. D_q = RHO * D_max, RHO = 1/2: "raise D_q until stability is about to be lost",
     backed off to a 6 dB gain margin.
  3. P_q: the highest P_q whose step response q_d -> q does not overshoot: scan P_q
     upward from 1 N/rad by factors of 1.25 until the overshoot first exceeds EPS = 0.1 %
     (or the loop is unstable), then bisect between the last good and the first bad
     value to 1e-6 relative.
  The closed-loop natural frequency omega_n is sqrt(|p1 p2|) of the two closed-loop
  poles of smallest modulus (the dominant pair; the loop is critically damped there).

Controller 3 (position PD around the DOB force loop): design model = ideal DOB
(the force loop sees the nominal plant P^inf), outer loop on the paper's
P_{F->q} = N_l/(M_l s^2 + B_l s):
  char(s) = (M_l s^2 + B_l s)(M_nom s^2 + (B_nom + g D_tau) s + K_nom + g P_tau)
            + N_l (P_q + D_q s)(K_nom + g P_tau + g D_tau s),      g = k_tau N_m K_r
  set equal to M_l M_nom (s + omega_1)^2 (s + omega_F)^2: the product of two critically
  damped second-order loops, the position loop at controller 1's omega_n and the force
  loop at omega_F = 2 pi f_F (f_F of force_dob.yaml, 30 Hz); 4 equations in
  (P_tau, D_tau, P_q, D_q), solved exactly (s^3 gives D_tau; the rest reduces to one
  equation in K_nom + g P_tau, solved by bracketing on a grid and bisection).
  Then checked on the full model (actual plant, DOB with Q filters, delays, filters).

Force loop alone (force_dob.yaml): nominal loop Pbar C_tau critically damped at f_F:
  P_tau = (M_nom w_F^2 - K_nom)/g, D_tau = (2 M_nom w_F - B_nom)/g (expressions in the YAML).

Usage: tune_reference.py [--check] [--write] [--diagrams DIR]
  prints JSON; --check exits 1 if the shipped gains differ from the procedure's by more
  than 1e-4 relative; --write rewrites the gain lines of the YAML files.
"""
import argparse
import json
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paper_loops as pl  # noqa: E402

mp = pl.mp
RHO = mp.mpf("0.5")
EPS = mp.mpf("0.1")          # percent
P_START = mp.mpf(1)
P_FACTOR = mp.mpf("1.25")


# ------------------------------------------------------------------ responses
def minimal(num, den):
    num, den = pl.trim(num), pl.trim(den)
    lead = den[0]
    n, d, poles, _ = pl.cancel([x / lead for x in num], [x / lead for x in den])
    return n, d, poles


def max_real(den):
    d = pl.trim(den)
    while len(d) > 1 and d[-1] == 0:
        d = d[:-1]
    return max(z.real for z in pl.proots(d))


def step_overshoot(num, den):
    """Percent overshoot of the unit step response (None if unstable): exact response
    y(t) = G(0) + sum_k r_k e^{p_k t}, r_k = N(p_k)/(p_k D'(p_k)), on the minimal TF;
    maximum over a quadratic grid to 12 slowest time constants, refined by golden search."""
    n, d, poles = minimal(num, den)
    if max(z.real for z in poles) >= 0:
        return None
    dd = [d[k] * (len(d) - 1 - k) for k in range(len(d) - 1)]
    g = pl.dc_gain(n, d)
    res = [pl.peval(n, p) / (p * pl.peval(dd, p)) for p in poles]

    def y(t):
        return (g + sum(r * mp.exp(p * t) for r, p in zip(res, poles))).real

    tend = min(12 / min(-z.real for z in poles), mp.mpf(60))
    N = 800
    ts = [tend * (mp.mpf(k) / N) ** 2 for k in range(1, N + 1)]
    ys = [y(t) for t in ts]
    k = max(range(N), key=lambda i: ys[i])
    lo, hi = ts[max(k - 1, 0)], ts[min(k + 1, N - 1)]
    phi = (mp.sqrt(5) - 1) / 2
    for _ in range(80):
        m1, m2 = hi - phi * (hi - lo), lo + phi * (hi - lo)
        if y(m1) > y(m2):
            hi = m2
        else:
            lo = m1
    peak = max(ys[k], y((lo + hi) / 2))
    return (peak - g) / abs(g) * 100


def omega_n(num, den):
    _, _, poles = minimal(num, den)
    p = sorted(poles, key=abs)
    return mp.sqrt(abs(p[0]) * abs(p[1])), p[:2]


def bandwidth_hz(num, den):
    n, d, _ = minimal(num, den)
    g0 = abs(pl.dc_gain(n, d))
    target = g0 * mp.power(10, mp.mpf(-3) / 20)
    mag = lambda f: abs(pl.peval(n, mp.mpc(0, 2 * mp.pi * f)) / pl.peval(d, mp.mpc(0, 2 * mp.pi * f)))
    f0 = mp.mpf("0.001")
    while mag(f0 * mp.mpf("1.02")) >= target:
        f0 *= mp.mpf("1.02")
        if f0 > 1e5:
            return None
    lo, hi = f0, f0 * mp.mpf("1.02")
    for _ in range(80):
        m = (lo + hi) / 2
        if mag(m) >= target:
            lo = m
        else:
            hi = m
    return lo


# ------------------------------------------------------------------ controllers 1 and 2
def tune_pd(loop, ctrl, plant, pade):
    f = lambda P, D: loop(dict(ctrl, P_q=P, D_q=D), plant, pade)
    stable = lambda P, D: max_real(f(P, D)["den"]) < 0
    hi = mp.mpf(1)
    while stable(0, hi):
        hi *= 2
    lo = hi / 2
    if not stable(0, lo):
        raise RuntimeError("no stabilising D_q found")
    while hi / lo > 1 + mp.mpf("1e-9"):
        m = mp.sqrt(lo * hi)
        if stable(0, m):
            lo = m
        else:
            hi = m
    Dmax = lo
    D = RHO * Dmax

    def ok(P):
        r = f(P, D)
        o = step_overshoot(r["num"], r["den"])
        return o is not None and o <= EPS

    P = P_START
    if not ok(P):
        raise RuntimeError("overshoot already at P_q = P_START")
    while ok(P * P_FACTOR):
        P *= P_FACTOR
    lo, hi = P, P * P_FACTOR
    while hi / lo > 1 + mp.mpf("1e-6"):
        m = mp.sqrt(lo * hi)
        if ok(m):
            lo = m
        else:
            hi = m
    r = f(lo, D)
    w, dom = omega_n(r["num"], r["den"])
    return {"D_max": float(Dmax), "D_q": float(D), "P_q": float(lo),
            "overshoot_pct": float(step_overshoot(r["num"], r["den"])),
            "omega_n": float(w), "f_n_hz": float(w / (2 * mp.pi)),
            "dominant_poles": [[float(z.real), float(z.imag)] for z in dom],
            "max_real_pole": float(max_real(r["den"])),
            "bandwidth_hz": float(bandwidth_hz(r["num"], r["den"]))}


# ------------------------------------------------------------------ controller 3
def design_c3(ctrl, dob, plant_p, w1, wF):
    M, B, K, g = dob["M_nom"], dob["B_nom"], dob["K_nom"], dob["g_nom"]
    Ml, Bl, Nl = plant_p["M_l"], plant_p["B_l"], plant_p["N_l"]
    t = pl.pmul(pl.P(1, w1), pl.P(1, w1), pl.P(1, wF), pl.P(1, wF))
    t3, t2, t1, t0 = t[1:]
    b = (t3 * Ml * M - Bl * M) / Ml              # B_nom + g D_tau
    D_tau = (b - B) / g
    e = g * D_tau

    def gains(a):                                  # a = K_nom + g P_tau
        D_q = (t2 * Ml * M - Ml * a - Bl * b) / (Nl * e)
        P_q = t0 * Ml * M / (Nl * a)
        return P_q, D_q

    def resid(a):
        P_q, D_q = gains(a)
        return Bl * a + Nl * a * D_q + Nl * e * P_q - t1 * Ml * M

    amax = (t2 * Ml * M - Bl * b) / Ml             # D_q > 0 needs a < amax
    grid = [amax * mp.mpf(k) / 4000 for k in range(1, 4000)]
    sols = []
    for x0, x1 in zip(grid, grid[1:]):
        if resid(x0) * resid(x1) < 0:
            lo, hi = x0, x1
            for _ in range(200):
                m = (lo + hi) / 2
                if resid(lo) * resid(m) <= 0:
                    hi = m
                else:
                    lo = m
            a = (lo + hi) / 2
            P_q, D_q = gains(a)
            if P_q > 0 and D_q > 0:
                sols.append({"P_tau": (a - K) / g, "D_tau": D_tau, "P_q": P_q, "D_q": D_q})
    if len(sols) != 1:
        raise RuntimeError(f"controller 3 design: {len(sols)} admissible solutions")
    return sols[0]


def tune_c3(entry, w1):
    ctrl, dob, plant_p = entry["ctrl"], entry["dob"], entry["plant"]
    wF = 2 * mp.pi * dob["f_F"]
    s = design_c3(ctrl, dob, plant_p, w1, wF)
    plant = pl.Plant(plant_p)
    r = pl.position_encoder_force_loop(dict(ctrl, P_q=s["P_q"], D_q=s["D_q"]),
                                       dict(dob, P_tau=s["P_tau"], D_tau=s["D_tau"]),
                                       plant, entry["pade"], entry["dob_pade"])
    w, dom = omega_n(r["num"], r["den"])
    return {"omega_target": float(w1), "omega_F": float(wF),
            "P_tau": float(s["P_tau"]), "D_tau": float(s["D_tau"]),
            "P_q": float(s["P_q"]), "D_q": float(s["D_q"]),
            "overshoot_pct": float(step_overshoot(r["num"], r["den"])),
            "omega_n": float(w), "f_n_hz": float(w / (2 * mp.pi)),
            "omega_n_over_controller_1": float(w / w1),
            "dominant_poles": [[float(z.real), float(z.imag)] for z in dom],
            "max_real_pole": float(max_real(r["den"])),
            "bandwidth_hz": float(bandwidth_hz(r["num"], r["den"]))}


# ------------------------------------------------------------------ force loop
def dob_figures(entry):
    c, plant_p, n = entry["ctrl"], entry["plant"], entry["pade"]
    out = {"f_F": float(c["f_F"]), "P_tau": float(c["P_tau"]), "D_tau": float(c["D_tau"])}
    for Ml in (mp.mpf(2953), mp.mpf("1e9")):
        d = pl.dob_loop(c, pl.Plant(dict(plant_p, M_l=Ml)), n)
        key = "M_l=%g" % float(Ml)
        out[key] = {"overshoot_pct": float(step_overshoot(d["F"], d["chi"])),
                    "bandwidth_hz": float(bandwidth_hz(d["F"], d["chi"])),
                    "max_real_pole": float(max(z.real for z in minimal(d["F"], d["chi"])[2])),
                    "margins": margins(c, pl.Plant(dict(plant_p, M_l=Ml)), n)}
    return out


def margins(c, plant, n):
    """Loop broken at the plant input (i): L = P Dl (C + QP)/(1 - Q_A).  Gain and phase
    margins from a dense log scan (0.01 Hz .. 10 kHz) refined by bisection."""
    wc = 2 * mp.pi * c["fc_Q"]
    _, B2 = pl.butter(2, wc)
    nQP = pl.pscale(pl.P(c["M_nom"], c["B_nom"], c["K_nom"]), wc ** 2 / c["g_nom"])
    nC, dC = pl.pd(c["P_tau"], c["D_tau"], c["tau_tau"])
    nD, dD = pl.pade(c["T_F"], n)
    num = pl.pmul(plant.num_F_i, nD, pl.padd(pl.pmul(nQP, dC), pl.pmul(nC, B2)), B2)
    den = pl.pmul(plant.den, dD, dC, B2, pl.padd(B2, pl.P(-wc ** 2)))
    L = lambda f: pl.peval(num, mp.mpc(0, 2 * mp.pi * f)) / pl.peval(den, mp.mpc(0, 2 * mp.pi * f))
    fs = [mp.mpf(10) ** (-2 + mp.mpf(k) / 200) for k in range(1201)]
    vals = [L(f) for f in fs]
    pm, gm = None, None

    def refine(fun, a, b):
        for _ in range(100):
            m = (a + b) / 2
            if fun(a) * fun(m) <= 0:
                b = m
            else:
                a = m
        return (a + b) / 2

    for k in range(len(fs) - 1):
        a, b = vals[k], vals[k + 1]
        if (abs(a) - 1) * (abs(b) - 1) < 0:
            f = refine(lambda x: abs(L(x)) - 1, fs[k], fs[k + 1])
            m = float(180 + mp.degrees(mp.arg(L(f))))
            m = (m + 180) % 360 - 180
            if pm is None or abs(m) < abs(pm[0]):
                pm = (m, float(f))
        if a.imag * b.imag < 0 and (a.real + b.real) < 0:
            f = refine(lambda x: L(x).imag, fs[k], fs[k + 1])
            gdb = float(-20 * mp.log10(abs(L(f))))
            if gm is None or abs(gdb) < abs(gm[0]):
                gm = (gdb, float(f))
    return {"phase_margin_deg": pm[0] if pm else None, "gain_crossover_hz": pm[1] if pm else None,
            "gain_margin_db": gm[0] if gm else None, "phase_crossover_hz": gm[1] if gm else None}


# ------------------------------------------------------------------ main
GAIN_KEYS = {
    "position_encoder": ("controller_1", ["P_q", "D_q"]),
    "position_potentiometer": ("controller_2", ["P_q", "D_q"]),
    "position_encoder_force": ("controller_3", ["P_q", "D_q", "P_tau", "D_tau"]),
}


def run(diagrams):
    params = pl.load_params(diagrams, {})
    out = {"procedure": {"rho": float(RHO), "overshoot_threshold_pct": float(EPS),
                         "P_start": float(P_START), "P_factor": float(P_FACTOR)}}
    e = params["position_encoder"]
    out["controller_1"] = tune_pd(pl.position_encoder_loop, e["ctrl"], pl.Plant(e["plant"]), e["pade"])
    e = params["position_potentiometer"]
    out["controller_2"] = tune_pd(pl.position_potentiometer_loop, e["ctrl"], pl.Plant(e["plant"]), e["pade"])
    out["controller_3"] = tune_c3(params["position_encoder_force"], mp.mpf(out["controller_1"]["omega_n"]))
    out["force_dob"] = dob_figures(params["force_dob"])
    return params, out


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--diagrams", default=pl.DEFAULT_DIAGRAMS)
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--write", action="store_true")
    a = ap.parse_args()
    params, out = run(a.diagrams)
    json.dump(out, sys.stdout, indent=1)
    print()
    bad = []
    for fname, (key, names) in GAIN_KEYS.items():
        path = os.path.join(a.diagrams, fname + ".yaml")
        text = open(path).read()
        for nm in names:
            want = out[key][nm]
            have = float(params[fname]["ctrl"][nm])
            if abs(have - want) > 1e-4 * abs(want):
                bad.append(f"{fname}.yaml: {nm} = {have:.7g}, procedure gives {want:.7g}")
            if a.write:
                text, k = re.subn(rf"^(  {nm}:\s*)[-+0-9.eE]+", lambda m: m.group(1) + f"{want:.7g}", text,
                                  count=1, flags=re.M)
                if k != 1:
                    raise RuntimeError(f"{path}: no numeric line for {nm}")
        if a.write:
            open(path, "w").write(text)
    if a.check and bad:
        print("\n".join(bad), file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
