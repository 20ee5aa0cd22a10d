#pragma once
// `dmbd analyze`: a transfer function (--tf EXPR) or the transfer between two signals of
// a diagram (--from/--to, or the loop at a break point with --loop-at): poles, zeros,
// DC gain, margins, bandwidth, Bode, step response, discretisation, a parameter sweep.
// The figures themselves are computed in analyze.cpp.
#include <string>
#include <vector>

#include "command.hpp"

namespace dmbd::apps {

class AnalyzeCommand : public Command {
 public:
  explicit AnalyzeCommand(CLI::App& app);
  int run() override;

  struct Args {
    std::string diagram, from, to, loop_at, sweep;
    std::string tf;
    bool tf_given = false;
    std::vector<std::string> params;
    bool json = false;
    std::string freq, freq_range, step, c2d, ts, prewarp, bode, step_plot;
    std::string pade, minreal;  // --pade N (a delay's Padé order), --minreal TOL
  };

 private:
  Args a_;
};

}  // namespace dmbd::apps
