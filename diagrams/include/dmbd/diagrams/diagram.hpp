#pragma once
// Block diagrams: the YAML authoring format (docs/diagram-format.md), validation,
// and the evaluated, immutable diagram that analysis and code generation read.
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "dmbd/base/location.hpp"
#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/blocks/expression.hpp"
#include "dmbd/blocks/state_space.hpp"

namespace dmbd::diagrams {

// A place in a diagram file and a problem there (dmbd/base/location.hpp).
using Location = dmbd::Location;
// One problem at a Location: what DiagramError collects (dmbd/base/location.hpp).
using Diagnostic = dmbd::Diagnostic;

// Every problem found while loading a diagram; what() is one line per problem.
class DiagramError : public InputError {
 public:
  // what() joins the diagnostics' "file:line:column: error: message", one per line.
  explicit DiagramError(std::vector<Diagnostic> diagnostics);
  // Every problem with its location, in the order found.
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

// A diagram input or output as declared under `inputs:` / `outputs:`.
struct SignalSpec {
  // The signal's name: an identifier, the key under `inputs:` or `outputs:`.
  std::string name, unit;  // free text (e.g. "m", "N*m"); empty when not given
  // [lo, hi] with lo < hi, in `unit`, if given: the values the signal takes (code
  // generation scales fixed-point arithmetic by the inputs' ranges).
  std::optional<std::pair<double, double>> range;
  int size = 1;    // width: the number of scalar entries (1..1000)
  Location where;  // the name's place in the file
};

// A block's `type:` in the file (docs/diagram-format.md, "Blocks"); to_string gives
// the word.
enum class BlockType { Gain, Sum, Tf, Ss, Pd, Pid, Lowpass, Delay, Saturation, Integrator, Subsystem };
// The type's word in the file: "gain", "sum", "tf", "ss", "pd", "pid", "lowpass", "delay",
// "saturation", "integrator", "subsystem".
const char* to_string(BlockType t);

// One input or output port of a block.
struct Port {
  // "in", "out", "in1".."inN" for a sum, or a subsystem diagram's own input/output names.
  std::string name;
  int size = 1;  // width: the number of scalar entries
};

class Diagram;

// What a pid block's integrator does while its output is limited
// (docs/diagram-format.md, "The pid block").
enum class AntiWindup {
  None,             // the integrator runs on (winds up)
  Clamp,            // the integral term is held within the output limits
  BackCalculation,  // the integrator is driven by Kt (u_limited - u) as well
};
// "none", "clamp", "back_calculation".
const char* to_string(AntiWindup a);

// A pid block's law term by term, as written: P + I/s + D s/(tau s + 1), then its
// output limits. A term absent from the block, or written as a literal 0, is absent
// here (has_i, has_d false) and carries no state; one given by a parameter keeps its
// state at any value. Code generation realises a pid with output limits from this
// (codegen/src/pid_lowering.cpp); linear analysis uses the unsaturated law.
struct PidLaw {
  double p = 0.0;     // proportional gain
  double i = 0.0;     // integral gain (1/s), when has_i
  double d = 0.0;     // derivative gain (s), when has_d
  double tau = 0.0;   // derivative filter time constant (s, > 0 when has_d)
  bool has_i = false;  // the block has an integral term (and its state)
  bool has_d = false;  // the block has a derivative term (and its filter's state)
  // `output_limits: [lo, hi]` (lo < hi), if given: the output is clamped there.
  std::optional<std::pair<double, double>> output_limits;
  AntiWindup anti_windup = AntiWindup::None;  // `anti_windup` (needs output_limits and I)
  double kt = 0.0;  // `Kt` (1/s, > 0): the back-calculation gain
};

// One block of a diagram, evaluated at the diagram's parameter values. Which of the
// type-specific fields below are set depends on `type`.
struct Block {
  std::string name;                  // unique within its diagram; `name.port` in connections
  BlockType type = BlockType::Gain;  // its `type:`, which decides the fields below
  Location where;                    // the name's place in the file
  // The block's fields as written (scalars as text, lists in YAML flow style), in file
  // order: for drawings and for comments in generated code.
  std::vector<std::pair<std::string, std::string>> fields;
  // The input ports in order (their widths stack in the columns of `model`'s B and D).
  std::vector<Port> inputs, outputs;  // the output ports in order (rows of C and D)
  // The block's linear model, inputs and outputs stacked in port order: continuous
  // (a delay as its Padé approximant) or discrete at the diagram's sample time. Empty
  // for a subsystem.
  blocks::StateSpace model;
  // The SISO transfer function where the block is one (tf, pd, pid, lowpass,
  // integrator; a delay's Padé approximant, or z^-n when discrete; also a 1 x 1 gain, a
  // SISO ss and a saturation, as 1), at the diagram's sample time; code generation
  // realises it.
  std::optional<blocks::TransferFunction> tf;
  blocks::Matrix gain;             // gain: k, outputs x inputs
  std::vector<double> signs;       // sum: +1 or -1 per input port
  double delay_s = 0.0;            // delay: seconds (when discrete, delay_samples * ts)
  int delay_samples = 0;           // delay: whole samples of a discrete diagram (0 when continuous)
  // saturation: the lower bound of the output (lower < upper; identity in linear analysis).
  double lower = 0.0, upper = 0.0; // saturation: the upper bound
  // subsystem: the diagram of its `file`, evaluated at the block's `parameters`.
  std::shared_ptr<const Diagram> subsystem;
  // subsystem: a continuous diagram inside a discrete one is a sampled plant: one
  // atomic block whose `model` is its exact sampled-data model at the diagram's sample
  // time (zero-order hold at its inputs, sampled outputs; blocks::c2d_zoh_delayed), its
  // delay blocks at the inputs and outputs kept exact (docs/diagram-format.md).
  bool sampled = false;
  // A sampled plant's dead time per input (s) and whole-period delay per output.
  std::vector<double> input_delays_s;
  std::vector<int> output_delay_samples;  // per output of a sampled plant
  // pid: its law term by term, with its output limits and anti-windup.
  std::optional<PidLaw> pid;
  // The block's own discretisation for code generation (field `discretization`), if any.
  std::optional<blocks::C2dMethod> method;
  // Direct feedthrough from input port k to any output (algebraic-loop check).
  std::vector<bool> feedthrough;
};

// Where a value comes from: a diagram input (block == -1) or a block output port.
struct Source {
  int block = -1;  // index into Diagram::blocks(), or -1 for a diagram input
  int port = 0;    // index into that block's outputs, or into Diagram::inputs()
  // The same block (or diagram input) and port.
  bool operator==(const Source& o) const { return block == o.block && port == o.port; }
};

// A loaded, evaluated and validated block diagram: immutable, shared (std::shared_ptr)
// with the subsystem blocks that use it. Continuous when ts() == 0, else every block is
// discrete at ts(). Indices of blocks, inputs and outputs are in file order.
class Diagram {
 public:
  // Load, evaluate and validate a diagram file. `overrides` replace parameter values
  // (every name must be a parameter of the diagram). Throws DiagramError listing every
  // problem found. To evaluate one file at many parameter values, load a DiagramSource
  // (diagram_source.hpp) once instead.
  static std::shared_ptr<const Diagram> load(const std::string& path, const blocks::ParameterMap& overrides = {});
  // The same from YAML text; `path` names it in messages and resolves subsystem files.
  static std::shared_ptr<const Diagram> parse(const std::string& yaml, const std::string& path,
                                              const blocks::ParameterMap& overrides = {});

