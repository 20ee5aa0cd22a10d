#pragma once
// Software in the loop: a scenario controller run as its generated
// code instead of by the interpreter: the header codegen emits for its loop program
// (emit_header in double or float, emit_fixed_header in fixed point), a shim of
// extern "C" functions around the generated class (the program's Controller), compiled by
// the system compiler into a shared object and loaded (shared_object.hpp). At each tick the simulation calls its
// step_real() where it would call the interpreter: the same double inputs, converted
// as the interpreter converts them (float: cast; fixed point: the runtime's quantiser),
// the same double outputs. No allocation in a step.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dmbd/sim/shared_object.hpp"

#include "dmbd/sim/controller.hpp"

namespace dmbd::sim {

// What a generated controller is made of.
struct GeneratedSource {
  std::shared_ptr<const codegen::LoopProgram> program;  // the loop program
  Scalar scalar = Scalar::Double;                       // its arithmetic
  std::shared_ptr<const codegen::FixedProgram> fixed;  // fixed point: the program's fixed form
  std::string origin;                                  // the diagram file, for the header's comment
};

// The shared object's source: NAME.hpp (the generated header, as `dmbd codegen` writes
// it) and sil_NAME.cpp (the shim). InputError when the program cannot be emitted.
SharedObjectSource sil_source(const GeneratedSource& g);

// A loop program run as its generated code, compiled and loaded (a sim::Controller).
class GeneratedController : public Controller {
 public:
  // `b` must hold an object built from sil_source(g).
  GeneratedController(GeneratedSource g, SharedObjectBuild b);
  ~GeneratedController() override;
  GeneratedController(const GeneratedController&) = delete;
  GeneratedController& operator=(const GeneratedController&) = delete;

  double rate_hz() const override;
  int num_inputs() const override;
  int num_outputs() const override;
  std::string input_name(int k) const override;
  std::string output_name(int k) const override;
  std::string output_unit(int k) const override;
  void step(const double* u, double* y) override;
  // The generated code does not count the saturation blocks that engage.
  bool counts_clamp_events() const override { return false; }

  // Fixed point: the words the generated code saturated since it was made (its
  // saturations()); none in double or float.
  std::optional<unsigned long long> saturations() const;
  // What it was generated from.
  const GeneratedSource& source() const { return source_; }
  // The shared object it runs, and its compiler.
  const SharedObjectBuild& build() const { return build_; }

 private:
  GeneratedSource source_;
  SharedObjectBuild build_;
  void* instance_ = nullptr;
  void (*destroy_)(void*) = nullptr;
  void (*step_)(void*, const double*, double*) = nullptr;
  unsigned long long (*saturations_)(const void*) = nullptr;
};

// The generated controller of a source, built now unless it was (several sources are
// built at once by build_shared_objects(sil_source(...) ...) beforehand). InputError
// "the generated code does not compile (c++): FIRST ERROR LINE (full log: PATH)".
std::shared_ptr<GeneratedController> generated_controller(const GeneratedSource& g);

}  // namespace dmbd::sim
