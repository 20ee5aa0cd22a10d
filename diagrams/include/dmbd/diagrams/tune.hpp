#pragma once
// Gain tuning of position loops by the paper's procedure (Sec. III-C): raise the
// derivative gain until stability is about to be lost, then take the highest
// proportional gain whose step response does not overshoot; for a loop with an inner
// force loop, make the closed loop critically damped at a given natural frequency.
#include <string>
#include <vector>

#include "dmbd/diagrams/diagram_source.hpp"

namespace dmbd::diagrams {

// What the tunings judge a closed loop by (closed_loop_figures()). When the loop is not
// stable, every figure but `stable` is 0.
struct ClosedLoopFigures {
  // Every mode of the linearised interconnection strictly stable (StateSpace::is_stable:
  // an integrator at the origin is not), including modes the two signals do not see.
  bool stable = false;
  double overshoot_pct = 0.0;           // step, refined peak (0 when unstable: see stable)
  double natural_frequency_rad_s = 0.0; // see closed_loop_figures()
  double rise_time_s = 0.0;             // step, 10 % to 90 % of the final value (0 if undefined)
};

// Figures of the closed loop from `from` to `to` of an evaluated diagram. The natural
// frequency is the geometric mean of the magnitudes of the two slowest poles, leaving
// out poles that a zero within 2 % cancels (for a second-order loop it is w_n); poles of
// a discrete diagram are mapped to s = ln(z)/ts first. The step response runs on the
// minimal realisation over default_step_horizon(). InputError as linearize().
ClosedLoopFigures closed_loop_figures(const Diagram& diagram, const std::string& from, const std::string& to);

// The tunings evaluate their diagram's source at every gain they try: the file is read
// and parsed once (DiagramSource::load).
struct PdTuning {
  std::shared_ptr<const DiagramSource> diagram;  // the loop's diagram, read and parsed once
  // The signal the closed loop is driven at (e.g. the position command q_d).
  std::string from, to;                 // where it is measured: the closed loop from -> to (e.g. q_d -> q)
  // The proportional gain's parameter; its value in the diagram starts the search.
  std::string p_param, d_param;         // the derivative gain's: the PD gains are diagram parameters
  blocks::ParameterMap fixed;           // other overrides
  double gain_margin_db = 6.0;          // D = D_critical * 10^(-gain_margin_db/20)
  double max_overshoot_pct = 0.5;       // "does not overshoot", to this tolerance
};

// The gains a tuning chose and the closed loop they give.
struct PdTuningResult {
  // The derivative gain at which the loop with P = 0 loses stability (a root at the
  // origin, the plant's integrator left alone by a pure D loop, set aside).
  double d_critical = 0.0;
  // The chosen derivative gain: d_critical backed off by the gain margin (tune_pd), or
  // the smallest that keeps the overshoot bound (tune_critical).
  double d = 0.0, p = 0.0;  // the chosen proportional gain
  ClosedLoopFigures figures;  // of the closed loop at the chosen p and d
  int evaluations = 0;        // diagram evaluations (each a linearisation) the search took
};

// Controllers 1 and 2 of the paper. Each search starts at the parameter's value in the
// diagram (1 when it is not > 0), brackets the limit by factors of 4 for at most 70 steps
// either way (about 1e-42 .. 1e42 times the start), then bisects it geometrically.
// InputError when p_param or d_param is not a parameter of the diagram, when no stability
// limit of D or no P within the overshoot bound is found in that range, or as
// closed_loop_figures(); DiagramError when the diagram does not evaluate at some gains.
PdTuningResult tune_pd(const PdTuning& spec);

// What tune_critical needs: as PdTuning, with a target natural frequency instead of a
// gain margin.
struct CriticalTuning {
  std::shared_ptr<const DiagramSource> diagram;  // the loop's diagram, read and parsed once
  // The signal the closed loop is driven at (e.g. the position command q_d).
  std::string from, to;  // the signal it is measured at (e.g. q)
  // The proportional gain's parameter; its value in the diagram starts the search.
  std::string p_param, d_param;  // the derivative gain's parameter, likewise
  blocks::ParameterMap fixed;    // other parameter overrides, kept throughout
  double natural_frequency_rad_s = 0.0;  // the target, e.g. controller 1's
  double max_overshoot_pct = 0.5;        // the overshoot bound of critical damping, percent
};

// Controller 3: for each P the smallest D that keeps the overshoot within the bound
// (critical damping), and P such that the closed-loop natural frequency is the target.
// The searches as tune_pd's. InputError when the target is not > 0, when no D meets the
// overshoot bound at some P, or when the target is not reached in the range.
PdTuningResult tune_critical(const CriticalTuning& spec);

}  // namespace dmbd::diagrams
