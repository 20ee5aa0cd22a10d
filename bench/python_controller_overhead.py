#!/usr/bin/env python3
"""What a controller written in Python costs in the simulated loop (docs/python.md,
"Controllers in Python"), on the standing scenario (DRACO, ten joint loops at 1 kHz, 10 s).

Contenders, interleaved round by round in one process:
  loop programs  the scenario as shipped: ten loop programs run by the interpreter (C++)
  NumPy loops    the same ten loops as Python objects (examples/python/standing_numpy.py)
  null           ten Python objects whose step() returns a ready array (nothing computed)
Per round: each run's wall time, and each Python controller's median tick (the bus
controller's own timing: taking the GIL, the input array, the call, reading the result).
Also the bare Python cost of JointPD.step (timeit, no simulation), so that the overhead of
a call, the tick minus what the user's step() costs itself, is printed. The anchor is the
scenario with its loop programs: the ratio of wall times says what Python adds to a run.

Usage: PYTHONPATH=build/python bench/python_controller_overhead.py [--rounds 5] [--duration 10]
"""
import argparse
import os
import statistics
import sys
import timeit

import numpy as np

import dmbd

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "examples", "python"))
import standing_numpy  # noqa: E402


class Null:
    """Drives one joint's current with a constant zero array: the call's overhead alone."""

    def __init__(self, joint):
        self.rate_hz, self.delay_s = 1000.0, 0.001
        self.inputs = [joint + ".q_d", joint + ".q_enc"]
        self.outputs = [joint + ".current"]
        self.y = np.zeros(1)

    def step(self, t, u):
        return self.y


def tick_median(run):
    """The median over the ten Python controllers of their median tick (µs)."""
    timing = run.metrics["runs"]["base"]["timing_us"]
    return statistics.median(v for k, v in timing.items() if k.startswith("python_") and k.endswith("_tick_us_median"))


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--duration", type=float, default=10.0)
    a = ap.parse_args()
    numpy_loops = standing_numpy.controllers()
    nulls = {name: Null(name) for name in numpy_loops}
    wall = {"loop programs": [], "NumPy loops": [], "null": []}
    ticks = {"NumPy loops": [], "null": []}
    for _ in range(a.rounds):
        wall["loop programs"].append(dmbd.run_scenario(standing_numpy.SCENARIO, duration_s=a.duration).runs[0]["wall_s"])
        for name, ctrl in (("NumPy loops", numpy_loops), ("null", nulls)):
            run = dmbd.run_scenario(standing_numpy.SCENARIO, duration_s=a.duration, controllers=ctrl)
            wall[name].append(run.runs[0]["wall_s"])
            ticks[name].append(tick_median(run))
    pd = numpy_loops["l_knee"]
    u = np.array([0.6, 0.61])
    n = 20000
    bare_us = min(timeit.repeat(lambda: pd.step(0.0, u), number=n, repeat=5)) / n * 1e6
    for name, w in wall.items():
        print(f"{name:14s} wall {statistics.median(w):.3f} s (min {min(w):.3f}, max {max(w):.3f}) for {a.duration:g} s simulated")
    for name, t in ticks.items():
        print(f"{name:14s} tick median {statistics.median(t):.2f} us (rounds {min(t):.2f}-{max(t):.2f})")
    print(f"JointPD.step alone (timeit): {bare_us:.2f} us")
    print(f"overhead per call (NumPy tick - step alone): {statistics.median(ticks['NumPy loops']) - bare_us:.2f} us; "
          f"null tick: {statistics.median(ticks['null']):.2f} us")
    ratio = statistics.median(wall["NumPy loops"]) / statistics.median(wall["loop programs"])
    print(f"wall time NumPy loops / loop programs: {ratio:.2f}")


if __name__ == "__main__":
    main()
