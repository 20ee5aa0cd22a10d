#pragma once
// A discrete controller on the simulation's bus: what the co-simulation asks of it. A
// controller states its own sample rate (the one place the rate lives; it ticks at
// t_k = k / rate), names its input and output ports, and steps without allocating. The
// bus binds its ports to signals and adds the computation delay (ControllerSpec in
// simulation.hpp). Loop programs (the generated code's arithmetic, run by codegen's
// interpreters, or the generated code itself compiled and loaded: software in the
// loop) are one implementation; a whole-body controller is another kind.
#include <memory>
#include <string>

#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/loop_program.hpp"

namespace dmbd::sim {

class Controller {
 public:
  virtual ~Controller() = default;
  virtual double rate_hz() const = 0;
  virtual int num_inputs() const = 0;
  virtual int num_outputs() const = 0;
  virtual std::string input_name(int k) const = 0;
  virtual std::string output_name(int k) const = 0;
  virtual std::string output_unit(int k) const = 0;   // the unit of the bus signal it drives
  // One sample: reads u[0 .. num_inputs), writes y[0 .. num_outputs). No allocation.
  virtual void step(const double* u, double* y) = 0;
  // Saturations engaged so far (0 for a controller without any).
  virtual unsigned long long clamp_events() const { return 0; }
  // Whether clamp_events() counts them: false for one that cannot tell (a loop program
  // run as its compiled generated code, which does not count; its clamp_events() is 0).
  virtual bool counts_clamp_events() const { return true; }
};

enum class Scalar { Double, Float, Fixed };

// A loop program run by its interpreter in double, float or fixed point (then `fixed`
// is the program's fixed-point form); its rate is the rate it was lowered at. Throws
// InputError for fixed point without a fixed-point program.
std::unique_ptr<Controller> loop_program_controller(std::shared_ptr<const codegen::LoopProgram> program, Scalar scalar,
                                                    std::shared_ptr<const codegen::FixedProgram> fixed = nullptr);

}  // namespace dmbd::sim
