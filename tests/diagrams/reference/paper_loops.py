#!/usr/bin/env python3
"""Independent reference for the paper's actuator loops (examples/diagrams/*.yaml).

The closed-loop transfer functions of the knee RFSEA force loop with a disturbance
observer (force_dob.yaml) and of the three position controllers
(position_encoder.yaml, position_potentiometer.yaml, position_encoder_force.yaml)
are derived here BY HAND, as ratios of polynomials, from the plant equations of
motion and the block transfer functions, with 50-digit polynomial arithmetic
(mpmath).  Nothing here interconnects state-space blocks: the derivations are in
the docstrings of the loop functions and in docs/paper-actuators.md.

Every closed loop is kept at the order of the diagram's realisation (the sum of the
block orders), so that `den` is the characteristic polynomial det(sI - A) of the
interconnected state-space model `dmbd analyze` builds; `minimal` gives the same
transfer function with the common roots of num and den cancelled (the load position
integrator is unobservable from F in the force loop, see the docs).

Parameter values are read from the YAML files (numbers and expressions of other
parameters), so this script always checks what is shipped.  Delays are replaced by
the diagonal Pade approximant of the order in the diagram's `analysis.pade_order`
(default 3).

Usage:
  paper_loops.py [--diagrams DIR] [--param NAME=VALUE ...] [--sweep N] [--compact]
prints one JSON object:
  {loop: {num, den, order, poles, dc_gain, stable, max_real_pole, minimal: {...}}},
  "boundary_layer": {...}, "dob_sweep": [...], "normal_form": {...}, "plant": {...}
"""
import argparse
import json
import math
import os
import sys

import mpmath as mp

mp.mp.dps = 50
HERE = os.path.dirname(os.path.abspath(__file__))
DEFAULT_DIAGRAMS = os.path.normpath(os.path.join(HERE, "..", "..", "..", "examples", "diagrams"))


# --------------------------------------------------------------------------------------
# polynomials: lists of mpf, highest power first
# --------------------------------------------------------------------------------------
def P(*c):
    return [mp.mpf(x) for x in c]


def trim(a):
    i = 0
    while i < len(a) - 1 and a[i] == 0:
        i += 1
    return a[i:]


def padd(*ps):
    n = max(len(p) for p in ps)
    out = [mp.mpf(0)] * n
    for p in ps:
        off = n - len(p)
        for k, c in enumerate(p):
            out[off + k] += c
    return trim(out)


def pmul(*ps):
    out = [mp.mpf(1)]
    for p in ps:
        r = [mp.mpf(0)] * (len(out) + len(p) - 1)
        for i, a in enumerate(out):
            for j, b in enumerate(p):
                r[i + j] += a * b
        out = r
    return trim(out)


def pscale(p, c):
    return [c * x for x in p]


def pneg(p):
    return [-x for x in p]


def peval(p, s):
    v = mp.mpc(0)
    for c in p:
        v = v * s + c
    return v


def proots(p):
    p = trim(p)
    if len(p) < 2:
        return []
    # strip exact zero roots first (polyroots dislikes a zero constant term)
    zeros = 0
    while len(p) > 1 and p[-1] == 0:
        p = p[:-1]
        zeros += 1
    r = [mp.mpc(0)] * zeros
    if len(p) > 1:
        r += list(mp.polyroots(p, maxsteps=400, extraprec=400))
    return sorted(r, key=lambda z: (float(z.real), float(z.imag)))


def from_roots(roots, lead=1):
    out = [mp.mpc(lead)]
    for r in roots:
        out = [a - r * b for a, b in zip(out + [mp.mpc(0)], [mp.mpc(0)] + out)]
    return [mp.mpf(c.real) for c in out]


def pade(T, n):
    """Diagonal Pade approximant of exp(-T s): num(s)/den(s), order n."""
    if T == 0 or n == 0:
        return P(1), P(1)
    c = [mp.factorial(2 * n - k) * mp.factorial(n) / (mp.factorial(2 * n) * mp.factorial(k) * mp.factorial(n - k))
         for k in range(n + 1)]
    num = [c[k] * (-T) ** k for k in range(n, -1, -1)]
    den = [c[k] * T ** k for k in range(n, -1, -1)]
    return num, den


