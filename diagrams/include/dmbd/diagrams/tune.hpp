#pragma once
// Gain tuning of position loops by the paper's procedure (Sec. III-C): raise the
// derivative gain until stability is about to be lost, then take the highest
// proportional gain whose step response does not overshoot; for a loop with an inner
// force loop, make the closed loop critically damped at a given natural frequency.
#include <string>
#include <vector>

#include "dmbd/diagrams/diagram_source.hpp"

namespace dmbd::diagrams {

struct ClosedLoopFigures {
  bool stable = false;
  double overshoot_pct = 0.0;           // step, refined peak (0 when unstable: see stable)
  double natural_frequency_rad_s = 0.0; // see closed_loop_figures()
  double rise_time_s = 0.0;
};

// Figures of the closed loop from `from` to `to` of an evaluated diagram. The natural
// frequency is the geometric mean of the magnitudes of the two slowest poles, leaving
// out poles that a zero within 2 % cancels (for a second-order loop it is w_n).
ClosedLoopFigures closed_loop_figures(const Diagram& diagram, const std::string& from, const std::string& to);

// The tunings evaluate their diagram's source at every gain they try: the file is read
// and parsed once (DiagramSource::load).
struct PdTuning {
  std::shared_ptr<const DiagramSource> diagram;
  std::string from, to;                 // the closed loop (e.g. q_d -> q)
  std::string p_param, d_param;         // the PD gains (diagram parameters)
  blocks::ParameterMap fixed;           // other overrides
  double gain_margin_db = 6.0;          // D = D_critical * 10^(-gain_margin_db/20)
  double max_overshoot_pct = 0.5;       // "does not overshoot", to this tolerance
};

struct PdTuningResult {
  // The derivative gain at which the loop with P = 0 loses stability (a root at the
  // origin, the plant's integrator left alone by a pure D loop, set aside).
  double d_critical = 0.0;
  double d = 0.0, p = 0.0;  // the chosen gains
  ClosedLoopFigures figures;
  int evaluations = 0;
};

// Controllers 1 and 2 of the paper. InputError when no stable gain exists in a search
// range of 1e-9 .. 1e12 times the diagram's own values.
PdTuningResult tune_pd(const PdTuning& spec);

struct CriticalTuning {
  std::shared_ptr<const DiagramSource> diagram;
  std::string from, to;
  std::string p_param, d_param;
  blocks::ParameterMap fixed;
  double natural_frequency_rad_s = 0.0;  // the target, e.g. controller 1's
  double max_overshoot_pct = 0.5;
};

// Controller 3: for each P the smallest D that keeps the overshoot within the bound
// (critical damping), and P such that the closed-loop natural frequency is the target.
PdTuningResult tune_critical(const CriticalTuning& spec);

}  // namespace dmbd::diagrams
