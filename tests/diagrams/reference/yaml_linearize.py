#!/usr/bin/env python3
"""Wiring check of the shipped diagrams: a deliberately small, independent reading of
the YAML format (docs/diagram-format.md) into one state-space model, compared with
the hand-derived closed loops of paper_loops.py.

This is NOT the reference for `dmbd analyze` (paper_loops.py is: it never builds state
space); it only makes sure that the YAML files say what the derivation says -- a sign,
a port or a gain wired wrongly shows up as a frequency-response mismatch.

Usage:  yaml_linearize.py [--diagrams DIR]      exit status 1 on a mismatch
        yaml_linearize.py FILE --from IN --to OUT [--param NAME=VALUE ...]   print poles and Bode
"""
import argparse
import math
import os
import sys

import numpy as np
from scipy import signal

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import paper_loops as pl  # noqa: E402


# ---------------------------------------------------------------- rational expressions
class Rat:
    def __init__(self, num, den=(1.0,)):
        self.n = np.atleast_1d(np.asarray(num, float))
        self.d = np.atleast_1d(np.asarray(den, float))

    @staticmethod
    def lift(x):
        return x if isinstance(x, Rat) else Rat([float(x)])

    def __add__(self, o):
        o = Rat.lift(o)
        return Rat(np.polyadd(np.polymul(self.n, o.d), np.polymul(o.n, self.d)), np.polymul(self.d, o.d))

    __radd__ = __add__

    def __neg__(self):
        return Rat(-self.n, self.d)

    def __sub__(self, o):
        return self + (-Rat.lift(o))

    def __rsub__(self, o):
        return Rat.lift(o) - self

    def __mul__(self, o):
        o = Rat.lift(o)
        return Rat(np.polymul(self.n, o.n), np.polymul(self.d, o.d))

    __rmul__ = __mul__

    def __truediv__(self, o):
        o = Rat.lift(o)
        return Rat(np.polymul(self.n, o.d), np.polymul(self.d, o.n))

    def __rtruediv__(self, o):
        return Rat.lift(o) / self

    def __pow__(self, k):
        assert int(k) == k and k >= 0
        r = Rat([1.0])
        for _ in range(int(k)):
            r = r * self
        return r


def eval_tf(expr, env):
    names = {k: float(v) for k, v in env.items() if not k.startswith("_")}
    names.update({"pi": math.pi, "e": math.e, "sqrt": math.sqrt, "exp": math.exp, "log": math.log,
                  "log10": math.log10, "sin": math.sin, "cos": math.cos, "tan": math.tan, "abs": abs,
                  "pow": pow, "min": min, "max": max, "s": Rat([1.0, 0.0])})
    r = eval(str(expr).replace("^", "**"), {"__builtins__": {}}, names)
    r = Rat.lift(r)
    # strip leading zeros
    n, d = np.trim_zeros(r.n, "f"), np.trim_zeros(r.d, "f")
    return (n if len(n) else np.array([0.0])), d


def num(v, env):
    return float(pl.eval_expr(v, env))


def tf_ss(n, d):
    n, d = np.asarray(n, float), np.asarray(d, float)
    if len(d) == 1:
        return np.zeros((0, 0)), np.zeros((0, 1)), np.zeros((1, 0)), np.array([[n[-1] / d[0]]])
    A, B, C, D = signal.tf2ss(n, d)
    return A, B, C, D


# ---------------------------------------------------------------- flattening
class Flat:
    def __init__(self):
        self.nodes = {}      # name -> dict(A,B,C,D, ins, outs)
        self.drivers = {}    # (node, in_port) -> signal
        self.ext = []        # top-level inputs


