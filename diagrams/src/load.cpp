// Loading, evaluating and validating a diagram (docs/diagram-format.md).
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <set>
#include <unordered_map>

#include "dmbd/base/yaml_reader.hpp"
#include "dmbd/blocks/delay.hpp"
#include "dmbd/blocks/discretize.hpp"
#include "dmbd/blocks/elements.hpp"
#include "dmbd/blocks/expression_numbers.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "parsed_diagram.hpp"
#include "sampled_plant.hpp"

namespace dmbd::diagrams {

namespace b = dmbd::blocks;
namespace fs = std::filesystem;

namespace {
std::string join(const std::vector<Diagnostic>& d) {
  std::string s;
  for (size_t i = 0; i < d.size(); ++i) s += (i ? "\n" : "") + d[i].str();
  return s;
}
}  // namespace

DiagramError::DiagramError(std::vector<Diagnostic> diagnostics)
    : InputError(join(diagnostics)), diagnostics_(std::move(diagnostics)) {}

const char* to_string(AntiWindup a) {
  switch (a) {
    case AntiWindup::None: return "none";
    case AntiWindup::Clamp: return "clamp";
    case AntiWindup::BackCalculation: return "back_calculation";
  }
  return "none";
}

const char* to_string(BlockType t) {
  switch (t) {
    case BlockType::Gain: return "gain";
    case BlockType::Sum: return "sum";
    case BlockType::Tf: return "tf";
    case BlockType::Ss: return "ss";
    case BlockType::Pd: return "pd";
    case BlockType::Pid: return "pid";
    case BlockType::Lowpass: return "lowpass";
    case BlockType::Delay: return "delay";
    case BlockType::Saturation: return "saturation";
    case BlockType::Integrator: return "integrator";
    case BlockType::Subsystem: return "subsystem";
  }
  return "?";
}

int Diagram::find_block(const std::string& n) const {
  for (size_t i = 0; i < blocks_.size(); ++i)
    if (blocks_[i].name == n) return static_cast<int>(i);
  return -1;
}
int Diagram::find_input(const std::string& n) const {
  for (size_t i = 0; i < inputs_.size(); ++i)
    if (inputs_[i].name == n) return static_cast<int>(i);
  return -1;
}
int Diagram::find_output(const std::string& n) const {
  for (size_t i = 0; i < outputs_.size(); ++i)
    if (outputs_[i].name == n) return static_cast<int>(i);
  return -1;
}

// A delay of n samples is a dense n x n state-space model, a sum of k inputs of size m
// an m x km gain: bounded so that a short file cannot ask for gigabytes.
constexpr int kMaxDelaySamples = 1000;
constexpr int kMaxSumEntries = 10000000;

// Builds one Diagram from a parsed file, collecting every problem before throwing.
class Loader {
 public:
  Loader(const ParsedDiagram& parsed, std::vector<std::string> chain)
      : parsed_(parsed), path_(parsed.path), chain_(std::move(chain)),
        rd_(parsed.path, [this](const std::string& text) { return evaluate_number(text); }) {}

  std::shared_ptr<const Diagram> run(const b::ParameterMap& overrides, const std::map<std::string, Location>& override_where) {
    auto d = std::make_shared<Diagram>();
    d_ = d.get();
    d_->file_ = path_;
    const YAML::Node& root = parsed_.root;
    if (!root.IsMap()) {
      error(Location{path_, 1, 1}, "expected a map with the keys name, parameters, inputs, outputs, blocks, connections");
      throw DiagramError(rd_.diagnostics());
    }
    check_keys(root, {"name", "description", "sample_time", "discretization", "parameters", "analysis", "inputs",
                      "outputs", "blocks", "connections"},
               "top-level key");
    // name
    if (const YAML::Node n = root["name"]; !n) {
      error(Location{path_, 1, 1}, "missing 'name'");
    } else if (!n.IsScalar() || !is_identifier(n.Scalar())) {
      error(n, "'name' must be an identifier (letters, digits, _)");
    } else {
      d_->name_ = n.Scalar();
    }
    if (const YAML::Node n = root["description"]; n && n.IsScalar()) d_->description_ = n.Scalar();
    parameters(root["parameters"], overrides, override_where);
    if (const YAML::Node n = root["sample_time"]) {
      const double ts = number(n, "sample_time");
      if (std::isfinite(ts) && !(ts >= 0.0)) error(n, "'sample_time' must be >= 0 seconds");
      if (std::isfinite(ts) && ts >= 0.0) d_->ts_ = ts;
    }
    if (const YAML::Node n = root["discretization"]) {
      try {
        method_ = b::parse_c2d_method(n.Scalar());
        d_->discretization_ = method_;
      } catch (const InputError& e) {
        error(n, e.what());
      }
    }
    if (const YAML::Node n = root["analysis"]) {
      if (!n.IsMap()) {
        error(n, "'analysis' must be a map, e.g. {pade_order: 3}");
      } else {
        check_keys(n, {"pade_order"}, "analysis key");
        if (n["pade_order"]) d_->pade_order_ = integer(n["pade_order"], "pade_order", 0, 10, 3);
      }
    }
    signals(root["inputs"], "inputs", d_->inputs_);
    signals(root["outputs"], "outputs", d_->outputs_);
    blocks(root["blocks"]);
    connections(root["connections"]);
    if (!rd_.failed()) algebraic_loops();
    if (rd_.failed()) throw DiagramError(rd_.diagnostics());
    return d;
  }

 private:
  // ---- diagnostics -------------------------------------------------------------
  Location where(const YAML::Node& n, int offset = 0) const { return rd_.at(n, offset); }
  void error(const Location& at, const std::string& msg) { rd_.error(at, msg); }
  void error(const YAML::Node& n, const std::string& msg) { error(where(n), msg); }

  static bool is_identifier(const std::string& s) {
    if (s.empty() || std::isdigit(static_cast<unsigned char>(s[0]))) return false;
    return std::all_of(s.begin(), s.end(), [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; });
  }

  // Keys of a map must be among `allowed`; reports the others at their own location.
  void check_keys(const YAML::Node& map, const std::vector<std::string>& allowed, const std::string& what) {
    rd_.guard([&] { rd_.keys(map, allowed, "", what); });
  }

  // ---- values ---------------------------------------------------------------------
  // The reader's numbers: constant expressions of the parameters. One that uses a
  // parameter whose own definition is wrong is not reported again (Skip).
  double evaluate_number(const std::string& text) {
    try {
      const b::Expression e = parsed_.expression(text);
      for (const std::string& p : e.parameters())
        if (broken_parameters_.count(p)) throw yaml::Skip{};
      return e.evaluate(d_->parameters_);
    } catch (const b::ExpressionError& e) {
      throw NumberError(e.column(), b::without_column(e.what()));
    }
  }

