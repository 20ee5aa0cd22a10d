// The osc bus controller type: its options read from YAML (key by key over a base) and
// its controller built for a fixed-base variant (registry.hpp, osc_controller.hpp).
#include <fmt/format.h>

#include "builtin_types.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/control/osc_controller.hpp"

namespace dmbd::control::detail {

namespace {

Eigen::Vector3d vec3(const yaml::Fields& f, const YAML::Node& n, const std::string& what) {
  const auto v = f.numbers<3>(n, what);
  return {v[0], v[1], v[2]};
}

// Three gains: one number for every axis, or a list of three.
Eigen::Vector3d gains3(const yaml::Fields& f, const YAML::Node& n, const std::string& what) {
  if (n.IsScalar()) return Eigen::Vector3d::Constant(f.number_in(n, what, 0.0, 1e9, ""));
  const Eigen::Vector3d g = vec3(f, n, what);
  if ((g.array() < 0).any()) f.fail(n, what + ": expected gains of 0 or more");
  return g;
}

void read_trajectory(const yaml::Fields& f, const YAML::Node& t, OscTrajectory& tr) {
  f.keys(t, "osc.trajectory", {"amplitude_m", "frequency_hz", "ramp_s"});
  f.optional(t, "amplitude_m", [&](const YAML::Node& x) { tr.amplitude_m = vec3(f, x, "osc.trajectory.amplitude_m"); });
  f.optional(t, "frequency_hz", [&](const YAML::Node& x) { tr.frequency_hz = f.number_in(x, "osc.trajectory.frequency_hz", 0.0, 1e3, "Hz"); });
  f.optional(t, "ramp_s", [&](const YAML::Node& x) { tr.ramp_s = f.number_in(x, "osc.trajectory.ramp_s", 0.0, 1e6, "s"); });
}

class OscType : public BusControllerType {
 public:
  std::shared_ptr<BusControllerOptions> read(const yaml::Fields& f, const YAML::Node& n, const BusControllerOptions* base) const override {
    check_keys(f, n, "osc", {"link", "point", "trajectory", "kp", "kd", "posture", "sensors", "compensate_load_damping"});
    auto o = std::make_shared<OscSetup>();
    if (const auto* b = dynamic_cast<const OscSetup*>(base)) *o = *b;
    o->type = "osc";
    if (o->name.empty()) o->name = "osc";
    o->where = f.at(n);
    read_common_options(f, n, *o);
    f.optional(n, "link", [&](const YAML::Node& x) { o->link = f.text(x, "osc.link"); });
    f.optional(n, "point", [&](const YAML::Node& x) { o->point_L = vec3(f, x, "osc.point"); });
    f.optional(n, "trajectory", [&](const YAML::Node& t) { read_trajectory(f, t, o->trajectory); });
    f.optional(n, "kp", [&](const YAML::Node& x) { o->kp = gains3(f, x, "osc.kp"); });
    f.optional(n, "kd", [&](const YAML::Node& x) { o->kd = gains3(f, x, "osc.kd"); });
    f.optional(n, "posture", [&](const YAML::Node& p) {
      f.keys(p, "osc.posture", {"kp", "kd"});
      f.optional(p, "kp", [&](const YAML::Node& x) { o->posture_kp = f.number_in(x, "osc.posture.kp", 0.0, 1e9, "1/s^2"); });
      f.optional(p, "kd", [&](const YAML::Node& x) { o->posture_kd = f.number_in(x, "osc.posture.kd", 0.0, 1e9, "1/s"); });
    });
    f.optional(n, "compensate_load_damping", [&](const YAML::Node& x) { o->compensate_load_damping = f.boolean(x, "osc.compensate_load_damping"); });
    f.optional(n, "sensors", [&](const YAML::Node& x) {
      f.keys(x, "osc.sensors", {"q", "qd"});
      f.optional(x, "q", [&](const YAML::Node& y) { o->q_signal = f.text(y, "osc.sensors.q"); });
      f.optional(x, "qd", [&](const YAML::Node& y) { o->qd_signal = f.text(y, "osc.sensors.qd"); });
    });
    return o;
  }

  std::shared_ptr<BusController> make(const BusControllerOptions& options, const BusControllerContext& c) const override {
    const auto& o = dynamic_cast<const OscSetup&>(options);
    if (c.base != model::BaseMode::Fixed)
      throw InputError(o.where + ": " + o.name + ": operational space control needs the robot's base fixed (robot.base: fixed)");
    return std::make_shared<OscController>(c.robot, c.X_WB, c.gravity_m_s2, c.actuators, c.q0, o, ticks_over(c.duration_s, o.rate_hz));
  }

  // The point's measured path (solid) under its target's (dashed): the measured colour
  // shows between the target's dashes where they coincide.
  std::vector<sim::Overlay> overlays(const BusControllerOptions& o) const override {
    const std::string& n = o.name;
    sim::Overlay measured{"measured", {n + ".x", n + ".y", n + ".z"}, {255, 40, 200}, false, 2.0, sim::Overlay::Kind::Path, {}};
    sim::Overlay desired{"desired", {n + ".x_d", n + ".y_d", n + ".z_d"}, {0, 190, 255}, true, 2.0, sim::Overlay::Kind::Path, {}};
    return {measured, desired};
  }
};

}  // namespace

std::shared_ptr<const BusControllerType> osc_type() { return std::make_shared<OscType>(); }

std::vector<std::string> allowed_keys(std::initializer_list<const char*> own) {
  std::vector<std::string> k;
  for (const char* c : common_option_keys()) k.emplace_back(c);
  for (const char* c : own) k.emplace_back(c);
  return k;
}

void check_keys(const yaml::Fields& f, const YAML::Node& n, const std::string& what, std::initializer_list<const char*> own) {
  if (!f.reader().keys(n, allowed_keys(own), what)) throw yaml::Skip{};
}

}  // namespace dmbd::control::detail
