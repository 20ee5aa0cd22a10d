#!/usr/bin/env python3
"""`dmbd analyze` on the paper's diagrams against the hand derivation of paper_loops.py.

For each closed loop (DOB force loop F_d -> F, position controllers q_d -> q) dmbd
interconnects the YAML diagram in state space and reduces it to a minimal transfer
function; paper_loops.py derives the same loop by hand as a ratio of polynomials in
50-digit arithmetic. They must agree to 1e-6 relative on the frequency response, the
poles and the DC gain, and on stability; the M_l sweep of the DOB must be stable at
every point in both.
Usage: compare_dmbd.py PATH/TO/dmbd
"""
import json
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.normpath(os.path.join(HERE, "..", "..", ".."))
DIAGRAMS = os.path.join(ROOT, "examples", "diagrams")
RTOL = 1e-6
LOOPS = {
    "force_dob": ("F_d", "F"),
    "position_encoder": ("q_d", "q"),
    "position_potentiometer": ("q_d", "q"),
    "position_encoder_force": ("q_d", "q"),
}
failures = []


def dmbd(exe, *args):
    out = subprocess.run([exe, *args], capture_output=True, text=True)
    if out.returncode != 0:
        raise SystemExit(f"dmbd {' '.join(args)} failed: {out.stderr.strip()}")
    return json.loads(out.stdout)


def main():
    exe = sys.argv[1]
    ref = json.loads(subprocess.run([sys.executable, os.path.join(HERE, "paper_loops.py"), "--sweep", "40", "--compact"],
                                    capture_output=True, text=True, check=True).stdout)
    for name, (frm, to) in LOOPS.items():
        r = dmbd(exe, "analyze", os.path.join(DIAGRAMS, name + ".yaml"), "--from", frm, "--to", to, "--json",
                 "--freq-range", "0.01:2000:60")
        m = ref[name]["minimal"]
        w = 2 * np.pi * np.array(r["bode"]["freq_hz"])
        h_ref = np.polyval(m["num"], 1j * w) / np.polyval(m["den"], 1j * w)
        h = 10 ** (np.array(r["bode"]["mag_db"]) / 20) * np.exp(1j * np.radians(r["bode"]["phase_deg"]))
        err = np.max(np.abs(h - h_ref) / np.maximum(np.abs(h_ref), 1e-12))
        ok = err <= RTOL
        # Poles: every reference pole matched to 1e-6 relative (to 1e-3 of the largest
        # for poles near zero).
        got = [complex(a, b) for a, b in r["poles"]]
        want = [complex(a, b) for a, b in m["poles"]]
        scale = max(abs(p) for p in want)
        pole_err = 0.0
        if len(got) != len(want):
            failures.append(f"{name}: {len(got)} poles, reference {len(want)}")
            ok = False
        else:
            for p in want:
                k = int(np.argmin([abs(g - p) for g in got]))
                pole_err = max(pole_err, abs(got[k] - p) / max(abs(p), 1e-3 * scale))
                got.pop(k)
            ok = ok and pole_err <= RTOL
        dc_err = abs(r["dc_gain"] - ref[name]["dc_gain"]) / abs(ref[name]["dc_gain"])
        ok = ok and dc_err <= RTOL and r["stable"] == m["stable"]
        print(f"{'ok  ' if ok else 'FAIL'} {name}: response {err:.1e}, poles {pole_err:.1e}, dc gain {dc_err:.1e}, "
              f"stable {r['stable']} (reference {m['stable']}), order {len(r['poles'])}")
        if not ok:
            failures.append(name)
    # The DOB's robustness over the load mass (paper's theorem).
    r = dmbd(exe, "analyze", os.path.join(DIAGRAMS, "force_dob.yaml"), "--from", "F_d", "--to", "F", "--json",
             "--sweep", "M_l=2953:1e9:40:log")
    got = [p["stable"] for p in r["sweep"]]
    want = [p["stable"] for p in ref["dob_sweep"]]
    ok = len(got) == 40 and all(got) and all(want)
    for p, q in zip(r["sweep"], ref["dob_sweep"]):
        if abs(p["value"] - q["M_l"]) > 1e-9 * q["M_l"]:
            ok = False
    print(f"{'ok  ' if ok else 'FAIL'} force_dob sweep M_l = 2953 .. 1e9 (40 log points): {sum(got)} stable in dmbd, "
          f"{sum(want)} in the reference")
    if not ok:
        failures.append("sweep")
    n = len(LOOPS) + 1
    print(f"{n - len(failures)} passed, {len(failures)} failed")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
