#!/usr/bin/env python3
"""The standing scenario with controller 1 of the paper written in NumPy (docs/python.md,
"Controllers in Python").

examples/scenarios/standing.yaml holds DRACO up with ten loop programs of
examples/diagrams/position_encoder_controller.yaml, one per joint. Here each is replaced by
JointPD below, the same loop by hand: PD on the encoder angle, the derivative through
D s/(tau s + 1) discretised by Tustin's rule at the loop's rate, force -> current by
1/(k_tau N_m), the current limit. Same rate (1 kHz), same computation delay (one period),
same bus signals.

    PYTHONPATH=build/python python3 examples/python/standing_numpy.py
"""
import math
import os
import sys

import numpy as np
import yaml

import dmbd

HERE = os.path.dirname(os.path.abspath(__file__))
SCENARIO = os.path.join(HERE, "..", "scenarios", "standing.yaml")


class JointPD:
    """Controller 1 for one joint: inputs [q_d, q_enc] (rad), output the motor current (A)."""

    def __init__(self, joint, N_m, k_tau, i_max, P_q, D_q, fc_dq=100.0, rate_hz=1000.0, delay_s=0.001):
        T = 1.0 / rate_hz
        tau = 1.0 / (2.0 * math.pi * fc_dq)
        # D s/(tau s + 1) by Tustin (s = (2/T)(z - 1)/(z + 1)):
        # (b0 - b0 z^-1)/(1 - p z^-1), b0 = 2 D/(2 tau + T), p = (2/T - 1/tau)/(2/T + 1/tau).
        c = 2.0 / T
        self.b0 = 2.0 * D_q / (2.0 * tau + T)
        self.p = (c - 1.0 / tau) / (c + 1.0 / tau)
        self.P = P_q
        self.k_ff = 1.0 / (k_tau * N_m)
        self.i_max = i_max
        self.rate_hz, self.delay_s = rate_hz, delay_s
        self.inputs = [joint + ".q_d", joint + ".q_enc"]
        self.outputs = {joint + ".current": "A"}
        self.reset()

    def reset(self):
        self.s = 0.0  # the derivative filter's state (direct form II transposed)

    def step(self, t, u):
        q_d, q_m = u
        d = self.b0 * q_m + self.s           # filtered derivative term (N)
        self.s = -self.b0 * q_m + self.p * d
        force = self.P * (q_d - q_m) - d     # N
        i = self.k_ff * force
        return np.array([min(max(i, -self.i_max), self.i_max)])


def controllers(scenario=SCENARIO):
    """A JointPD for each loop program of the scenario, with its parameters."""
    with open(scenario) as f:
        s = yaml.safe_load(f)
    return {c["name"]: JointPD(c["name"], **c["parameters"]) for c in s["controllers"]}


if __name__ == "__main__":
    duration = float(sys.argv[1]) if len(sys.argv) > 1 else None
    diagram = dmbd.run_scenario(SCENARIO, duration_s=duration)
    numpy_loop = dmbd.run_scenario(SCENARIO, duration_s=duration, controllers=controllers())
    a, b = diagram.log(), numpy_loop.log()
    worst = max(np.max(np.abs(a[k] - b[k])) / max(np.max(np.abs(a[k])), 1e-300) for k in a)
    timing = numpy_loop.metrics["runs"]["base"]["timing_us"]
    print(f"largest difference of a logged signal, relative to its largest value: {worst:.3g}")
    print(f"Python tick, median: {timing['python_l_knee_tick_us_median']:.2f} us (l_knee)")
