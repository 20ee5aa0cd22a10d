#include "engine_names.hpp"
#include "variant_controllers.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/control/registry.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/error.hpp"

namespace dmbd::scenario {

namespace {

using Ranges = std::vector<std::pair<double, double>>;

Ranges input_ranges(const diagrams::Diagram& d) {
  Ranges r;
  for (const auto& in : d.inputs())
    for (int k = 0; k < in.size; ++k) r.push_back(in.range.value_or(std::make_pair(-1.0, 1.0)));
  return r;
}

// Program ports in the diagram's order -> bus signals (and where each was bound).
std::vector<std::string> bind_ports(const ControllerSetup& c, const std::vector<diagrams::SignalSpec>& ports, bool inputs,
                              const std::string& cwhere, std::vector<std::string>* port_where) {
  const auto& given = inputs ? c.inputs : c.outputs;
  const auto& given_where = inputs ? c.input_where : c.output_where;
  const auto where_of = [&](std::size_t k) { return k < given_where.size() && !given_where[k].empty() ? given_where[k] : cwhere; };
  std::vector<std::string> out;
  for (const auto& port : ports) {
    // The bindings of this port, one per element in order (a list for a wider port).
    std::vector<std::size_t> at;
    for (std::size_t k = 0; k < given.size(); ++k)
      if (given[k].first == port.name) at.push_back(k);
    if (at.empty()) {
      if (!inputs) {
        out.insert(out.end(), static_cast<std::size_t>(port.size), std::string());  // published as "<controller>.<port>"
        continue;
      }
      throw InputError(cwhere + ": controller '" + c.name + "': input '" + port.name + "' of " + c.diagram + " is not bound");
    }
    if (at.size() != static_cast<std::size_t>(port.size))
      throw InputError(fmt::format("{}: controller '{}': {} '{}' of {} has {} element{}: expected {}, got {} bus signal{}", where_of(at.front()),
                                   c.name, inputs ? "input" : "output", port.name, c.diagram, port.size, port.size == 1 ? "" : "s",
                                   port.size == 1 ? "one bus signal" : fmt::format("a list of {} bus signals, one per element in order", port.size),
                                   at.size(), at.size() == 1 ? "" : "s"));
    for (std::size_t k : at) {
      out.push_back(given[k].second);
      if (port_where) port_where->push_back(where_of(k));
    }
  }
  for (std::size_t k = 0; k < given.size(); ++k)
    if (std::none_of(ports.begin(), ports.end(), [&](const auto& p) { return p.name == given[k].first; }))
      throw InputError(where_of(k) + ": controller '" + c.name + "': " + c.diagram + " has no " + (inputs ? "input" : "output") +
                       " '" + given[k].first + "'");
  return out;
}

std::vector<FixedPointFacts> facts(const ControllerSetup& c, const diagrams::Diagram& d, const codegen::LoopProgram& p,
                                   const codegen::FixedProgram& f, double duration_s) {
  const int horizon = static_cast<int>(std::clamp(std::ceil(duration_s * c.rate_hz), 1.0, 200000.0));
  const codegen::ErrorBound b = codegen::predicted_error_bound(p, f, input_ranges(d), horizon);
  std::vector<FixedPointFacts> out;
  std::size_t k = 0;
  for (const auto& o : d.outputs())
    for (int i = 0; i < o.size; ++i, ++k) {
      const double range = o.range ? std::max(std::abs(o.range->first), std::abs(o.range->second)) : std::nan("");
      out.push_back({c.name, o.name, o.unit, c.word_bits, k < b.over_horizon.size() ? b.over_horizon[k] : std::nan(""), range});
    }
  return out;
}

}  // namespace

namespace {

// A controller's diagram loaded with its parameters and lowered at its rate (and, in
// fixed point, the program's fixed form).
struct Lowered {
  std::shared_ptr<const diagrams::Diagram> diagram;
  std::shared_ptr<const codegen::LoopProgram> program;
  std::shared_ptr<const codegen::FixedProgram> fixed;
};

Lowered lowered(const ControllerSetup& c) {
  blocks::ParameterMap overrides;
  for (const auto& [k, val] : c.parameters) overrides[k] = val;
  Lowered l;
  l.diagram = diagrams::Diagram::load(c.diagram, overrides);
  codegen::LowerOptions lo;
  lo.rate_hz = c.rate_hz;
  if (l.diagram->discretization()) lo.method = *l.diagram->discretization();
  l.program = std::make_shared<codegen::LoopProgram>(codegen::lower(*l.diagram, lo));
  if (c.scalar == Scalar::Fixed)
    l.fixed = std::make_shared<codegen::FixedProgram>(codegen::make_fixed(*l.program, input_ranges(*l.diagram), c.word_bits));
  return l;
}

GeneratedSource generated_source(const ControllerSetup& c, const Lowered& l) { return {l.program, c.scalar, l.fixed, c.diagram}; }

std::string where_of(const Scenario& s, const ControllerSetup& c) { return c.where.empty() ? s.file : c.where; }

}  // namespace

VariantController variant_controller(const Scenario& s, const ControllerSetup& c, double duration_s) {
  const std::string cwhere = where_of(s, c);
  Lowered l;
  try {
    l = lowered(c);
  } catch (const diagrams::DiagramError&) {
    throw;  // located in the diagram file already, one line per problem
  } catch (InputError& e) {
    e.prepend(cwhere + ": controller '" + c.name + "': ");  // lowering: the controller's line
    throw;
  }
  VariantController vc;
  if (c.scalar == Scalar::Fixed) vc.fixed_point = facts(c, *l.diagram, *l.program, *l.fixed, duration_s);
  ControllerSpec& cs = vc.spec;
  cs.name = c.name;
  cs.delay_s = c.delay_s;
  cs.where = cwhere;
  try {
    if (c.implementation == Implementation::Generated) {
      vc.generated = generated_controller(generated_source(c, l));
      cs.controller = vc.generated;
    } else {
      cs.controller = loop_program_controller(l.program, c.scalar, l.fixed);
    }
  } catch (InputError& e) {
    e.prepend(cwhere + ": controller '" + c.name + "': ");
    throw;
  }
  cs.inputs = bind_ports(c, l.diagram->inputs(), true, cwhere, &cs.input_where);
  cs.outputs = bind_ports(c, l.diagram->outputs(), false, cwhere, nullptr);
  return vc;
}

void build_generated_controllers(const Scenario& s) {
  std::vector<SharedObjectSource> sources;
  std::vector<std::string> context;  // how each one's errors begin
  for (const auto& v : s.variants)
    for (const auto& c : v.controllers) {
      if (c.implementation != Implementation::Generated) continue;
      context.push_back(s.file + ": variant '" + v.name + "': " + where_of(s, c) + ": controller '" + c.name + "': ");
      try {
        sources.push_back(sil_source(generated_source(c, lowered(c))));
      } catch (InputError& e) {
        e.prepend(context.back());
        throw;
      }
    }
  const std::vector<SharedObjectBuild> built = build_shared_objects(sources);
  for (std::size_t k = 0; k < built.size(); ++k)
    if (!built[k].object) throw InputError(context[k] + "the generated code " + built[k].error);
}

void record_controllers(const Simulation& sim, const SimulationSpec& spec, const std::vector<VariantController>& scenario_controllers,
                        VariantResult& r) {
  const std::vector<unsigned long long> clamps = sim.controller_clamp_events();
  for (std::size_t k = 0; k < clamps.size() && k < spec.controllers.size(); ++k)
    r.clamp_events.push_back(spec.controllers[k].controller->counts_clamp_events() ? std::optional<unsigned long long>(clamps[k])
                                                                                    : std::nullopt);
  for (const auto& vc : scenario_controllers) {
    if (!vc.generated) continue;
    const GeneratedSource& g = vc.generated->source();
    const SharedObjectBuild& b = vc.generated->build();
    if (!r.sil) r.sil = SilFacts{b.compiler.command, b.compiler.version, b.compiler.flags, {}};
    const std::string scalar = g.scalar == Scalar::Fixed ? "fixed" + std::to_string(g.fixed->word_bits)
                                                         : (g.scalar == Scalar::Float ? "float" : "double");
    r.sil->controllers.push_back({vc.spec.name, scalar, b.key, b.compile_s, vc.generated->saturations()});
  }
}

std::vector<BusControllerRun> bus_controllers(const VariantSetup& v, const VariantPlant& vp, const model::Plant& plant, double duration_s) {
  control::BusControllerContext c{vp.robot, v.robot.base, v.robot.X_WB, v.robot.gravity_m_s2, v.robot.contact, {}, {}, duration_s};
  for (int k = 0; k < plant.num_actuators(); ++k) c.actuators.push_back(plant.actuator(k));
  for (const auto& j : vp.robot.joints) c.q0.emplace_back(j.name, initial_angle(v.robot, j.name));
  std::vector<BusControllerRun> out;
  for (const auto& o : v.bus_controllers) {
    const control::BusControllerType* t = control::find_bus_controller(o->type);
    if (!t) throw InputError(o->where + ": bus controller type '" + o->type + "' is not registered");
    if (o->assumed_load_set.empty()) {
      out.push_back({o, t->make(*o, c)});
      continue;
    }
    control::BusControllerContext assumed = c;  // the plant's table with the named set's load terms
    if (assumed.actuators.empty())
      throw InputError(o->assumed_load_set_where + ": " + o->name + ".assumed_load_set: the plant has no actuators (robot.actuators) whose load to assume");
    try {
      model::select_load_set(assumed.actuators, o->assumed_load_set);
    } catch (const model::ModelError& e) {
      throw InputError(o->assumed_load_set_where + ": " + o->name + ".assumed_load_set: " + e.what());
    }
    out.push_back({o, t->make(*o, assumed)});
  }
  return out;
}

sim::ControllerSpec bus_controller_spec(const control::BusControllerOptions& o, std::shared_ptr<sim::Controller> c) {
  sim::ControllerSpec cs;
  cs.name = o.name;
  cs.delay_s = o.delay_s;
  cs.where = o.where;
  for (int k = 0; k < c->num_inputs(); ++k) cs.inputs.push_back(c->input_name(k));
  for (int k = 0; k < c->num_outputs(); ++k) cs.outputs.push_back(c->output_name(k));
  cs.controller = std::move(c);
  return cs;
}

void tick_timing(const std::vector<double>& times_us, const std::string& prefix, VariantResult& r) {
  std::vector<double> t = times_us;
  if (t.empty()) return;
  std::nth_element(t.begin(), t.begin() + static_cast<std::ptrdiff_t>(t.size() / 2), t.end());
  r.timing_us[prefix + "_tick_us_median"] = t[t.size() / 2];
  r.timing_us[prefix + "_tick_us_max"] = *std::max_element(t.begin(), t.end());
}

void record_limits(const Simulation& sim, const model::Plant& plant, VariantResult& r) {
  for (int j = 0; j < plant.num_joints(); ++j)
    if (const long long n = plant.effort_clamp_events()[static_cast<std::size_t>(j)]; n > 0)
      r.effort_clamp_events[plant.joint_names()[static_cast<std::size_t>(j)]] = n;
  r.velocity_limit_exceeded = sim.velocity_limit_exceeded();
  for (const std::string& line : sim.unfired_triggers()) r.warnings.push_back("variant '" + r.name + "': " + line);
  for (const auto& [joint, e] : r.velocity_limit_exceeded)
    r.warnings.push_back(fmt::format("variant '{}': joint '{}' ran at up to {:.4g} (its URDF velocity limit: {:.4g}) in {} plant steps", r.name,
                                     joint, e.peak, e.limit, e.samples));
}

void fixed_point_warnings(VariantResult& r) {
  for (const auto& f : r.fixed_point)
    if (!(f.bound <= f.range))  // a bound beyond the range, or none (inf)
      r.warnings.push_back(fmt::format("variant '{}': controller '{}' in {}-bit fixed point: the predicted error bound on its output '{}' "
                                       "over the run, {:.4g} {}, is not within its range (+-{:.4g} {}): its output may be wrong by more "
                                       "than it can hold",
                                       r.name, f.controller, f.word_bits, f.output, f.bound, f.unit, f.range, f.unit));
}

}  // namespace dmbd::scenario