def block_ss(b, env, pade_order):
    t = b["type"]
    if t == "gain":
        return tf_ss([num(b["k"], env)], [1.0]), ["in"]
    if t == "sum":
        signs = b.get("signs", "++")
        D = np.array([[1.0 if c == "+" else -1.0 for c in signs]])
        return (np.zeros((0, 0)), np.zeros((0, len(signs))), np.zeros((1, 0)), D), [f"in{k + 1}" for k in range(len(signs))]
    if t == "saturation":
        return tf_ss([1.0], [1.0]), ["in"]
    if t == "integrator":
        return tf_ss([num(b.get("k", 1), env)], [1.0, 0.0]), ["in"]
    if t == "tf":
        if "expr" in b:
            n, d = eval_tf(b["expr"], env)
        else:
            n = [num(x, env) for x in b["num"]]
            d = [num(x, env) for x in b["den"]]
        return tf_ss(n, d), ["in"]
    if t == "pd":
        P_, D_, tau = num(b["P"], env), num(b["D"], env), num(b["tau"], env)
        return tf_ss([P_ * tau + D_, P_], [tau, 1.0]), ["in"]
    if t == "pid":
        P_, I_, D_, tau = (num(b[k], env) for k in ("P", "I", "D", "tau"))
        r = Rat([P_]) + Rat([I_], [1, 0]) + Rat([D_, 0], [tau, 1])
        return tf_ss(r.n, r.d), ["in"]
    if t == "lowpass":
        n, d = pl.butter(int(num(b["order"], env)), 2 * pl.mp.pi * num(b["cutoff_hz"], env))
        return tf_ss([float(x) for x in n], [float(x) for x in d]), ["in"]
    if t == "delay":
        order = int(b.get("pade_order", pade_order))
        n, d = pl.pade(pl.mp.mpf(num(b["seconds"], env)), order)
        return tf_ss([float(x) for x in n], [float(x) for x in d]), ["in"]
    if t == "ss":
        A = np.array([[num(x, env) for x in row] for row in b["A"]], float)
        B = np.array([[num(x, env) for x in row] for row in b["B"]], float)
        C = np.array([[num(x, env) for x in row] for row in b["C"]], float)
        D = np.array([[num(x, env) for x in row] for row in b["D"]], float) if "D" in b else np.zeros((C.shape[0], B.shape[1]))
        return (A, B, C, D), ["in"]
    raise ValueError(f"block type {t}")


def flatten(path, prefix, overrides, cli, flat, parent_pade=3):
    import yaml

    with open(path) as f:
        d = yaml.safe_load(f)
    raw = dict(d.get("parameters") or {})
    raw.update(overrides or {})
    raw.update(cli or {})
    env = pl.resolve(raw)
    pade_order = int((d.get("analysis") or {}).get("pade_order", parent_pade))
    inputs = list((d.get("inputs") or {}).keys())
    outputs = list((d.get("outputs") or {}).keys())
    blocks = d["blocks"]
    local = {}   # name -> ("node", nodename) or ("sub", info)
    # diagram inputs: identity nodes
    for name in inputs:
        node = f"{prefix}{name}@in"
        flat.nodes[node] = dict(zip("ABCD", tf_ss([1.0], [1.0])), ins=["in"], outs=["out"])
        if not prefix:
            flat.ext.append(name)
            flat.drivers[(node, "in")] = ("ext", name)
    for name, b in blocks.items():
        if b["type"] == "subsystem":
            ov = {k: pl.eval_expr(v, env) for k, v in (b.get("parameters") or {}).items()}
            info = flatten(os.path.join(os.path.dirname(path), b["file"]), f"{prefix}{name}/", ov, cli, flat, pade_order)
            local[name] = ("sub", info)
        else:
            (A, B, C, D), ins = block_ss(b, env, pade_order)
            node = prefix + name
            flat.nodes[node] = dict(A=A, B=B, C=C, D=D, ins=ins, outs=["out"])
            local[name] = ("node", node)

    def source(ref):
        if ref in inputs:
            return (f"{prefix}{ref}@in", "out")
        blk, _, port = ref.partition(".")
        kind, obj = local[blk]
        if kind == "node":
            return (obj, "out")
        return obj["outputs"][port]          # subsystem output: its driving signal

    def sink(ref):
        if ref in outputs:
            return ("out", ref)
        blk, _, port = ref.partition(".")
        kind, obj = local[blk]
        if kind == "node":
            ins = flat.nodes[obj]["ins"]
            return (obj, port if port else ins[0])
        return (obj["inputs"][port], "in")

    out_map = {}
    for c in d["connections"]:
        if isinstance(c, dict):
            frm, to = c["from"], c["to"]
        else:
            frm, to = [x.strip() for x in c.split("->")]
            if to.startswith("["):
                to = [x.strip() for x in to.strip("[]").split(",")]
        tos = to if isinstance(to, list) else [to]
        src = source(frm)
        for t in tos:
            kind, port = sink(t)
            if kind == "out":
                out_map[port] = src
            else:
                key = (kind, port)
                assert key not in flat.drivers, f"{t} driven twice"
                flat.drivers[key] = src
    return {"inputs": {n: f"{prefix}{n}@in" for n in inputs}, "outputs": out_map}


