#pragma once
// `dmbd tune DIAGRAM --from R --to Y --p P --d D`: PD gains of a position loop by the
// paper's procedure (Sec. III-C), or critical damping at a natural frequency
// (diagrams/tune.hpp).
#include <string>
#include <vector>

#include "command.hpp"

namespace dmbd::apps {

class TuneCommand : public Command {
 public:
  explicit TuneCommand(CLI::App& app);
  int run() override;

 private:
  std::string diagram_, from_, to_, p_, d_, gain_margin_db_ = "6", overshoot_ = "0.5", wn_hz_;
  std::vector<std::string> params_;
  bool json_ = false;
};

}  // namespace dmbd::apps
