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
using Diagnostic = dmbd::Diagnostic;

// Every problem found while loading a diagram; what() is one line per problem.
class DiagramError : public InputError {
 public:
  explicit DiagramError(std::vector<Diagnostic> diagnostics);
  const std::vector<Diagnostic>& diagnostics() const { return diagnostics_; }

 private:
  std::vector<Diagnostic> diagnostics_;
};

struct SignalSpec {
  std::string name, unit;
  std::optional<std::pair<double, double>> range;
  int size = 1;
  Location where;
};

enum class BlockType { Gain, Sum, Tf, Ss, Pd, Pid, Lowpass, Delay, Saturation, Integrator, Subsystem };
const char* to_string(BlockType t);

struct Port {
  std::string name;
  int size = 1;
};

class Diagram;

struct Block {
  std::string name;
  BlockType type = BlockType::Gain;
  Location where;
  // The block's fields as written (scalars as text, lists in YAML flow style), in file
  // order: for drawings and for comments in generated code.
  std::vector<std::pair<std::string, std::string>> fields;
  std::vector<Port> inputs, outputs;
  // The block's linear model, inputs and outputs stacked in port order: continuous
  // (a delay as its Padé approximant) or discrete at the diagram's sample time. Empty
  // for a subsystem.
  blocks::StateSpace model;
  // The SISO transfer function where the block is one (tf, pd, pid, lowpass,
  // integrator; a delay's Padé approximant); code generation realises it.
  std::optional<blocks::TransferFunction> tf;
  blocks::Matrix gain;             // gain
  std::vector<double> signs;       // sum
  double delay_s = 0.0;            // delay (continuous)
  int delay_samples = 0;           // delay (discrete)
  double lower = 0.0, upper = 0.0; // saturation
  std::shared_ptr<const Diagram> subsystem;
  // The block's own discretisation for code generation (field `discretization`), if any.
  std::optional<blocks::C2dMethod> method;
  // Direct feedthrough from input port k to any output (algebraic-loop check).
  std::vector<bool> feedthrough;
};

// Where a value comes from: a diagram input (block == -1) or a block output port.
struct Source {
  int block = -1;
  int port = 0;
  bool operator==(const Source& o) const { return block == o.block && port == o.port; }
};

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

  const std::string& name() const { return name_; }
  const std::string& description() const { return description_; }
  const std::string& file() const { return file_; }
  double ts() const { return ts_; }
  bool is_discrete() const { return ts_ > 0.0; }
  int pade_order() const { return pade_order_; }
  // The diagram's own `discretization` key, if given: how its continuous blocks are
  // discretised (a discrete diagram's pd/pid/lowpass; the default of code generation).
  const std::optional<blocks::C2dMethod>& discretization() const { return discretization_; }
  // Parameter values after overrides, and the names in definition order.
  const blocks::ParameterMap& parameters() const { return parameters_; }
  const std::vector<std::string>& parameter_order() const { return parameter_order_; }
  const std::vector<SignalSpec>& inputs() const { return inputs_; }
  const std::vector<SignalSpec>& outputs() const { return outputs_; }
  const std::vector<Block>& blocks() const { return blocks_; }
  // driver(b)[k]: what drives input port k of block b; output_driver(j): diagram output j.
  const std::vector<Source>& drivers(int block) const { return drivers_[static_cast<size_t>(block)]; }
  const Source& output_driver(int output) const { return output_drivers_[static_cast<size_t>(output)]; }

  int find_block(const std::string& name) const;   // -1 if none
  int find_input(const std::string& name) const;   // -1 if none
  int find_output(const std::string& name) const;  // -1 if none

 private:
  friend class Loader;
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
