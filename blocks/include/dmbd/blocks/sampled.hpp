#pragma once
// Exact sampled-data models: a continuous system between a zero-order hold (its inputs
// held constant over each period ts) and a sampler (its outputs read at k ts), with dead
// times at its inputs and outputs. This is what a discrete controller running at ts sees
// of a continuous plant; it is exact, not an approximation (Franklin, Powell and
// Workman, Digital Control of Dynamic Systems, 3rd ed., Sec. 4.3.4 and 6.2: the
// modified z-transform).
#include <optional>
#include <vector>

#include "dmbd/blocks/state_space.hpp"
#include "dmbd/blocks/transfer_function.hpp"

namespace dmbd::blocks {

// delay_s as whole samples of ts: n when |delay_s / ts - n| <= 1e-9 max(1, n), else
// nullopt. InputError for ts <= 0 or delay_s < 0.
std::optional<int> whole_samples(double delay_s, double ts);

// The ZOH-sampled model of a continuous `sys` at ts, input j delayed by
// input_delays_s[j] >= 0 seconds (any value: a fraction of a period is exact too) and
// output i by output_delay_samples[i] >= 0 whole periods (an empty list: no delay).
//
// With input delay tau = d ts + theta (0 <= theta < ts), the input reaches the plant as
// u[k-d-1] over the first theta of period k and u[k-d] over the rest, so
//   x[k+1] = Phi x[k] + Gamma(ts - theta) u[k-d] + e^{A (ts - theta)} Gamma(theta) u[k-d-1]
// with Phi = e^{A ts}, Gamma(t) = int_0^t e^{A s} ds B; the output at k ts reads the
// input of period k-d-1 through D when theta > 0. The model's states: the plant's, one
// per input with theta > 0 (u[k-d-1]), then shift registers for the whole-period delays
// of the inputs and of the outputs, in that order. Without delays it is c2d(sys, ts, Zoh).
// InputError for a discrete sys, ts <= 0, a list of the wrong length, a negative or
// non-finite delay, or one of more than 1000 periods.
StateSpace c2d_zoh_delayed(const StateSpace& sys, double ts, const std::vector<double>& input_delays_s,
                           const std::vector<int>& output_delay_samples = {});

// The same for a SISO transfer function G(s) e^{-s delay_s}: the modified z-transform of
// ZOH, as a transfer function in z (order: G's, plus one when the delay has a fraction
// of a period, plus the whole periods). InputError as above, and for an improper G.
TransferFunction c2d_zoh_delayed(const TransferFunction& g, double ts, double delay_s);

}  // namespace dmbd::blocks
