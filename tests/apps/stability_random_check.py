#!/usr/bin/env python3
"""Certified stability verdicts near the boundary (issue 28): 200 random systems.

Continuous and discrete systems of orders 1-20 with one critical pole (or conjugate
pair) at a distance d from the stability boundary, d log-uniform in [1e-12, 1e-2]
(continuous: Re p = -+d with the system's poles of size 0.1-10; discrete: |z| = 1 -+ d),
on the stable side for half of them and the unstable side for the other half; some
with a repeated pole of multiplicity m at a distance >= 1e-15^(1/m); the other poles
inside, at least 1e-2 from the boundary. Each denominator is multiplied out in mpmath
and rounded to doubles, written with repr (monic, so the transfer function's
normalisation leaves the coefficients as written).

The truth: mpmath.polyroots at 50 digits on those same doubles (error estimate checked
against the distance to the boundary). Each verdict from
  - `dmbd analyze --tf '1/(...)' [--ts 0.001] --json`  (JSON `stability`),
  - `dmbd analyze DIAGRAM --from u --to y --json` for a diagram with one `tf` block
    whose `den` is the same list of doubles,
  - the Python module (`dmbd.stability(dmbd.tf(...))`), when it is importable,
must be right, or "undecided"; a wrong verdict fails the test. The undecided counts are
printed (and must stay a minority: at most 10 % per interface).

Usage: stability_random_check.py PATH/TO/dmbd
"""
import concurrent.futures
import json
import os
import random
import subprocess
import sys
import tempfile

import mpmath

SEED = 2028
COUNT = 200
TS = 0.001
TIMEOUT_S = 5  # a run that takes longer has no verdict: a failure


def critical_poles(rng, discrete, outside, d, n_left):
    """The pole(s) at distance d from the boundary, on the side asked."""
    pair = n_left >= 2 and rng.random() < 0.6
    sign = 1 if outside else -1
    if not discrete:
        if pair:
            w = mpmath.mpf(10) ** rng.uniform(-1, 1)
            return [mpmath.mpc(sign * d, w), mpmath.mpc(sign * d, -w)]
        return [mpmath.mpf(sign * d)]
    r = 1 + sign * mpmath.mpf(d)
    if pair:
        th = rng.uniform(0.05, 3.0)
        return [r * mpmath.expjpi(th / mpmath.pi), r * mpmath.expjpi(-th / mpmath.pi)]
    return [r if rng.random() < 0.7 else -r]


def inside_poles(rng, discrete, n, min_distance=1e-2):
    """n poles (conjugate pairs where complex) at least min_distance inside."""
    out = []
    while len(out) < n:
        pair = n - len(out) >= 2 and rng.random() < 0.5
        if not discrete:
            rho = mpmath.mpf(10) ** rng.uniform(-1, 1)
            sigma = max(min_distance, rho * rng.uniform(0.02, 1.0))
            if pair:
                w = rho * rng.uniform(0.1, 2.0)
                out += [mpmath.mpc(-sigma, w), mpmath.mpc(-sigma, -w)]
            else:
                out.append(-sigma)
        else:
            r = mpmath.mpf(rng.uniform(0.0, 1.0 - min_distance))
            if pair:
                th = rng.uniform(0.05, 3.0)
                out += [r * mpmath.expjpi(th / mpmath.pi), r * mpmath.expjpi(-th / mpmath.pi)]
            else:
                out.append(r if rng.random() < 0.7 else -r)
    return out


def repeated_poles(rng, discrete, m, outside):
    """A pole of multiplicity m at a distance >= 1e-15^(1/m) from the boundary."""
    lo = -15.0 / m
    d = mpmath.mpf(10) ** rng.uniform(lo, max(lo, -1.0))
    sign = 1 if outside else -1
    if not discrete:
        return [mpmath.mpf(sign * d) - (0 if outside else 0)] * m
    return [1 + sign * d] * m