  // The `name` key: an identifier, also the name of generated code.
  const std::string& name() const { return name_; }
  // The `description` key; empty when not given.
  const std::string& description() const { return description_; }
  // The path the diagram was loaded from, as given (or the `path` of parse()).
  const std::string& file() const { return file_; }
  // The `sample_time` key in seconds; 0 (the default) for a continuous diagram.
  double ts() const { return ts_; }
  // ts() > 0: every block is discrete at ts() (tf expressions in z, ss matrices taken as
  // discrete, delays in whole samples, pd/pid/lowpass discretised by discretization(),
  // Tustin when not given).
  bool is_discrete() const { return ts_ > 0.0; }
  // `analysis: {pade_order}` (0..10, default 3): the order of the Padé approximants of
  // this file's continuous delay blocks (a block's own `pade_order` overrides it).
  int pade_order() const { return pade_order_; }
  // The diagram's own `discretization` key, if given: how its continuous blocks are
  // discretised (a discrete diagram's pd/pid/lowpass; the default of code generation).
  const std::optional<blocks::C2dMethod>& discretization() const { return discretization_; }
  // Parameter values after overrides, and the names in definition order.
  const blocks::ParameterMap& parameters() const { return parameters_; }
  const std::vector<std::string>& parameter_order() const { return parameter_order_; }  // file order
  // The diagram inputs in file order (Source{-1, j} is input j).
  const std::vector<SignalSpec>& inputs() const { return inputs_; }
  // The diagram outputs in file order (output_driver(j) drives output j).
  const std::vector<SignalSpec>& outputs() const { return outputs_; }
  // The blocks in file order, subsystem blocks included (not flattened: see FlatDiagram).
  const std::vector<Block>& blocks() const { return blocks_; }
  // drivers(b)[k]: what drives input port k of block b (b is not checked).
  const std::vector<Source>& drivers(int block) const { return drivers_[static_cast<size_t>(block)]; }
  // output_driver(j): what drives diagram output j (j is not checked).
  const Source& output_driver(int output) const { return output_drivers_[static_cast<size_t>(output)]; }

  int find_block(const std::string& name) const;   // index into blocks(), -1 if none
  int find_input(const std::string& name) const;   // index into inputs(), -1 if none
  int find_output(const std::string& name) const;  // index into outputs(), -1 if none

 private:
  friend class Loader;
  // A copy with the given delay blocks made wires (diagrams/src/sampled_plant.cpp).
  friend std::shared_ptr<const Diagram> with_wires(const Diagram& d, const std::vector<int>& delay_blocks);
  std::string name_, description_, file_;
  double ts_ = 0.0;
  int pade_order_ = 3;
  std::optional<blocks::C2dMethod> discretization_;
  blocks::ParameterMap parameters_;
  std::vector<std::string> parameter_order_;
  std::vector<SignalSpec> inputs_, outputs_;
  std::vector<Block> blocks_;
  std::vector<std::vector<Source>> drivers_;
  std::vector<Source> output_drivers_;
};

}  // namespace dmbd::diagrams