def assemble(path, cli=None):
    flat = Flat()
    top = flatten(path, "", None, cli, flat)
    names = list(flat.nodes)
    xo, yo, uo = {}, {}, {}
    nx = ny = nu = 0
    for n in names:
        nd = flat.nodes[n]
        xo[n] = nx
        nx += nd["A"].shape[0]
        yo[n] = ny
        ny += 1
        uo[n] = nu
        nu += len(nd["ins"])
    ne = len(flat.ext)
    A = np.zeros((nx, nx)); B = np.zeros((nx, nu)); C = np.zeros((ny, nx)); D = np.zeros((ny, nu))
    for n in names:
        nd = flat.nodes[n]
        k = nd["A"].shape[0]
        A[xo[n]:xo[n] + k, xo[n]:xo[n] + k] = nd["A"]
        B[xo[n]:xo[n] + k, uo[n]:uo[n] + len(nd["ins"])] = nd["B"]
        C[yo[n], xo[n]:xo[n] + k] = nd["C"]
        D[yo[n], uo[n]:uo[n] + len(nd["ins"])] = nd["D"]
    S = np.zeros((nu, ny)); W = np.zeros((nu, ne))
    for n in names:
        for j, p in enumerate(flat.nodes[n]["ins"]):
            src = flat.drivers[(n, p)]
            if src[0] == "ext":
                W[uo[n] + j, flat.ext.index(src[1])] = 1
            else:
                S[uo[n] + j, yo[src[0]]] = 1
    L = np.linalg.inv(np.eye(ny) - D @ S)
    Acl = A + B @ S @ L @ C
    Bcl = B @ (S @ L @ D @ W + W)
    Ccl = L @ C
    Dcl = L @ D @ W
    outs = {o: yo[src[0]] for o, src in top["outputs"].items()}
    return Acl, Bcl, Ccl, Dcl, flat.ext, outs


def analyze(path, frm, to, cli=None):
    A, B, C, D, ext, outs = assemble(path, cli)
    j, i = ext.index(frm), outs[to]
    return A, B[:, [j]], C[[i], :], D[[i]][:, [j]]


def freq(sys_, w):
    A, B, C, D = sys_
    n = A.shape[0]
    return np.array([(C @ np.linalg.solve(1j * x * np.eye(n) - A, B) + D)[0, 0] for x in w])


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("file", nargs="?")
    ap.add_argument("--from", dest="frm")
    ap.add_argument("--to")
    ap.add_argument("--param", action="append", default=[])
    ap.add_argument("--diagrams", default=pl.DEFAULT_DIAGRAMS)
    a = ap.parse_args()
    cli = dict(kv.split("=", 1) for kv in a.param)
    if a.file:
        s = analyze(a.file, a.frm, a.to, cli)
        ev = np.linalg.eigvals(s[0])
        print("order", s[0].shape[0], "max real pole", ev.real.max())
        for z in sorted(ev, key=lambda z: (z.real, z.imag)):
            print(f"  {z.real:.10g} {z.imag:+.10g}j")
        for f in (0.1, 1, 10, 100):
            h = freq(s, [2 * math.pi * f])[0]
            print(f"  {f:6g} Hz  |G| {abs(h):.8g}  phase {math.degrees(math.atan2(h.imag, h.real)):.4f} deg")
        return 0
    params = pl.load_params(a.diagrams, cli)
    loops = pl.closed_loops(params)
    w = 2 * np.pi * np.logspace(-2, 3, 61)
    bad = 0
    cases = [("force_dob", "F_d", "F"), ("position_encoder", "q_d", "q"),
             ("position_potentiometer", "q_d", "q"), ("position_encoder_force", "q_d", "q")]
    for name, frm, to in cases:
        s = analyze(os.path.join(a.diagrams, name + ".yaml"), frm, to, cli)
        h = freq(s, w)
        n, d = loops[name]
        nf = np.array([float(x) for x in n]); df = np.array([float(x) for x in d])
        href = np.polyval(nf, 1j * w) / np.polyval(df, 1j * w)
        err = np.max(np.abs(h - href) / np.maximum(np.abs(href), 1e-6))
        ev = np.sort_complex(np.linalg.eigvals(s[0]))
        order_ok = s[0].shape[0] == len(d) - 1
        ok = err < 1e-6 and order_ok
        bad += not ok
        print(f"{name:24s} order {s[0].shape[0]:2d} (reference {len(d) - 1:2d})  max rel. freq. error {err:.2e}  "
              f"max real pole {ev.real.max():.6g}  {'ok' if ok else 'MISMATCH'}")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