def make_system(rng, k):
    discrete = k % 2 == 1
    unstable = (k // 2) % 2 == 1
    n = rng.randint(1, 20)
    d = mpmath.mpf(10) ** rng.uniform(-12, -2)
    poles = []
    if n >= 3 and rng.random() < 0.25:
        m = rng.randint(2, min(6, n - 1))
        outside = unstable and rng.random() < 0.3
        poles += repeated_poles(rng, discrete, m, outside)
    poles += critical_poles(rng, discrete, unstable, d, n - len(poles))
    poles += inside_poles(rng, discrete, n - len(poles))
    with mpmath.workdps(60):
        c = [mpmath.mpc(1)]
        for p in poles:
            c = [a - p * b for a, b in zip(c + [0], [0] + c)]
    coeffs = [float(mpmath.re(x)) for x in c]  # highest power first, c[0] = 1
    return {"k": k, "discrete": discrete, "unstable_by_design": unstable, "distance": float(d), "den": coeffs}


def truth(sys_):
    """mpmath.polyroots at 50 digits on the doubles: 'stable' or 'unstable' (None if a
    root is closer to the boundary than the roots' error estimate)."""
    with mpmath.workdps(50):
        cs = [mpmath.mpf(x) for x in sys_["den"]]
        if len(cs) == 2:
            roots, err = [-cs[1] / cs[0]], mpmath.mpf(0)
        else:
            roots, err = mpmath.polyroots(cs, maxsteps=400, extraprec=400, error=True)
        worst = None
        for r in roots:
            dist = (abs(r) - 1) if sys_["discrete"] else mpmath.re(r)
            if abs(dist) <= 10 * err + mpmath.mpf(10) ** -45:
                return None
            worst = dist if worst is None else max(worst, dist)
        return "unstable" if worst > 0 else "stable"


def poly_text(den, var):
    n = len(den) - 1
    terms = []
    for i, c in enumerate(den):
        p = n - i
        mono = "" if p == 0 else (var if p == 1 else f"{var}^{p}")
        if i == 0:
            terms.append(mono if c == 1.0 else f"{c!r}*{mono}")
        else:
            terms.append(f"({c!r})" + ("" if p == 0 else "*" + mono))
    return " + ".join(terms)


def expression(sys_):
    return "1/(" + poly_text(sys_["den"], "z" if sys_["discrete"] else "s") + ")"


def run_json(args):
    try:
        r = subprocess.run(args, capture_output=True, text=True, timeout=TIMEOUT_S)
    except subprocess.TimeoutExpired:
        return {"error": f"did not finish in {TIMEOUT_S} s"}
    if r.returncode != 0:
        return {"error": r.stderr.strip()}
    return json.loads(r.stdout)


def cli_verdict(dmbd, sys_):
    args = [dmbd, "analyze", "--tf", expression(sys_), "--json"]
    if sys_["discrete"]:
        args += ["--ts", repr(TS)]
    j = run_json(args)
    return j.get("stability", "error: " + j.get("error", "?"))


def diagram_verdict(dmbd, sys_, folder):
    path = os.path.join(folder, f"system_{sys_['k']}.yaml")
    den = ", ".join(f"'{c!r}'" for c in sys_["den"])
    with open(path, "w") as f:
        f.write(f"name: system_{sys_['k']}\n")
        if sys_["discrete"]:
            f.write(f"sample_time: {TS!r}\n")
        f.write("inputs:\n  u: {}\noutputs:\n  y: {}\nblocks:\n")
        f.write(f"  G: {{type: tf, num: [1], den: [{den}]}}\n")
        f.write("connections:\n  - u -> G\n  - G -> y\n")
    j = run_json([dmbd, "analyze", path, "--from", "u", "--to", "y", "--json"])
    return j.get("stability", "error: " + j.get("error", "?"))


def python_verdict(dmbd_module, sys_):
    g = dmbd_module.tf(expression(sys_), TS if sys_["discrete"] else 0.0)
    return dmbd_module.stability(g)


def main():
    dmbd = sys.argv[1]
    rng = random.Random(SEED)
    systems = [make_system(rng, k) for k in range(COUNT)]
    try:
        import dmbd as dmbd_module  # from PYTHONPATH (the build tree), when built
    except ImportError:
        dmbd_module = None
        print("Python module dmbd not importable: that interface is skipped")
    truths = [truth(s) for s in systems]
    interfaces = {"--tf": [], "diagram": [], "python": []}
    with tempfile.TemporaryDirectory() as folder, concurrent.futures.ThreadPoolExecutor(4) as pool:
        interfaces["--tf"] = list(pool.map(lambda s: cli_verdict(dmbd, s), systems))
        interfaces["diagram"] = list(pool.map(lambda s: diagram_verdict(dmbd, s, folder), systems))
    if dmbd_module is not None:
        interfaces["python"] = [python_verdict(dmbd_module, s) for s in systems]
    failures = []
    ambiguous = sum(t is None for t in truths)
    for name, verdicts in interfaces.items():
        if not verdicts:
            continue
        right = undecided = wrong = 0
        for s, t, v in zip(systems, truths, verdicts):
            if t is None:
                continue
            if v == t:
                right += 1
            elif v == "undecided":
                undecided += 1
            else:
                wrong += 1
                failures.append(f"{name}: system {s['k']} ({'discrete' if s['discrete'] else 'continuous'}, order "
                                f"{len(s['den']) - 1}, distance {s['distance']:.3g}): {v}, truth {t}; den {s['den']!r}")
        print(f"{name:8s}: {right} right, {undecided} undecided, {wrong} wrong or no verdict (of {COUNT - ambiguous})")
        if undecided > COUNT // 10:
            failures.append(f"{name}: {undecided} undecided verdicts (more than 10 %)")
    stable = sum(t == "stable" for t in truths)
    print(f"truth: {stable} stable, {COUNT - ambiguous - stable} unstable, {ambiguous} too close to call (skipped)")
    for f in failures:
        print("FAIL", f)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
