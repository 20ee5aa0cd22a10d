#!/usr/bin/env python3
"""Bode of a 10th-order transfer function at 1000 frequencies: dmbd against SciPy,
like for like, interleaved in one process.

Both start from the same coefficients, held in a system object made once (dmbd's
TransferFunction, scipy.signal.lti); every timed call computes everything again from
those coefficients (dmbd finds the roots for its phase model each call; nothing is
cached across iterations). Both return the magnitude in dB and the unwrapped phase in
degrees. Rounds alternate dmbd, scipy.signal.bode, scipy.signal.freqs (the response
alone, as a floor); each round times `--calls` calls per contender and keeps the best
of `--repeat` such batches. Printed: per contender the median time per call over the
rounds, min-max, and the median over rounds of the per-round ratio SciPy / dmbd (> 1:
dmbd is faster).

Usage: PYTHONPATH=build/python bench/bode_vs_scipy.py [--rounds 7] [--calls 200]
"""
import argparse
import statistics
import timeit

import numpy as np
from scipy import signal

import dmbd


def system():
    """Five lightly to well damped pole pairs from 0.1 to 100 rad/s and nine zeros
    (four pairs and one real, one pair in the right half-plane), gain 1 at DC."""
    wn = np.logspace(-1, 2, 5)
    zeta = np.array([0.05, 0.2, 0.4, 0.7, 0.1])
    poles = np.concatenate([-zeta * wn + 1j * wn * np.sqrt(1 - zeta**2), -zeta * wn - 1j * wn * np.sqrt(1 - zeta**2)])
    zwn = np.logspace(-0.5, 1.5, 4)
    zzeta = np.array([0.3, -0.2, 0.6, 0.15])
    zeros = np.concatenate([-zzeta * zwn + 1j * zwn * np.sqrt(1 - zzeta**2),
                            -zzeta * zwn - 1j * zwn * np.sqrt(1 - zzeta**2), [-3.0]])
    num = np.real(np.poly(zeros))
    den = np.real(np.poly(poles))
    num *= den[-1] / num[-1]
    return num, den


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=7)
    ap.add_argument("--calls", type=int, default=200)
    ap.add_argument("--repeat", type=int, default=3)
    args = ap.parse_args()

    num, den = system()
    w = np.logspace(-2, 3, 1000)
    g = dmbd.TransferFunction(list(num), list(den))
    sys = signal.lti(num, den)

    # Same answer first: magnitude to 1e-9 dB; phase to 1e-7 deg once SciPy's unwrap
    # (which starts from the principal value at the first frequency) is moved onto
    # dmbd's branch at DC.
    mag, ph = dmbd.bode(g, w)
    _, smag, sph = signal.bode(sys, w=w)
    shift = 360.0 * np.round((ph[0] - sph[0]) / 360.0)
    assert np.max(np.abs(mag - smag)) < 1e-9, np.max(np.abs(mag - smag))
    assert np.max(np.abs(ph - (sph + shift))) < 1e-7, np.max(np.abs(ph - (sph + shift)))

    contenders = {
        "dmbd.bode": lambda: dmbd.bode(g, w),
        "scipy.signal.bode": lambda: signal.bode(sys, w=w),
        "scipy.signal.freqs": lambda: signal.freqs(num, den, worN=w),
    }
    times = {k: [] for k in contenders}
    for _ in range(args.rounds):
        for name, f in contenders.items():
            best = min(timeit.repeat(f, number=args.calls, repeat=args.repeat)) / args.calls
            times[name].append(best)

    print(f"Bode, 10th order (9 zeros), {len(w)} frequencies; {args.rounds} interleaved rounds,"
          f" best of {args.repeat} x {args.calls} calls each")
    for name, t in times.items():
        print(f"  {name:20s} median {statistics.median(t) * 1e6:8.1f} us  (min {min(t) * 1e6:.1f}, max {max(t) * 1e6:.1f})")
    for name in ("scipy.signal.bode", "scipy.signal.freqs"):
        ratios = [s / d for s, d in zip(times[name], times["dmbd.bode"])]
        print(f"  {name} / dmbd.bode: median {statistics.median(ratios):.2f}"
              f" (min {min(ratios):.2f}, max {max(ratios):.2f})")


if __name__ == "__main__":
    main()
