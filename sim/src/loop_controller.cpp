// A loop program as a sim::Controller: codegen's interpreters behind the interface.
#include <variant>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/sim/controller.hpp"

namespace dmbd::sim {

namespace {

class LoopProgramController : public Controller {
 public:
  using Run = std::variant<codegen::Interpreter<double>, codegen::Interpreter<float>, codegen::FixedInterpreter>;
  LoopProgramController(std::shared_ptr<const codegen::LoopProgram> p, std::shared_ptr<const codegen::FixedProgram> fixed, Run run)
      : program_(std::move(p)), fixed_(std::move(fixed)), run_(std::move(run)), uf_(program_->inputs.size()), yf_(program_->outputs.size()) {}

  double rate_hz() const override { return program_->rate_hz; }
  int num_inputs() const override { return static_cast<int>(program_->inputs.size()); }
  int num_outputs() const override { return static_cast<int>(program_->outputs.size()); }
  std::string input_name(int k) const override { return slot(program_->inputs, k).name; }
  std::string output_name(int k) const override { return slot(program_->outputs, k).name; }
  std::string output_unit(int k) const override { return slot(program_->outputs, k).unit; }
  unsigned long long clamp_events() const override {
    return std::visit([](const auto& r) { return r.clamp_events(); }, run_);
  }

  void step(const double* u, double* y) override {
    if (auto* d = std::get_if<codegen::Interpreter<double>>(&run_)) {
      d->step(u, y);
    } else if (auto* f = std::get_if<codegen::Interpreter<float>>(&run_)) {
      for (std::size_t k = 0; k < uf_.size(); ++k) uf_[k] = static_cast<float>(u[k]);
      f->step(uf_.data(), yf_.data());
      for (std::size_t k = 0; k < yf_.size(); ++k) y[k] = static_cast<double>(yf_[k]);
    } else {
      std::get<codegen::FixedInterpreter>(run_).step_real(u, y);
    }
  }

 private:
  const codegen::Slot& slot(const std::vector<int>& ports, int k) const {
    return program_->slots[static_cast<std::size_t>(ports[static_cast<std::size_t>(k)])];
  }
  std::shared_ptr<const codegen::LoopProgram> program_;
  std::shared_ptr<const codegen::FixedProgram> fixed_;  // the interpreters refer to both
  Run run_;
  std::vector<float> uf_, yf_;
};

}  // namespace

std::unique_ptr<Controller> loop_program_controller(std::shared_ptr<const codegen::LoopProgram> program, Scalar scalar,
                                                    std::shared_ptr<const codegen::FixedProgram> fixed) {
  const codegen::LoopProgram& p = *program;
  switch (scalar) {
    case Scalar::Float:
      return std::make_unique<LoopProgramController>(program, nullptr, codegen::Interpreter<float>(p));
    case Scalar::Fixed:
      if (!fixed) throw InputError("fixed point without a fixed-point program of '" + p.name + "'");
      return std::make_unique<LoopProgramController>(program, fixed, codegen::FixedInterpreter(p, *fixed));
    default:
      return std::make_unique<LoopProgramController>(program, nullptr, codegen::Interpreter<double>(p));
  }
}

}  // namespace dmbd::sim