  // A number or a constant expression of the parameters; NaN (and a diagnostic) if not.
  double number(const YAML::Node& n, const std::string& what) {
    double v = NAN;
    const std::size_t before = rd_.diagnostics().size();
    if (!rd_.guard([&] { v = rd_.number(n, "'" + what + "'"); }) && rd_.diagnostics().size() == before)
      quiet_failure_ = true;
    return v;
  }

  // True (and quiet_failure_ set) when the expression uses a wrong parameter.
  bool uses_broken_parameter(const b::Expression& e) {
    for (const std::string& p : e.parameters())
      if (broken_parameters_.count(p)) quiet_failure_ = true;
    return quiet_failure_;
  }

  int integer(const YAML::Node& n, const std::string& what, int lo, int hi, int fallback) {
    const double v = number(n, what);
    if (!std::isfinite(v)) return fallback;
    if (v != std::floor(v) || v < lo || v > hi) {
      error(n, "'" + what + "' must be a whole number from " + std::to_string(lo) + " to " + std::to_string(hi));
      return fallback;
    }
    return static_cast<int>(v);
  }

  b::Matrix matrix(const YAML::Node& n, const std::string& what) {
    if (!n) return b::Matrix();
    if (n.IsScalar()) {
      b::Matrix m(1, 1);
      m(0, 0) = number(n, what);
      if (!std::isfinite(m(0, 0))) return b::Matrix();
      return m;
    }
    if (!n.IsSequence() || n.size() == 0) {
      error(n, "'" + what + "' must be a matrix: a list of rows, e.g. [[1, 0], [0, 1]]");
      return b::Matrix();
    }
    const bool rows_are_lists = n[0].IsSequence();
    const size_t rows = rows_are_lists ? n.size() : 1;
    const size_t cols = rows_are_lists ? n[0].size() : n.size();
    b::Matrix m(static_cast<Eigen::Index>(rows), static_cast<Eigen::Index>(cols));
    for (size_t i = 0; i < rows; ++i) {
      const YAML::Node row = rows_are_lists ? n[i] : n;
      if (!row.IsSequence() || row.size() != cols) {
        error(row, "'" + what + "': every row must have " + std::to_string(cols) + " entries");
        return b::Matrix();
      }
      for (size_t j = 0; j < cols; ++j)
        m(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = number(row[j], what);
    }
    if (!m.allFinite()) return b::Matrix();
    return m;
  }

  std::vector<double> coefficients(const YAML::Node& n, const std::string& what) {
    std::vector<double> c;
    if (!n.IsSequence() || n.size() == 0) {
      error(n, "'" + what + "' must be a list of coefficients, highest power first");
      return c;
    }
    for (const auto& e : n) c.push_back(number(e, what));
    return c;
  }

  // ---- parameters -------------------------------------------------------------------
  using Definitions = std::map<std::string, std::pair<b::Expression, YAML::Node>>;

  // The parameters as written, in d_->parameter_order_; a wrong one is reported and
  // its name kept in broken_parameters_ (what uses it is not reported again).
  Definitions parameter_definitions(const YAML::Node& n) {
    Definitions defs;
    if (!n) return defs;
    if (!n.IsMap()) {
      error(n, "'parameters' must be a map of name: value");
      return defs;
    }
    for (const auto& kv : n) {
      const std::string name = kv.first.Scalar();
      if (!is_identifier(name) || name == "s" || name == "z" || name == "pi" || name == "e") {
        error(kv.first, "'" + name + "' is not a usable parameter name");
        continue;
      }
      if (!kv.second.IsScalar()) {
        error(kv.second, "parameter '" + name + "' must be a number or an expression");
        broken_parameters_.insert(name);
        continue;
      }
      try {
        defs.emplace(name, std::make_pair(parsed_.expression(kv.second.Scalar()), kv.second));
        d_->parameter_order_.push_back(name);
      } catch (const b::ExpressionError& e) {
        error(where(kv.second, e.column() - 1), "parameter '" + name + "': " + b::without_column(e.what()));
        broken_parameters_.insert(name);
      }
    }
    return defs;
  }

  void parameters(const YAML::Node& n, const b::ParameterMap& overrides,
                  const std::map<std::string, Location>& override_where) {
    const Definitions defs = parameter_definitions(n);
    for (const auto& [name, value] : overrides) {
      if (!defs.count(name)) {
        auto it = override_where.find(name);
        if (!broken_parameters_.count(name))
          error(it != override_where.end() ? it->second : Location{path_, 0, 0},
                "no parameter '" + name + "' to override in '" + path_ + "'");
        continue;
      }
      d_->parameters_[name] = value;
    }
    evaluate_parameters(defs);
  }

  // Evaluates the definitions in dependency order; reports unknown names and cycles.
  void evaluate_parameters(const Definitions& defs) {
    std::map<std::string, int> state;  // 0 new, 1 in progress, 2 done
    std::vector<std::string> stack;
    std::function<bool(const std::string&)> eval = [&](const std::string& name) -> bool {
      if (d_->parameters_.count(name) && state[name] != 1) {
        state[name] = 2;
        return true;
      }
      if (state[name] == 1) {
        std::string cycle;
        auto it = std::find(stack.begin(), stack.end(), name);
        for (; it != stack.end(); ++it) cycle += *it + " -> ";
        error(defs.at(name).second, "cyclic parameter definitions: " + cycle + name);
        return false;
      }
      if (state[name] == 2) return d_->parameters_.count(name) > 0;
      state[name] = 1;
      stack.push_back(name);
      const auto& [expr, node] = defs.at(name);
      bool ok = true;
      for (const std::string& dep : expr.parameters()) {
        if (!defs.count(dep)) {  // unknown: reported by evaluate() below with its column
          if (broken_parameters_.count(dep)) ok = false;  // reported at its own definition
          continue;
        }
        if (!eval(dep)) ok = false;
      }
      stack.pop_back();
      state[name] = 2;
      if (!ok || !evaluate_parameter(name, expr, node)) {
        broken_parameters_.insert(name);
        return false;
      }
      return true;
    };
    for (const std::string& name : d_->parameter_order_) eval(name);
  }

  bool evaluate_parameter(const std::string& name, const b::Expression& expr, const YAML::Node& node) {
    try {
      const double v = expr.evaluate(d_->parameters_);
      if (!std::isfinite(v)) {
        error(node, "parameter '" + name + "' is not a finite number");
        return false;
      }
      d_->parameters_[name] = v;
      return true;
    } catch (const b::ExpressionError& e) {
      error(where(node, e.column() - 1), "parameter '" + name + "': " + b::without_column(e.what()));
      return false;
    }
  }

  // ---- inputs / outputs -----------------------------------------------------------------
  void signals(const YAML::Node& n, const std::string& what, std::vector<SignalSpec>& out) {
    if (!n) {
      error(Location{path_, 1, 1}, "missing '" + what + "'");
      return;
    }
    if (!n.IsMap()) {
      error(n, "'" + what + "' must be a map of name: {unit, range, size}");
      return;
    }
    for (const auto& kv : n) {
      SignalSpec s;
      s.name = kv.first.Scalar();
      s.where = where(kv.first);
      if (!is_identifier(s.name)) error(kv.first, "'" + s.name + "' is not a valid signal name");
      const YAML::Node v = kv.second;
      if (v && !v.IsNull()) {
        if (!v.IsMap()) {
          error(v, "signal '" + s.name + "' must be a map {unit, range, size}");
        } else {
          check_keys(v, {"unit", "range", "size", "description"}, "signal key");
          if (v["unit"]) s.unit = v["unit"].Scalar();
          if (v["size"]) s.size = integer(v["size"], "size", 1, 1000, 1);
          if (const YAML::Node r = v["range"]) {
            if (!r.IsSequence() || r.size() != 2) {
              error(r, "'range' must be [lo, hi]");
            } else {
              const double lo = number(r[0], "range"), hi = number(r[1], "range");
              if (std::isfinite(lo) && std::isfinite(hi)) {
                if (!(lo < hi)) {
                  error(r, "'range' must have lo < hi");
                } else {
                  s.range = std::make_pair(lo, hi);
                }
              }
            }
          }
        }
      }
      out.push_back(s);
    }
  }

  // ---- blocks ---------------------------------------------------------------------------
  static const std::map<std::string, std::pair<BlockType, std::vector<std::string>>>& block_fields() {
    static const std::map<std::string, std::pair<BlockType, std::vector<std::string>>> f = {
        {"gain", {BlockType::Gain, {"k"}}},
        {"sum", {BlockType::Sum, {"signs", "size"}}},
        {"tf", {BlockType::Tf, {"expr", "num", "den", "discretization"}}},
        {"ss", {BlockType::Ss, {"A", "B", "C", "D", "discretization"}}},
        {"pd", {BlockType::Pd, {"P", "D", "tau", "discretization"}}},
        {"pid", {BlockType::Pid, {"P", "I", "D", "tau", "output_limits", "anti_windup", "Kt", "discretization"}}},
        {"lowpass", {BlockType::Lowpass, {"order", "cutoff_hz", "discretization"}}},
        {"delay", {BlockType::Delay, {"seconds", "samples", "pade_order"}}},
        {"saturation", {BlockType::Saturation, {"lower", "upper"}}},
        {"integrator", {BlockType::Integrator, {"k", "discretization"}}},
        {"subsystem", {BlockType::Subsystem, {"file", "parameters"}}},
    };
    return f;
  }

  void require(const YAML::Node& blk, const std::string& field, const Block& bl) {
    if (!blk[field]) error(bl.where, "block '" + bl.name + "' (" + to_string(bl.type) + ") needs '" + field + "'");
  }

  // A SISO block from a transfer function: continuous, or discretised for a discrete diagram.
  void set_tf(Block& bl, b::TransferFunction tf, const YAML::Node& at) {
    if (!tf.is_proper()) {
      error(at, "block '" + bl.name + "': improper transfer function (numerator degree " +
                    std::to_string(tf.num().degree()) + " > denominator degree " + std::to_string(tf.den().degree()) +
                    "): it has no state-space realisation");
      return;
    }
    if (d_->is_discrete() && !tf.is_discrete()) tf = b::c2d(tf, d_->ts_, bl.method.value_or(method_));
    bl.tf = tf;
    bl.model = b::StateSpace::from_tf(tf);
  }

  void blocks(const YAML::Node& n) {
    if (!n) {
      error(Location{path_, 1, 1}, "missing 'blocks'");
      return;
    }
    if (!n.IsMap()) {
      error(n, "'blocks' must be a map of name: {type: ..., ...}");
      return;
    }
    std::set<std::string> names;
    for (const auto& s : d_->inputs_) names.insert(s.name);
    for (const auto& s : d_->outputs_) names.insert(s.name);
    for (const auto& kv : n) {
      Block bl;
      bl.name = kv.first.Scalar();
      bl.where = where(kv.first);
      if (!is_identifier(bl.name)) error(kv.first, "'" + bl.name + "' is not a valid block name");
      if (names.count(bl.name)) error(kv.first, "'" + bl.name + "' is already the name of a diagram input, output or block");
      names.insert(bl.name);
      const YAML::Node blk = kv.second;
      if (!blk.IsMap() || !blk["type"]) {
        error(blk ? where(blk) : bl.where, "block '" + bl.name + "' must be a map with a 'type'");
        broken_.insert(bl.name);
        d_->blocks_.push_back(std::move(bl));
        continue;
      }
      const std::string type = blk["type"].Scalar();
      const auto it = block_fields().find(type);
      if (it == block_fields().end()) {
        std::string list;
        for (const auto& t : block_fields()) list += (list.empty() ? "" : ", ") + t.first;
        error(blk["type"], "unknown block type '" + type + "' (expected one of: " + list + ")");
        broken_.insert(bl.name);
        d_->blocks_.push_back(std::move(bl));
        continue;
      }
      bl.type = it->second.first;
      std::vector<std::string> allowed = it->second.second;
      allowed.insert(allowed.end(), {"type", "description"});
      check_keys(blk, allowed, std::string("field of a ") + type + " block");
      for (const auto& f : blk) {
        if (f.first.Scalar() == "type") continue;
        if (f.second.IsScalar()) {
          bl.fields.emplace_back(f.first.Scalar(), f.second.Scalar());
        } else {
          YAML::Emitter em;
          em << YAML::Flow << f.second;
          bl.fields.emplace_back(f.first.Scalar(), em.c_str());
        }
      }
      if (const YAML::Node m = blk["discretization"]) {
        try {
          bl.method = b::parse_c2d_method(m.Scalar());
        } catch (const InputError& e) {
          error(m, e.what());
        }
      }
      const size_t before = rd_.diagnostics().size();
      quiet_failure_ = false;
      build(bl, blk);
      if (rd_.diagnostics().size() == before && !quiet_failure_) d_->blocks_.push_back(std::move(bl));
      else d_->blocks_.push_back(std::move(bl)), broken_.insert(d_->blocks_.back().name);
    }
  }

  void build(Block& bl, const YAML::Node& blk) {
    const double ts = d_->ts_;
    auto scalar_ports = [&] {
      bl.inputs = {{"in", 1}};
      bl.outputs = {{"out", 1}};
    };
    switch (bl.type) {
      case BlockType::Gain: {
        require(blk, "k", bl);
        if (!blk["k"]) return;
        bl.gain = matrix(blk["k"], "k");
        if (bl.gain.size() == 0) return;
        bl.inputs = {{"in", static_cast<int>(bl.gain.cols())}};
        bl.outputs = {{"out", static_cast<int>(bl.gain.rows())}};
        bl.model = b::StateSpace::gain(bl.gain, ts);
        if (bl.gain.size() == 1) bl.tf = b::TransferFunction(bl.gain(0, 0), ts);
        break;
      }
      case BlockType::Sum: {
        std::string signs = "++";
        if (blk["signs"]) signs = blk["signs"].Scalar();
        if (signs.empty() || signs.find_first_not_of("+-") != std::string::npos) {
          error(blk["signs"], "'signs' must be a string of + and -, one per input, e.g. \"+-\"");
          return;
        }
        const int size = blk["size"] ? integer(blk["size"], "size", 1, 1000, 1) : 1;
        const int k = static_cast<int>(signs.size());
        if (static_cast<double>(size) * size * k > kMaxSumEntries) {
          error(blk["signs"], "block '" + bl.name + "': " + std::to_string(k) + " inputs of size " + std::to_string(size) +
                                  " make a matrix of more than " + std::to_string(kMaxSumEntries) + " entries");
          return;
        }
        b::Matrix d = b::Matrix::Zero(size, size * k);
        for (int i = 0; i < k; ++i) {
          bl.inputs.push_back({"in" + std::to_string(i + 1), size});
          bl.signs.push_back(signs[static_cast<size_t>(i)] == '+' ? 1.0 : -1.0);
          d.block(0, i * size, size, size) = bl.signs.back() * b::Matrix::Identity(size, size);
        }
        bl.outputs = {{"out", size}};
        bl.model = b::StateSpace::gain(d, ts);
        break;
      }
      case BlockType::Tf: {
        scalar_ports();
        if (blk["expr"] && (blk["num"] || blk["den"])) {
          error(blk["expr"], "block '" + bl.name + "': give either 'expr' or 'num' and 'den', not both");
          return;
        }
        if (blk["expr"]) {
          const YAML::Node e = blk["expr"];
          try {
            const b::Expression expr = parsed_.expression(e.Scalar());
            if (uses_broken_parameter(expr)) return;
            const b::Rational r = expr.evaluate_rational(d_->parameters_, d_->is_discrete() ? 'z' : 's');
            set_tf(bl, b::TransferFunction(r.num, r.den, ts).with_factors(r.num_factors, r.den_factors), e);
          } catch (const b::ExpressionError& x) {
            error(where(e, x.column() - 1), "block '" + bl.name + "': " + b::without_column(x.what()));
          } catch (const InputError& x) {
            error(e, "block '" + bl.name + "': " + x.what());
          }
        } else if (blk["num"] && blk["den"]) {
          const auto num = coefficients(blk["num"], "num"), den = coefficients(blk["den"], "den");
          for (double c : num)
            if (!std::isfinite(c)) return;
          for (double c : den)
            if (!std::isfinite(c)) return;
          if (num.empty() || den.empty()) return;
          try {
            set_tf(bl, b::TransferFunction::from_descending(num, den, ts), blk["num"]);
          } catch (const InputError& x) {
            error(blk["den"], "block '" + bl.name + "': " + x.what());
          }
        } else {
          error(bl.where, "block '" + bl.name + "' (tf) needs 'expr', or 'num' and 'den'");
        }
        break;
      }
      case BlockType::Ss: {
        for (const char* f : {"A", "B", "C"}) require(blk, f, bl);
        if (!blk["A"] || !blk["B"] || !blk["C"]) return;
        const b::Matrix a = matrix(blk["A"], "A"), bm = matrix(blk["B"], "B"), c = matrix(blk["C"], "C");
        if (a.size() == 0 || bm.size() == 0 || c.size() == 0) return;
        b::Matrix d = blk["D"] ? matrix(blk["D"], "D") : b::Matrix::Zero(c.rows(), bm.cols());
        try {
          bl.model = b::StateSpace(a, bm, c, d, ts);
        } catch (const InputError& x) {
          error(bl.where, "block '" + bl.name + "': " + x.what());
          return;
        }
        bl.inputs = {{"in", bl.model.num_inputs()}};
        bl.outputs = {{"out", bl.model.num_outputs()}};
        if (bl.model.num_inputs() == 1 && bl.model.num_outputs() == 1) bl.tf = bl.model.to_tf();
        break;
      }
      case BlockType::Pd:
      case BlockType::Pid: {
        scalar_ports();
        pid_block(bl, blk);
        break;
      }
      case BlockType::Lowpass: {
        scalar_ports();
        require(blk, "order", bl);
        require(blk, "cutoff_hz", bl);
        if (!blk["order"] || !blk["cutoff_hz"]) return;
        const int order = integer(blk["order"], "order", 1, 20, 0);
        const double fc = number(blk["cutoff_hz"], "cutoff_hz");
        if (order == 0 || !std::isfinite(fc)) return;
        if (!(fc > 0.0)) {
          error(blk["cutoff_hz"], "'cutoff_hz' must be > 0");
          return;
        }
        if (ts > 0.0 && fc >= 0.5 / ts) {
          error(blk["cutoff_hz"], "'cutoff_hz' must be below the Nyquist frequency " + std::to_string(0.5 / ts) + " Hz");
          return;
        }
        set_tf(bl, b::butterworth_lowpass(order, 2.0 * M_PI * fc), blk);
        break;
      }
      case BlockType::Delay: {
        scalar_ports();
        if (blk["seconds"] && blk["samples"]) {
          error(blk["samples"], "block '" + bl.name + "': give either 'seconds' or 'samples'");
          return;
        }
        if (!blk["seconds"] && !blk["samples"]) {
          error(bl.where, "block '" + bl.name + "' (delay) needs 'seconds' (or 'samples' in a discrete diagram)");
          return;
        }
        const int pade = blk["pade_order"] ? integer(blk["pade_order"], "pade_order", 0, 10, 3) : d_->pade_order_;
        if (blk["samples"]) {
          if (ts == 0.0) {
            error(blk["samples"], "'samples' needs a discrete diagram (a sample_time); use 'seconds'");
            return;
          }
          bl.delay_samples = integer(blk["samples"], "samples", 0, kMaxDelaySamples, 0);
          bl.delay_s = bl.delay_samples * ts;
        } else {
          bl.delay_s = number(blk["seconds"], "seconds");
          if (!std::isfinite(bl.delay_s)) return;
          if (bl.delay_s < 0.0) {
            error(blk["seconds"], "'seconds' must be >= 0");
            return;
          }
          if (ts > 0.0) {
            const double n = bl.delay_s / ts;
            if (std::abs(n - std::round(n)) > 1e-6 * std::max(1.0, n)) {
              error(blk["seconds"], "a delay of " + std::to_string(bl.delay_s) + " s is not a whole number of samples of " +
                                        std::to_string(ts) + " s");
              return;
            }
            if (n > kMaxDelaySamples) {
              error(blk["seconds"], "a delay of " + std::to_string(bl.delay_s) + " s is more than " +
                                        std::to_string(kMaxDelaySamples) + " samples of " + std::to_string(ts) + " s");
              return;
            }
            bl.delay_samples = static_cast<int>(std::round(n));
          }
        }
        const b::TransferFunction tf = ts > 0.0 ? b::sample_delay(bl.delay_samples, ts) : b::pade(bl.delay_s, pade);
        bl.tf = tf;
        bl.model = b::StateSpace::from_tf(tf);
        // A true delay is never part of an algebraic loop; a zero delay is a wire.
        bl.feedthrough = {bl.delay_s == 0.0 && bl.delay_samples == 0};
        return;
      }
      case BlockType::Saturation: {
        scalar_ports();
        require(blk, "lower", bl);
        require(blk, "upper", bl);
        if (!blk["lower"] || !blk["upper"]) return;
        bl.lower = number(blk["lower"], "lower");
        bl.upper = number(blk["upper"], "upper");
        if (std::isfinite(bl.lower) && std::isfinite(bl.upper) && !(bl.lower < bl.upper))
          error(blk["upper"], "'upper' must be greater than 'lower'");
        bl.model = b::StateSpace::gain(b::Matrix::Identity(1, 1), ts);
        bl.tf = b::TransferFunction(1.0, ts);
        break;
      }
      case BlockType::Integrator: {
        scalar_ports();
        const double k = blk["k"] ? number(blk["k"], "k") : 1.0;
        if (!std::isfinite(k)) return;
        if (ts > 0.0) {
          // A discrete accumulator (forward Euler, no feedthrough): y[k+1] = y[k] + k ts u[k].
          set_tf(bl, b::TransferFunction(b::Polynomial::constant(k * ts), b::Polynomial({-1.0, 1.0}), ts), blk);
        } else {
          set_tf(bl, b::integrator(k), blk);
        }
        break;
      }
      case BlockType::Subsystem: {
        subsystem(bl, blk);
        return;
      }
    }
    // Direct feedthrough per input port from the model's D.
    bl.feedthrough.clear();
    int col = 0;
    for (const Port& p : bl.inputs) {
      bool ft = false;
      if (bl.model.d().size() > 0 && col + p.size <= bl.model.d().cols())
        ft = bl.model.d().middleCols(col, p.size).cwiseAbs().maxCoeff() > 0.0;
      bl.feedthrough.push_back(ft);
      col += p.size;
    }
  }

  // A gain of a pd or pid block: absent, or written as a literal 0 (a constant
  // expression, no parameter, equal to 0), is no term and carries no state.
  std::optional<double> term(const YAML::Node& blk, const char* field) {
    const YAML::Node n = blk[field];
    if (!n) return std::nullopt;
    const double v = number(n, field);
    if (v == 0.0 && n.IsScalar()) {
      bool literal = false;
      try {
        literal = parsed_.expression(n.Scalar()).parameters().empty();
      } catch (const b::ExpressionError&) {
      }
      if (literal) return std::nullopt;
    }
    return v;
  }

  // pd and pid: P + I/s + D s/(tau s + 1), states by structure; a pid's output limits
  // and anti-windup (docs/diagram-format.md, "The pid block").
  void pid_block(Block& bl, const YAML::Node& blk) {
    const bool pid = bl.type == BlockType::Pid;
    require(blk, "P", bl);
    if (!pid) require(blk, "D", bl);
    const double p = blk["P"] ? number(blk["P"], "P") : NAN;
    const std::optional<double> i = pid ? term(blk, "I") : std::nullopt, dd = term(blk, "D");
    const double tau = blk["tau"] ? number(blk["tau"], "tau") : 0.0;
    if (!std::isfinite(p) || (i && !std::isfinite(*i)) || (dd && !std::isfinite(*dd)) || !std::isfinite(tau)) return;
    if (dd && !(tau > 0.0)) {
      error(blk["tau"] ? where(blk["tau"]) : bl.where,
            "block '" + bl.name + "': a derivative needs a filter time constant 'tau' > 0 (P + D s alone is improper; a D "
            "given by a parameter keeps its filter at any value, write D: 0 for no derivative)");
      return;
    }
    PidLaw law;
    law.p = p;
    law.has_i = i.has_value();
    law.i = i.value_or(0.0);
    law.has_d = dd.has_value();
    law.d = dd.value_or(0.0);
    law.tau = law.has_d ? tau : 0.0;
    if (pid && !pid_limits(bl, blk, law)) return;
    if (pid) bl.pid = law;
    set_tf(bl, b::pid_terms(p, i, dd, tau), blk);
  }

  // A pid's `output_limits`, `anti_windup` and `Kt`; false after an error.
  bool pid_limits(const Block& bl, const YAML::Node& blk, PidLaw& law) {
    const std::size_t before = rd_.diagnostics().size();
    if (const YAML::Node r = blk["output_limits"]) {
      if (!r.IsSequence() || r.size() != 2) {
        error(r, "block '" + bl.name + "': 'output_limits' must be [lo, hi]");
      } else {
        const double lo = number(r[0], "output_limits"), hi = number(r[1], "output_limits");
        if (std::isfinite(lo) && std::isfinite(hi) && !(lo < hi)) error(r, "block '" + bl.name + "': 'output_limits' must have lo < hi");
        law.output_limits = std::make_pair(lo, hi);
      }
    }
    if (const YAML::Node a = blk["anti_windup"]) {
      const std::string t = a.IsScalar() ? a.Scalar() : "";
      if (t == "none") law.anti_windup = AntiWindup::None;
      else if (t == "clamp") law.anti_windup = AntiWindup::Clamp;
      else if (t == "back_calculation") law.anti_windup = AntiWindup::BackCalculation;
      else error(a, "block '" + bl.name + "': 'anti_windup' must be none, clamp or back_calculation");
      if (law.anti_windup != AntiWindup::None && !law.output_limits)
        error(a, "block '" + bl.name + "': 'anti_windup' needs 'output_limits' (there is nothing to wind up against)");
      if (law.anti_windup != AntiWindup::None && !law.has_i)
        error(a, "block '" + bl.name + "': 'anti_windup' needs an integral term 'I' (there is no integrator to wind up)");
    }
    const bool back = law.anti_windup == AntiWindup::BackCalculation;
    if (const YAML::Node k = blk["Kt"]) {
      if (!back) error(k, "block '" + bl.name + "': 'Kt' is the gain of anti_windup: back_calculation");
      law.kt = number(k, "Kt");
      if (back && std::isfinite(law.kt) && !(law.kt > 0.0)) error(k, "block '" + bl.name + "': 'Kt' must be > 0 (1/s)");
    } else if (back) {
      error(blk["anti_windup"], "block '" + bl.name + "': anti_windup: back_calculation needs its gain 'Kt' (1/s, e.g. sqrt(I/D) or I/P)");
    }
    return rd_.diagnostics().size() == before && !quiet_failure_;
  }

  // The diagram a subsystem block names, evaluated at the block's parameter values
  // (its source was read and parsed with this diagram's: ParsedDiagram::subsystems).
  void subsystem(Block& bl, const YAML::Node& blk) {
    require(blk, "file", bl);
    if (!blk["file"]) return;
    const YAML::Node f = blk["file"];
    const fs::path file = fs::path(path_).parent_path() / f.Scalar();
    std::error_code ec;
    const fs::path canon = fs::weakly_canonical(file, ec);
    const std::string key = ec ? file.string() : canon.string();
    if (std::find(chain_.begin(), chain_.end(), key) != chain_.end()) {
      std::string c;
      for (const auto& p : chain_) c += fs::path(p).filename().string() + " -> ";
      error(f, "subsystem '" + bl.name + "' includes itself: " + c + fs::path(key).filename().string());
      return;
    }
    const auto sub = parsed_.subsystems.find(bl.name);
    if (sub == parsed_.subsystems.end() || !sub->second.source) {
      if (sub != parsed_.subsystems.end())
        for (const Diagnostic& d : sub->second.errors) error(d.where, d.message);
      return;
    }
    b::ParameterMap overrides;
    std::map<std::string, Location> override_where;
    subsystem_parameters(blk["parameters"], overrides, override_where);
    std::vector<std::string> chain = chain_;
    chain.push_back(key);
    try {
      bl.subsystem = evaluate_parsed(sub->second.source->parsed(), overrides, override_where, chain);
    } catch (const DiagramError& e) {
      for (const Diagnostic& d : e.diagnostics()) error(d.where, d.message);
      return;
    }
    const bool sampled = d_->is_discrete() && !bl.subsystem->is_discrete();
    if (bl.subsystem->ts() != d_->ts_ && !sampled) {
      error(f, "subsystem '" + bl.name + "' has sample time " + std::to_string(bl.subsystem->ts()) +
                   " s, this diagram " + std::to_string(d_->ts_) + " s");
      return;
    }
    for (const auto& s : bl.subsystem->inputs()) bl.inputs.push_back({s.name, s.size});
    for (const auto& s : bl.subsystem->outputs()) bl.outputs.push_back({s.name, s.size});
    bl.feedthrough = subsystem_feedthrough(*bl.subsystem);
    if (sampled) sample(bl, f);
  }

  // A continuous subsystem in a discrete diagram: its exact sampled-data model
  // (sampled_plant.hpp); direct feedthrough where the model's D has it (an undelayed
  // input reaching an output through gains alone).
  void sample(Block& bl, const YAML::Node& f) {
    try {
      SampledPlant p = sample_plant(*bl.subsystem, d_->ts_, bl.name);
      bl.sampled = true;
      bl.model = std::move(p.model);
      bl.input_delays_s = std::move(p.input_delays_s);
      bl.output_delay_samples = std::move(p.output_delay_samples);
    } catch (const DiagramError& e) {
      for (const Diagnostic& d : e.diagnostics()) error(d.where, d.message);
      return;
    } catch (const InputError& e) {
      error(f, "sampled plant '" + bl.name + "': " + e.what());
      return;
    }
    bl.feedthrough.clear();
    int col = 0;
    for (const Port& p : bl.inputs) {
      bl.feedthrough.push_back(bl.model.d().middleCols(col, p.size).cwiseAbs().maxCoeff() > 0.0);
      col += p.size;
    }
    if (bl.model.num_inputs() == 1 && bl.model.num_outputs() == 1) bl.tf = bl.model.to_tf();
  }

  void subsystem_parameters(const YAML::Node& p, b::ParameterMap& overrides, std::map<std::string, Location>& where_given) {
    if (!p) return;
    if (!p.IsMap()) {
      error(p, "'parameters' of a subsystem must be a map name: value");
      return;
    }
    for (const auto& kv : p) {
      const double v = number(kv.second, kv.first.Scalar());
      if (std::isfinite(v)) overrides[kv.first.Scalar()] = v;
      where_given[kv.first.Scalar()] = where(kv.first);
    }
  }

  // For each input of a diagram: does some output depend on it without a state in between?
  static std::vector<bool> subsystem_feedthrough(const Diagram& d) {
    std::vector<bool> out;
    for (size_t in = 0; in < d.inputs().size(); ++in) {
      // Forward search through feedthrough block ports from diagram input `in`.
      std::set<int> seen;
      std::vector<Source> frontier{{-1, static_cast<int>(in)}};
      bool reaches = false;
      while (!frontier.empty() && !reaches) {
        const Source s = frontier.back();
        frontier.pop_back();
        for (size_t j = 0; j < d.outputs().size(); ++j)
          if (d.output_driver(static_cast<int>(j)) == s) reaches = true;
        for (size_t bi = 0; bi < d.blocks().size(); ++bi) {
          const auto& drv = d.drivers(static_cast<int>(bi));
          for (size_t k = 0; k < drv.size(); ++k) {
            if (drv[k] == s && d.blocks()[bi].feedthrough[k] && !seen.count(static_cast<int>(bi))) {
              seen.insert(static_cast<int>(bi));
              for (size_t o = 0; o < d.blocks()[bi].outputs.size(); ++o)
                frontier.push_back({static_cast<int>(bi), static_cast<int>(o)});
            }
          }
        }
      }
      out.push_back(reaches);
    }
    return out;
  }

  // ---- connections -----------------------------------------------------------------------
  struct End {
    int block = -1;  // -1: a diagram input (as a source) or output (as a sink)
    int port = -1;
    int size = 1;
    bool ok = false;
  };

  End resolve(const std::string& text, const Location& at, bool as_source) {
    End e;
    const auto dot = text.find('.');
    const std::string bname = text.substr(0, dot);
    const std::string pname = dot == std::string::npos ? "" : text.substr(dot + 1);
    if (dot == std::string::npos) {
      const int io = as_source ? d_->find_input(bname) : d_->find_output(bname);
      if (io >= 0) {
        e.port = io;
        e.size = (as_source ? d_->inputs_ : d_->outputs_)[static_cast<size_t>(io)].size;
        e.ok = true;
        return e;
      }
      if ((as_source ? d_->find_output(bname) : d_->find_input(bname)) >= 0) {
        error(at, "'" + bname + "' is a diagram " + (as_source ? "output: it cannot drive a signal" : "input: it cannot be driven"));
        return e;
      }
    }
    const int bi = block_index(bname);
    if (bi < 0) {
      error(at, "unknown block or diagram " + std::string(as_source ? "input" : "output") + " '" + bname + "'");
      return e;
    }
    if (broken_.count(bname)) return e;  // already reported
    const Block& bl = d_->blocks_[static_cast<size_t>(bi)];
    const auto& ports = as_source ? bl.outputs : bl.inputs;
    std::string names;
    for (const auto& p : ports) names += (names.empty() ? "" : ", ") + p.name;
    if (pname.empty()) {
      if (ports.size() != 1) {
        error(at, "block '" + bname + "' has " + std::to_string(ports.size()) + " " + (as_source ? "outputs" : "inputs") +
                      ": name one (" + names + ")");
        return e;
      }
      e.block = bi;
      e.port = 0;
      e.size = ports[0].size;
      e.ok = true;
      return e;
    }
    for (size_t k = 0; k < ports.size(); ++k) {
      if (ports[k].name == pname) {
        e.block = bi;
        e.port = static_cast<int>(k);
        e.size = ports[k].size;
        e.ok = true;
        return e;
      }
    }
    const auto& other = as_source ? bl.inputs : bl.outputs;
    for (const auto& p : other)
      if (p.name == pname) {
        error(at, "'" + text + "' is an " + (as_source ? "input" : "output") + " of block '" + bname + "', not an " +
                      (as_source ? "output" : "input"));
        return e;
      }
    error(at, "block '" + bname + "' (" + to_string(bl.type) + ") has no " + (as_source ? "output" : "input") + " '" +
                  pname + "' (its " + (as_source ? "outputs" : "inputs") + ": " + (names.empty() ? "none" : names) + ")");
    return e;
  }

  static std::string trim(const std::string& s) {
    const auto a = s.find_first_not_of(" \t");
    const auto b = s.find_last_not_of(" \t");
    return a == std::string::npos ? "" : s.substr(a, b - a + 1);
  }

  void connections(const YAML::Node& n) {
    d_->drivers_.resize(d_->blocks_.size());
    for (size_t i = 0; i < d_->blocks_.size(); ++i)
      d_->drivers_[i].assign(d_->blocks_[i].inputs.size(), Source{-2, 0});
    d_->output_drivers_.assign(d_->outputs_.size(), Source{-2, 0});
    std::vector<std::vector<Location>> driven_at(d_->blocks_.size());
    for (size_t i = 0; i < d_->blocks_.size(); ++i) driven_at[i].resize(d_->blocks_[i].inputs.size());
    std::vector<Location> out_driven_at(d_->outputs_.size());
    if (!n) {
      error(Location{path_, 1, 1}, "missing 'connections'");
      return;
    }
    if (!n.IsSequence()) {
      error(n, "'connections' must be a list of 'from -> to' entries");
      return;
    }
    for (const auto& c : n) {
      std::string from;
      std::vector<std::pair<std::string, Location>> tos;
      Location from_at = where(c);
      if (c.IsScalar()) {
        const std::string s = c.Scalar();
        const auto arrow = s.find("->");
        if (arrow == std::string::npos) {
          error(c, "a connection is 'FROM -> TO', 'FROM -> [TO1, TO2]' or {from: FROM, to: TO}");
          continue;
        }
        from = trim(s.substr(0, arrow));
        from_at = where(c, static_cast<int>(s.find_first_not_of(" \t")));
        std::string rest = trim(s.substr(arrow + 2));
        size_t offset = s.find(rest, arrow + 2);
        if (!rest.empty() && rest.front() == '[' && rest.back() == ']') {
          std::string inner = rest.substr(1, rest.size() - 2);
          size_t pos = 0;
          while (pos <= inner.size()) {
            const size_t comma = inner.find(',', pos);
            const std::string item = inner.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
            const std::string t = trim(item);
            const size_t col = offset + 1 + pos + item.find_first_not_of(" \t");
            if (!t.empty()) tos.push_back({t, where(c, static_cast<int>(col))});
            if (comma == std::string::npos) break;
            pos = comma + 1;
          }
        } else if (!rest.empty()) {
          tos.push_back({rest, where(c, static_cast<int>(offset))});
        }
      } else if (c.IsMap() && c["from"] && c["to"]) {
        check_keys(c, {"from", "to"}, "connection key");
        from = c["from"].Scalar();
        from_at = where(c["from"]);
        if (c["to"].IsSequence()) {
          for (const auto& t : c["to"]) tos.push_back({t.Scalar(), where(t)});
        } else {
          tos.push_back({c["to"].Scalar(), where(c["to"])});
        }
      } else {
        error(c, "a connection is 'FROM -> TO', 'FROM -> [TO1, TO2]' or {from: FROM, to: TO}");
        continue;
      }
      if (from.empty() || tos.empty()) {
        error(c, "a connection needs a source and at least one destination");
        continue;
      }
      const End src = resolve(from, from_at, true);
      for (const auto& [t, at] : tos) {
        const End dst = resolve(t, at, false);
        // A destination whose connection was wrong is still "driven": no follow-on
        // "not driven" message for a problem already reported.
        auto mark_driven = [&] {
          if (!dst.ok) return;
          Source& slot = dst.block >= 0 ? d_->drivers_[static_cast<size_t>(dst.block)][static_cast<size_t>(dst.port)]
                                        : d_->output_drivers_[static_cast<size_t>(dst.port)];
          if (slot.block == -2) slot = Source{-3, 0};
        };
        if (!src.ok || !dst.ok) {
          mark_driven();
          continue;
        }
        if (src.size != dst.size) {
          error(at, "size mismatch: '" + from + "' has size " + std::to_string(src.size) + ", '" + t + "' expects " +
                        std::to_string(dst.size));
          mark_driven();
          continue;
        }
        const Source s{src.block, src.port};
        Source& slot = dst.block >= 0 ? d_->drivers_[static_cast<size_t>(dst.block)][static_cast<size_t>(dst.port)]
                                      : d_->output_drivers_[static_cast<size_t>(dst.port)];
        Location& first = dst.block >= 0 ? driven_at[static_cast<size_t>(dst.block)][static_cast<size_t>(dst.port)]
                                         : out_driven_at[static_cast<size_t>(dst.port)];
        if (slot.block == -3) {
          slot = s;
          first = at;
          continue;
        }
        if (slot.block != -2) {
          error(at, "'" + t + "' is driven twice (first at line " + std::to_string(first.line) + ")");
          continue;
        }
        slot = s;
        first = at;
      }
    }
    for (size_t i = 0; i < d_->blocks_.size(); ++i) {
      if (broken_.count(d_->blocks_[i].name)) continue;
      for (size_t k = 0; k < d_->blocks_[i].inputs.size(); ++k)
        if (d_->drivers_[i][k].block == -2)
          error(d_->blocks_[i].where, "input '" + d_->blocks_[i].name + "." + d_->blocks_[i].inputs[k].name +
                                          "' is not driven by any connection");
    }
    for (size_t j = 0; j < d_->outputs_.size(); ++j)
      if (d_->output_drivers_[j].block == -2)
        error(d_->outputs_[j].where, "diagram output '" + d_->outputs_[j].name + "' is not driven by any connection");
  }

  // ---- algebraic loops ----------------------------------------------------------------------
  // Depth-first search for cycles of feedthrough edges, with an explicit stack: a chain of
  // tens of thousands of blocks must not overflow the call stack (issue 13).
  void algebraic_loops() {
    const auto& bl = d_->blocks_;
    const size_t n = bl.size();
    // Edge a -> b when an output of a drives a feedthrough input of b.
    std::vector<std::vector<int>> next(n);
    for (size_t bi = 0; bi < n; ++bi) {
      const auto& drv = d_->drivers_[bi];
      for (size_t k = 0; k < drv.size(); ++k)
        if (drv[k].block >= 0 && bl[bi].feedthrough[k]) next[static_cast<size_t>(drv[k].block)].push_back(static_cast<int>(bi));
    }
    std::vector<int> state(n, 0), path;  // 0 new, 1 on the path, 2 done; path: the current DFS path
    std::vector<size_t> edge(n, 0);      // the next edge to follow from each vertex on the path
    std::set<std::set<int>> reported;
    for (size_t root = 0; root < n; ++root) {
      if (state[root] != 0) continue;
      state[root] = 1;
      path.push_back(static_cast<int>(root));
      while (!path.empty()) {
        const auto v = static_cast<size_t>(path.back());
        if (edge[v] == next[v].size()) {
          state[v] = 2;
          path.pop_back();
          continue;
        }
        const int w = next[v][edge[v]++];
        if (state[static_cast<size_t>(w)] == 1) {
          report_loop(path, w, reported);
        } else if (state[static_cast<size_t>(w)] == 0) {
          state[static_cast<size_t>(w)] = 1;
          path.push_back(w);
        }
      }
    }
  }

  // The loop closed by an edge from the end of `path` back to w (once per set of blocks).
  void report_loop(const std::vector<int>& path, int w, std::set<std::set<int>>& reported) {
    const auto& bl = d_->blocks_;
    const auto it = std::find(path.begin(), path.end(), w);
    if (!reported.insert(std::set<int>(it, path.end())).second) return;
    std::string names;
    for (auto j = it; j != path.end(); ++j) names += bl[static_cast<size_t>(*j)].name + " -> ";
    names += bl[static_cast<size_t>(w)].name;
    error(bl[static_cast<size_t>(w)].where,
          "algebraic loop: " + names + " (every block in the loop has direct feedthrough; add a delay, a "
          "filter or a state)");
  }

  const ParsedDiagram& parsed_;
  std::string path_;
  std::vector<std::string> chain_;
  yaml::Reader rd_;
  std::set<std::string> broken_parameters_;  // wrong definitions: their uses are not reported again
  bool quiet_failure_ = false;               // a value of the block being built used one
  Diagram* d_ = nullptr;
  b::C2dMethod method_ = b::C2dMethod::Tustin;
  std::set<std::string> broken_;  // blocks with errors: their ports are not checked further
  std::unordered_map<std::string, int> block_index_;  // name -> block, once the blocks are read

  // Diagram::find_block by hash: a diagram of 10^4 blocks has 10^4 connections (a linear
  // search each was most of the time of loading it).
  int block_index(const std::string& name) {
    if (block_index_.size() != d_->blocks_.size()) {
      block_index_.clear();
      for (size_t i = 0; i < d_->blocks_.size(); ++i) block_index_.emplace(d_->blocks_[i].name, static_cast<int>(i));
    }
    const auto it = block_index_.find(name);
    return it == block_index_.end() ? -1 : it->second;
  }
};

std::shared_ptr<const Diagram> evaluate_parsed(const ParsedDiagram& parsed, const b::ParameterMap& overrides,
                                               const std::map<std::string, Location>& override_where,
                                               const std::vector<std::string>& chain) {
  return Loader(parsed, chain).run(overrides, override_where);
}

std::shared_ptr<const Diagram> Diagram::parse(const std::string& yaml, const std::string& path,
                                              const b::ParameterMap& overrides) {
  return DiagramSource::parse(yaml, path)->evaluate(overrides);
}

std::shared_ptr<const Diagram> Diagram::load(const std::string& path, const b::ParameterMap& overrides) {
  return DiagramSource::load(path)->evaluate(overrides);
}

}  // namespace dmbd::diagrams