def butter(order, wc):
    """Butterworth low-pass, unit DC gain: wc^n / B_n(s)."""
    den = P(1)
    for k in range(1, order // 2 + 1):
        theta = mp.pi * (2 * k - 1) / (2 * order)
        den = pmul(den, P(1, 2 * mp.sin(theta) * wc, wc * wc))
    if order % 2:
        den = pmul(den, P(1, wc))
    return P(wc ** order), den


def pd(Pg, Dg, tau):
    """P + D s/(tau s + 1) = ((P tau + D) s + P)/(tau s + 1)."""
    return P(Pg * tau + Dg, Pg), P(tau, 1)


# --------------------------------------------------------------------------------------
# parameters from the YAML files
# --------------------------------------------------------------------------------------
def eval_expr(expr, env):
    if isinstance(expr, (int, float)):
        return mp.mpf(expr)
    e = str(expr).replace("^", "**")
    names = {"pi": mp.pi, "e": mp.e, "sqrt": mp.sqrt, "exp": mp.exp, "log": mp.log,
             "log10": mp.log10, "sin": mp.sin, "cos": mp.cos, "tan": mp.tan, "abs": abs,
             "pow": mp.power, "min": min, "max": max}
    names.update(env)
    return mp.mpf(eval(e, {"__builtins__": {}}, names))


def resolve(raw, overrides=None):
    """Evaluate a parameter map (values may reference each other in any order)."""
    raw = dict(raw)
    if overrides:
        raw.update(overrides)
    env, pending = {}, dict(raw)
    while pending:
        progress = False
        for k, v in list(pending.items()):
            try:
                env[k] = eval_expr(v, env)
            except NameError:
                continue
            del pending[k]
            progress = True
        if not progress:
            raise ValueError(f"cannot resolve parameters {sorted(pending)}")
    return env


def load_diagram(path, overrides=None, cli=None):
    """Resolve a diagram's parameters (its own, then the parent's overrides, then the
    command line) and, recursively, those of its subsystems.  Returns
    {"env": {...}, "pade": n, "subsystems": {block: {...}}}."""
    import yaml

    with open(path) as f:
        d = yaml.safe_load(f)
    raw = dict(d.get("parameters", {}) or {})
    raw.update(overrides or {})
    raw.update(cli or {})
    env = resolve(raw)
    subs = {}
    for name, b in (d.get("blocks") or {}).items():
        if b.get("type") == "subsystem":
            ov = {k: eval_expr(v, env) for k, v in (b.get("parameters") or {}).items()}
            subs[name] = load_diagram(os.path.join(os.path.dirname(path), b["file"]), ov, cli)
    return {"env": env, "pade": int((d.get("analysis") or {}).get("pade_order", 3)), "subsystems": subs}


def find_plant(tree):
    """The rfsea plant parameters inside a resolved diagram tree (depth-first)."""
    if "J_m" in tree["env"] and not tree["subsystems"]:
        return tree["env"]
    for sub in tree["subsystems"].values():
        r = find_plant(sub)
        if r is not None:
            return r
    return None


def load_params(diagrams_dir, cli):
    out = {}
    for n in ("force_dob", "position_encoder", "position_potentiometer", "position_encoder_force"):
        tree = load_diagram(os.path.join(diagrams_dir, n + ".yaml"), None, cli)
        entry = {"ctrl": tree["env"], "plant": find_plant(tree), "pade": tree["pade"]}
        if n == "position_encoder_force":
            dob = [s for s in tree["subsystems"].values() if s["subsystems"]][0]
            entry["dob"] = dob["env"]
            entry["dob_pade"] = dob["pade"]
        out[n] = entry
    return out


# --------------------------------------------------------------------------------------
# plant (derivation: docs/paper-actuators.md, section 1)
# --------------------------------------------------------------------------------------
class Plant:
    """Knee RFSEA, rad/m convention (N_m = 6632 rad of motor per m of travel).

    Coordinates: x_r elastomer compression (housing displacement = -x_r), x_l load
    (actuator output) position, screw travel relative to the housing y = x_l + x_r =
    theta_m/N_m.  With J' = J_m N_m^2, B' = B_m N_m^2 and the screw force F_s on the load:
        J' y'' + B' y' = k_tau N_m i - F_s
        M_l x_l'' + B_l x_l' = F_s + F_ext
        M_r x_r'' + B_r x_r' + K_r x_r = F_s,        F = K_r x_r.
    Eliminating F_s:  all outputs over the common denominator s*Delta(s),
        Delta = (M_l s + B_l)(M_r s^2 + B_r s + K_r) + (J' s + B')(M_r s^2 + B_r s + K_r + M_l s^2 + B_l s)
        x_l/i   = k N (M_r s^2 + B_r s + K_r) / (s Delta)
        x_r/i   = k N (M_l s + B_l) s / (s Delta)
        F/i     = k N K_r (M_l s + B_l) s / (s Delta)
        th/i    = k N^2 ((M_l + M_r) s^2 + (B_l + B_r) s + K_r) / (s Delta),  x_pot = th/N_m
        x_l/F_e = ((M_r + J') s^2 + (B_r + B') s + K_r) / (s Delta)
        x_r/F_e = -(J' s + B') s / (s Delta)
    """

    def __init__(self, p):
        self.p = p
        Jp = p["J_m"] * p["N_m"] ** 2
        Bp = p["B_m"] * p["N_m"] ** 2
        self.Jp, self.Bp = Jp, Bp
        self.kN = p["k_tau"] * p["N_m"]
        Ml, Bl, Mr, Br, Kr = p["M_l"], p["B_l"], p["M_r"], p["B_r"], p["K_r"]
        self.nX = P(Mr, Br, Kr)                       # elastomer impedance polynomial
        self.Delta = padd(pmul(P(Ml, Bl), self.nX), pmul(P(Jp, Bp), padd(self.nX, P(Ml, Bl, 0))))
        self.den = pmul(P(1, 0), self.Delta)         # s Delta, order 4
        kN = self.kN
        self.num_xl_i = pscale(self.nX, kN)
        self.num_xr_i = pscale(pmul(P(Ml, Bl), P(1, 0)), kN)
        self.num_F_i = pscale(self.num_xr_i, Kr)
        self.num_xpot_i = pscale(P(Ml + Mr, Bl + Br, Kr), kN)   # x_l + x_r = theta_m/N_m
        self.num_th_i = pscale(self.num_xpot_i, p["N_m"])
        self.num_xl_e = P(Mr + Jp, Br + Bp, Kr)
        self.num_xr_e = pneg(pmul(P(Jp, Bp), P(1, 0)))
        # nominal plant, M_l -> infinity: k N K_r / Delta_inf
        self.Delta_inf = P(Mr + Jp, Br + Bp, Kr)
        self.g_nom = kN * Kr


# --------------------------------------------------------------------------------------
# closed loops (derivations in the docstrings; orders = sum of the block orders)
# --------------------------------------------------------------------------------------
def dob_loop(c, pl, pade_order):
    """force_dob.yaml: F_d -> F (and F_d -> q, F_d -> i).  c: the diagram's parameters,
    pl: the plant (its own parameters; the DOB's nominal model uses only c).

    Blocks: C = C_tau = nC/dC (pd), feedforward k_ff, Q_A = wc^2/B2 (lowpass 2),
    QP = Q_B/Pbar = wc^2 (M_nom s^2 + B_nom s + K_nom)/(g_nom B2) (one tf), delay
    Dl = nD/dD on the measured F, plant F = P u, P = nF/(s Delta).  Equations:
        u = C (F_d - Dl F) + k_ff F_d - dhat,   dhat = QP Dl F - Q_A u
    => u (1 - Q_A) = (C + k_ff) F_d - (C + QP) Dl F
    => F/F_d = P (C + k_ff) / [(1 - Q_A) + P Dl (C + QP)].
    Multiplying through by s Delta B2 B2 dC dD:
        chi   = s Delta (B2 - wc^2) B2 dC dD + nF nD B2 (nQP dC + nC B2)        (order 12)
        F     : nF (nC + k_ff dC) B2^2 dD
        u     : s Delta (nC + k_ff dC) B2^2 dD
        q     : N_l k N nX (nC + k_ff dC) B2^2 dD
    """
    wc = 2 * mp.pi * c["fc_Q"]
    _, B2 = butter(2, wc)
    nQ = P(wc ** 2)
    nQP = pscale(P(c["M_nom"], c["B_nom"], c["K_nom"]), wc ** 2 / c["g_nom"])
    nC, dC = pd(c["P_tau"], c["D_tau"], c["tau_tau"])
    nD, dD = pade(c["T_F"], pade_order)
    kff = c["k_ff"]
    B2mQ = padd(B2, pneg(nQ))
    chi = padd(pmul(pl.den, B2mQ, B2, dC, dD), pmul(pl.num_F_i, nD, B2, padd(pmul(nQP, dC), pmul(nC, B2))))
    common = pmul(padd(nC, pscale(dC, kff)), B2, B2, dD)
    return {
        "chi": chi,
        "F": pmul(pl.num_F_i, common),
        "u": pmul(pl.den, common),
        "q": pscale(pmul(pl.num_xl_i, common), pl.p["N_l"]),
    }


def position_encoder_loop(c, pl, pade_order):
    """position_encoder.yaml (controller 1): q_d -> q.

    F_cmd = P_q (q_d - q_m) - D_q s/(tau_q s + 1) q_m,  i = k_ff F_cmd, k_ff = 1/(k_tau N_m),
    q_m = Dl q (encoders: N_l (theta_m/N_m - x_r) = N_l x_l = q exactly),
    q = H F_cmd with H = k_ff N_l k N nX/(s Delta).
    q/q_d = H P_q / (1 + H (P_q + Dd) Dl), Dd = D_q s/(tau_q s + 1):
        den = s Delta dDd dD + nH (P_q dDd + D_q s) nD         (order 4+1+3)
        num = nH P_q dDd dD,      nH = k_ff N_l k N nX
    """
    nD, dD = pade(c["T_enc"], pade_order)
    dDd = P(c["tau_q"], 1)
    nH = pscale(pl.num_xl_i, c["k_ff"] * pl.p["N_l"])
    fb = padd(pscale(dDd, c["P_q"]), P(c["D_q"], 0))
    den = padd(pmul(pl.den, dDd, dD), pmul(nH, fb, nD))
    num = pmul(nH, pscale(dDd, c["P_q"]), dD)
    return {"num": num, "den": den}


def position_potentiometer_loop(c, pl, pade_order):
    """position_potentiometer.yaml (controller 2): q_d -> q.

    As controller 1, the measurement being the potentiometer, which reads the screw
    travel relative to the housing, x_pot = x_l + x_r = theta_m/N_m (eq. collocated),
    q_m = N_l Dl Lp x_pot with Lp = wp^n/Bp (noise filter, Butterworth of order n_pot
    at fc_pot).  With nHm = k_ff N_l k N ((M_l + M_r) s^2 + (B_l + B_r) s + K_r):
        den = s Delta dDd Bp dD + nHm (P_q dDd + D_q s) wp^n nD  (order 4+1+n+3)
        num = nH P_q dDd Bp dD
    """
    nD, dD = pade(c["T_pot"], pade_order)
    nL, dL = butter(int(c["n_pot"]), 2 * mp.pi * c["fc_pot"])
    dDd = P(c["tau_q"], 1)
    nH = pscale(pl.num_xl_i, c["k_ff"] * pl.p["N_l"])
    nHm = pscale(pl.num_xpot_i, c["k_ff"] * pl.p["N_l"])
    fb = padd(pscale(dDd, c["P_q"]), P(c["D_q"], 0))
    den = padd(pmul(pl.den, dDd, dL, dD), pmul(nHm, fb, nL, nD))
    num = pmul(nH, pscale(dDd, c["P_q"]), dL, dD)
    return {"num": num, "den": den}


def position_encoder_force_loop(c, dob_c, pl, pade_order, dob_pade_order):
    """position_encoder_force.yaml (controller 3): q_d -> q.

    The position PD's force command F_d drives the DOB force loop; q = Hq F_d with
    Hq = q/F_d = nq/chi from dob_loop.  q_m = Dl q (encoders), so
        q/q_d = Hq P_q / (1 + Hq (P_q + Dd) Dl):
        den = chi dDd dD + nq (P_q dDd + D_q s) nD                 (order 12+1+3)
        num = nq P_q dDd dD
    """
    inner = dob_loop(dob_c, pl, dob_pade_order)
    nD, dD = pade(c["T_enc"], pade_order)
    dDd = P(c["tau_q"], 1)
    fb = padd(pscale(dDd, c["P_q"]), P(c["D_q"], 0))
    den = padd(pmul(inner["chi"], dDd, dD), pmul(inner["q"], fb, nD))
    num = pmul(inner["q"], pscale(dDd, c["P_q"]), dD)
    return {"num": num, "den": den}


# --------------------------------------------------------------------------------------
# reports
# --------------------------------------------------------------------------------------
def dc_gain(num, den):
    num, den = list(num), list(den)
    while len(num) > 1 and len(den) > 1 and abs(num[-1]) == 0 and abs(den[-1]) == 0:
        num, den = num[:-1], den[:-1]
    if den[-1] == 0:
        return None
    return num[-1] / den[-1]


def cancel(num, den, rtol=mp.mpf("1e-10")):
    """Cancel common roots (|z - p| <= rtol |p|, or both exactly 0); returns num, den, the
    remaining poles and the cancelled ones."""
    zs, ps = proots(num), proots(den)
    lead = trim(num)[0] / trim(den)[0]
    cancelled = []
    for z in list(zs):
        best = None
        for p_ in ps:
            d = abs(z - p_)
            if (d <= rtol * abs(p_) or d == 0) and (best is None or d < abs(z - best)):
                best = p_
        if best is not None:
            ps.remove(best)
            zs.remove(z)
            cancelled.append(best)
    return from_roots(zs, lead), from_roots(ps, 1), ps, cancelled


def report(num, den, digits=17):
    num, den = trim(num), trim(den)
    lead = den[0]
    numn = [x / lead for x in num]
    denn = [x / lead for x in den]
    poles = proots(denn)
    mn, md, mpoles, canc = cancel(numn, denn)
    g = dc_gain(numn, denn)
    f = lambda x: float(x)
    r = {
        "num": [f(x) for x in numn],
        "den": [f(x) for x in denn],
        "order": len(denn) - 1,
        "poles": [[f(z.real), f(z.imag)] for z in poles],
        "dc_gain": None if g is None else f(g),
        "stable": all(z.real < 0 for z in poles),
        "max_real_pole": f(max(z.real for z in poles)),
        "minimal": {
            "num": [f(x) for x in mn],
            "den": [f(x) for x in md],
            "order": len(md) - 1,
            "poles": [[f(z.real), f(z.imag)] for z in sorted(mpoles, key=lambda z: (float(z.real), float(z.imag)))],
            "cancelled_poles": [[f(z.real), f(z.imag)] for z in canc],
            "stable": all(z.real < 0 for z in mpoles),
            "max_real_pole": f(max(z.real for z in mpoles)),
        },
    }
    return r


def normal_form(num, den):
    """Relative degree 2 plant g (s + beta)/(s^3 + a2 s^2 + a1 s + a0) (or g/(s^2 + a1 s + a0)) in
    the form of eq. ss_realization_1: x1 = F, x2 = F', z' = S z + G x, G = [1 0],
    x2' = psi z + phi' x + g u.  With z = g w, w = u/den:  S = -beta,
    phi = [-(beta - a2) beta - a1, beta - a2], psi = -(a2 - beta) beta^2 + a1 beta - a0."""
    num, den = trim(num), trim(den)
    num = [x / den[0] for x in num]
    den = [x / den[0] for x in den]
    if len(den) == 3 and len(num) == 1:
        return {"g": float(num[0]), "S": None, "psi": None, "phi": [float(-den[2]), float(-den[1])], "G": None}
    assert len(den) == 4 and len(num) == 2
    g = num[0]
    beta = num[1] / num[0]
    a2, a1, a0 = den[1], den[2], den[3]
    return {"g": float(g), "S": float(-beta), "psi": float(-(a2 - beta) * beta ** 2 + a1 * beta - a0),
            "phi": [float(-(beta - a2) * beta - a1), float(beta - a2)], "G": [1.0, 0.0]}


def boundary_layer(dob_c, plant_p, Ml_values):
    """Fast subsystem of eq. ss_realization_2 (time scaled by tau = 1/wc):
    [[A - r B C, r B C], [-B C, A + B C]], r = g/g_bar, A, B, C of the normalised Q filter.
    g: high-frequency gain (F''/i) of the actual plant k N K_r M_l/(M_l M_r + J'(M_l + M_r));
    g_bar: that of the DOB's nominal model, g_nom/M_nom."""
    A = mp.matrix([[0, 1], [-1, -mp.sqrt(2)]])
    B = mp.matrix([[0], [1]])
    C = mp.matrix([[1, 0]])
    BC = B * C
    gbar = dob_c["g_nom"] / dob_c["M_nom"]
    out = []
    for Ml in Ml_values:
        pl = Plant(dict(plant_p, M_l=Ml))
        g = pl.num_F_i[0] / pl.den[0]
        r = g / gbar
        M = mp.matrix(4, 4)
        blocks = ((A - r * BC, 0, 0), (r * BC, 0, 2), (-BC, 2, 0), (A + BC, 2, 2))
        for blk, i0, j0 in blocks:
            for i in range(2):
                for j in range(2):
                    M[i0 + i, j0 + j] = blk[i, j]
        ev = mp.eig(M)[0]
        # the paper's factorisation: char. polynomial p_a(s) p_b(s)
        pa = P(1, mp.sqrt(2), 1)
        pb = P(1, mp.sqrt(2), r)      # |sI - A + (r - 1) B C| = s^2 + sqrt2 s + 1 + (r - 1)
        out.append({"M_l": float(Ml), "g": float(g), "g_bar": float(gbar), "g_over_g_bar": float(r),
                    "eigenvalues": [[float(z.real), float(z.imag)] for z in
                                    sorted(ev, key=lambda z: (float(z.real), float(z.imag)))],
                    "roots_pa_pb": [[float(z.real), float(z.imag)] for z in proots(pmul(pa, pb))],
                    "max_real_eigenvalue": float(max(z.real for z in ev))})
    return out


def logspace(lo, hi, n):
    return [mp.mpf(lo) * (mp.mpf(hi) / lo) ** (mp.mpf(k) / (n - 1)) for k in range(n)]


def freq_diff(a, b, f_lo=0.01, f_hi=1000, per_decade=24):
    """max |Ta(jw) - Tb(jw)| on a log grid (a, b: (num, den))."""
    err = mp.mpf(0)
    n = int(round(math.log10(f_hi / f_lo) * per_decade))
    for k in range(n + 1):
        w = 2 * mp.pi * f_lo * mp.mpf(10) ** (mp.mpf(k) / per_decade)
        s = mp.mpc(0, w)
        err = max(err, abs(peval(a[0], s) / peval(a[1], s) - peval(b[0], s) / peval(b[1], s)))
    return err


def closed_loops(params):
    """{name: (num, den)} for the four shipped diagrams."""
    out = {}
    e = params["force_dob"]
    d = dob_loop(e["ctrl"], Plant(e["plant"]), e["pade"])
    out["force_dob"] = (d["F"], d["chi"])
    e = params["position_encoder"]
    r = position_encoder_loop(e["ctrl"], Plant(e["plant"]), e["pade"])
    out["position_encoder"] = (r["num"], r["den"])
    e = params["position_potentiometer"]
    r = position_potentiometer_loop(e["ctrl"], Plant(e["plant"]), e["pade"])
    out["position_potentiometer"] = (r["num"], r["den"])
    e = params["position_encoder_force"]
    r = position_encoder_force_loop(e["ctrl"], e["dob"], Plant(e["plant"]), e["pade"], e["dob_pade"])
    out["position_encoder_force"] = (r["num"], r["den"])
    return out


def compute(params, sweep_n=40):
    res = {}
    for name, (num, den) in closed_loops(params).items():
        res[name] = report(num, den)
    # DOB sweep over the load mass; convergence to the nominal response (M_l -> inf)
    e = params["force_dob"]
    c, plant_p, n = e["ctrl"], e["plant"], e["pade"]
    d = dob_loop(c, Plant(dict(plant_p, M_l=mp.mpf("1e30"))), n)
    nominal = (d["F"], d["chi"])
    sweep = []
    for Ml in logspace(2953, 1e9, sweep_n):
        d = dob_loop(c, Plant(dict(plant_p, M_l=Ml)), n)
        r = report(d["F"], d["chi"])
        sweep.append({"M_l": float(Ml), "stable": r["minimal"]["stable"],
                      "max_real_pole": r["minimal"]["max_real_pole"],
                      "max_real_pole_full": r["max_real_pole"],
                      "dc_gain": r["dc_gain"],
                      "max_abs_diff_to_nominal": float(freq_diff((d["F"], d["chi"]), nominal))})
    res["dob_sweep"] = sweep
    bl = boundary_layer(c, plant_p, logspace(2953, 1e9, sweep_n))
    res["boundary_layer"] = {"max_real_eigenvalue": max(b["max_real_eigenvalue"] for b in bl),
                             "hurwitz": all(b["max_real_eigenvalue"] < 0 for b in bl), "sweep": bl}
    # normal form (eq. ss_realization_1) of the plant i -> F (current input) and of the
    # plant driven in force units u = k_tau N_m i, actual (default M_l) and nominal
    pl = Plant(plant_p)
    nF3 = pl.num_F_i[:-1]                 # the common factor s of num and den dropped
    kN = pl.kN
    res["normal_form"] = {
        "actual_current_input": normal_form(nF3, pl.Delta),
        "actual_force_input": normal_form(pscale(nF3, 1 / kN), pl.Delta),
        "nominal_current_input": normal_form(P(pl.g_nom), pl.Delta_inf),
        "nominal_force_input": normal_form(P(pl.g_nom / kN), pl.Delta_inf),
        "paper": {"psi_bar": -9.53e3, "phi_bar": [-1.49e4, -0.01e4], "S_bar": -0.0433, "G_bar": [1, 0],
                  "g_bar": 1.31e4, "g(M_l)": "3.2e4 M_l/(2.4 M_l + 3.1)"},
    }
    res["plant"] = {
        "J_reflected": float(pl.Jp), "B_reflected": float(pl.Bp), "k_tau_N_m": float(kN),
        "P_i_F": report(nF3, pl.Delta),
        "P_inf_i_F": report(P(pl.g_nom), pl.Delta_inf),
    }
    return res


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--diagrams", default=DEFAULT_DIAGRAMS)
    ap.add_argument("--param", action="append", default=[], help="NAME=VALUE override in every diagram")
    ap.add_argument("--sweep", type=int, default=40)
    ap.add_argument("--compact", action="store_true")
    a = ap.parse_args()
    cli = {}
    for kv in a.param:
        k, v = kv.split("=", 1)
        cli[k] = v
    params = load_params(a.diagrams, cli)
    res = compute(params, a.sweep)
    json.dump(res, sys.stdout, indent=None if a.compact else 1)
    print()


if __name__ == "__main__":
    main()
