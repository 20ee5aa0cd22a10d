#!/usr/bin/env python3
"""Step responses over long horizons, stiff and with repeated poles, against mpmath.

Issue 28: "Step responses of stable systems over horizons up to 1e6 time constants
agree with mpmath at every sample to |y - y_ref| <= 1e-9 max|y_ref|."

A set of stable transfers (six written out: stiffness ratios up to 1e12, repeated poles
up to (s + 1)^12, biproper; four drawn with a fixed seed: orders 1 to 8, real and
complex poles from 1e-4 to 1e4 rad/s, random numerators) is given as factored
expressions to `dmbd analyze --tf ... --step T:N --json` at horizons of 8 and 1e6
slowest time constants, and the six also at 1e-6 of the fastest one (the first samples
after t = 0, where y ~ t^k: exact there means relative to those tiny values). y(0) must
be D exactly. The reference takes the
coefficients dmbd printed (the same doubles) and evaluates the Van Loan exponential
e^{M t}, M = [A b; 0 0] of their companion realisation, in mpmath at 50 digits:
e^{M dt} once (mpmath.expm), then its powers (at 50 digits the products' rounding is
far below 1e-30). The same responses through the Python module when it is importable
(PYTHONPATH=build/python).

Usage: long_horizon_check.py PATH/TO/dmbd
"""
import json
import random
import subprocess
import sys

import mpmath

import mp_step  # beside this script

TOL = 1e-9
mpmath.mp.dps = 50


def factored_systems(rng):
    """(label, expression, slowest decay rate, fastest |pole|) for a fixed-seed set."""
    out = [
        ("1/(s+1)", "1/(s+1)", 1.0, 1.0),
        ("row 2b stiff", "1e6/((s+1e-6)*(s+1e6))", 1e-6, 1e6),
        ("(s+1)^5", "1/(s+1)^5", 1.0, 1.0),
        ("(s+1)^12", "1/(s+1)^12", 1.0, 1.0),
        ("(s^2+0.2s+1)^2 biproper", "(s^4 + 3*s^2 + 0.5)/(s^2+0.2*s+1)^2", 0.1, 1.0),
        ("(s+2)^3 (s+1e4)", "3e4*(s-1)/((s+2)^3*(s+1e4))", 2.0, 1e4),
    ]
    for k in range(4):
        order = rng.randint(1, 8)
        factors, rates, mags = [], [], []
        while sum(2 if "^2" in f else 1 for f in factors) < order:
            w = 10.0 ** rng.uniform(-4, 4)
            if rng.random() < 0.5 or sum(2 if "^2" in f else 1 for f in factors) == order - 1:
                factors.append(f"(s+{w!r})")
                rates.append(w)
            else:
                zeta = rng.uniform(0.02, 0.95)
                factors.append(f"(s^2+{2 * zeta * w!r}*s+{w * w!r})")
                rates.append(zeta * w)
            mags.append(w)
        n = sum(2 if "^2" in f else 1 for f in factors)
        deg = rng.randint(0, n)  # deg == n: biproper
        num = "+".join(f"{rng.uniform(-2, 2)!r}*s^{j}" for j in range(deg + 1))
        expr = f"({num})/({'*'.join(factors)})"
        out.append((f"random {k} (order {n})", expr, min(rates), max(mags)))
    return out


def reference_step(num, den, t):
    """The step response at the samples t from mpmath at 50 digits (mp_step.py)."""
    return mp_step.step_samples(num, den, t, 50)


def compare(label, got, ref, failures):
    scale = max(abs(v) for v in ref)
    worst = 0.0
    for k, (g, r) in enumerate(zip(got, ref)):
        if g is None:
            failures.append(f"{label}: y[{k}] is null, reference {r!r}")
            continue
        err = abs(g - r) / scale
        worst = max(worst, err)
        if not err <= TOL:
            failures.append(f"{label}: y[{k}] = {g!r}, reference {r!r} (error {err:.2e} of max|y|)")
    return worst


def main():
    exe = sys.argv[1]
    try:
        import numpy as np
        import dmbd
    except ImportError:
        dmbd = None
    rng = random.Random(28)
    failures, worst, checked = [], 0.0, 0
    for label, expr, slow, fast in factored_systems(rng):
        horizons = [("8 slowest", 8.0 / slow, 41), ("1e6 slowest", 1e6 / slow, 11)]
        if not label.startswith("random"):
            horizons.append(("1e-6 of the fastest", 1e-6 / fast, 5))
        for hname, t_end, n in horizons:
            out = subprocess.run([exe, "analyze", "--tf", expr, "--step", f"{t_end!r}:{n}", "--json"],
                                 capture_output=True, text=True)
            name = f"{label}, {hname}"
            if out.returncode != 0:
                failures.append(f"{name}: dmbd exited {out.returncode}: {out.stderr.strip()}")
                continue
            r = json.loads(out.stdout)
            t, y = r["step"]["t"], r["step"]["y"]
            if t[0] != 0.0 or y[0] != (r["num"][0] / r["den"][0] if len(r["num"]) == len(r["den"]) else 0.0):
                failures.append(f"{name}: y(0) = {y[0]!r} is not D exactly")
            ref = reference_step(r["num"], r["den"], t)
            worst = max(worst, compare(name, y, ref, failures))
            checked += 1
            if dmbd is not None:
                g = dmbd.tf(r["num"], r["den"], 0.0)
                yp = [float(v) for v in dmbd.step(g, np.array(t))]
                worst = max(worst, compare(name + " (Python)", yp, ref, failures))
    for f in failures:
        print("  " + f)
    print(f"{checked} responses{' (CLI and Python)' if dmbd else ' (CLI; Python module not importable)'}, "
          f"worst |y - y_ref| / max|y_ref| = {worst:.2e} (tolerance {TOL:g}), {len(failures)} failures")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
