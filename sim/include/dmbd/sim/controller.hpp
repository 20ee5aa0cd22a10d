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

// The interface the co-simulation steps (Simulation, through a ControllerSpec): scalar
// inputs in, scalar outputs out, once per tick. Implementations: loop_program_controller
// below, a loop program's generated code (the scenario's `implementation: generated`),
// OscController and BalanceController.
class Controller {
 public:
  virtual ~Controller() = default;
  // Ticks per second (Hz): it steps at t_k = k / rate_hz from t = 0. The period must be a
  // whole number of nanoseconds (the Simulation throws InputError otherwise).
  virtual double rate_hz() const = 0;
  // How many values step() reads from u; a ControllerSpec binds exactly this many.
  virtual int num_inputs() const = 0;
  // How many values step() writes to y; a ControllerSpec binds exactly this many.
  virtual int num_outputs() const = 0;
  // Input port k (0 <= k < num_inputs()) by name, for messages: a loop program's slot,
  // "in_" + the diagram input (in_q_m for q_m; in_x_0, in_x_1 for a vector x).
  virtual std::string input_name(int k) const = 0;
  // Output port k by name: a loop program's slot, "out_" + the diagram output. An output
  // left unbound is published on the bus as "<controller name>.<output_name(k)>".
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

// The arithmetic a loop program runs in (a scenario controller's `scalar`): double, float
// (inputs rounded to float, outputs widened back) or fixed point (the program's
// fixed-point form, codegen::FixedProgram, with its word size).
enum class Scalar { Double, Float, Fixed };

// A loop program run by its interpreter in double, float or fixed point (then `fixed`
// is the program's fixed-point form); its rate is the rate it was lowered at. Throws
// InputError for fixed point without a fixed-point program.
std::unique_ptr<Controller> loop_program_controller(std::shared_ptr<const codegen::LoopProgram> program, Scalar scalar,
                                                    std::shared_ptr<const codegen::FixedProgram> fixed = nullptr);

}  // namespace dmbd::sim
