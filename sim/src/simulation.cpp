#include "dmbd/sim/simulation.hpp"

#include <fnmatch.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <random>

#include <fmt/format.h>

#include "dmbd/sim/event_grid.hpp"
#include "dmbd/base/strings.hpp"

#include "dmbd/blocks/error.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/sensors.hpp"

namespace dmbd::sim {

namespace {

using Ns = int64_t;
constexpr Ns kNever = std::numeric_limits<Ns>::max();

// "where: " for a spec item written at `where` (file:line:col), "" when it is unknown.
std::string at(const std::string& where) { return where.empty() ? std::string() : where + ": "; }

Ns period_ns(double rate_hz, const std::string& what) {
  if (const std::string problem = rate_problem(rate_hz); !problem.empty()) throw InputError(what + ": " + problem);
  return static_cast<Ns>(std::llround(1e9 / rate_hz));
}

}  // namespace

struct Simulation::Impl {
  model::Plant& plant;
  SimulationSpec spec;

  // Bus.
  std::vector<std::string> names, units;
  std::vector<double> bus;
  std::map<std::string, int> index;
  int add(const std::string& name, const std::string& unit) {
    const auto [it, inserted] = index.emplace(name, static_cast<int>(names.size()));
    if (inserted) {
      names.push_back(name);
      units.push_back(unit);
      bus.push_back(0.0);
    }
    return it->second;
  }
  int find(const std::string& name) const {
    const auto it = index.find(name);
    return it == index.end() ? -1 : it->second;
  }

  // Per joint and per actuator signal indices.
  int nj = 0, na = 0;
  std::vector<int> sig_q, sig_qd, sig_torque;
  int plant_signals = 0;                      // signals [0, plant_signals) are the plant's
  std::map<std::string, std::string> driver;  // bus signal -> the controller that drives it
  int sig_base = -1;     // floating base: x, y, z, roll, pitch, yaw, tilt from here on
  int sig_contact = -1;  // contact sphere k's force: fx, fy, fz at sig_contact + 3 k
  struct ActuatorIo {
    int joint = -1;
    int current = -1, q_enc = -1, q_pot = -1, force = -1, motor = -1, spring = -1;
    int force_true = -1, current_applied = -1, i2t = -1, temp_on = -1, temp_off = -1, housing_on = -1, housing_off = -1;
    model::Encoder motor_enc, spring_enc;
    std::optional<model::Potentiometer> pot;
    model::ThermalModel thermal_on, thermal_off;
    double q_enc_last = 0;
    double i2t_A2s = 0;  // integral of the applied current squared since t = 0
  };
  std::vector<ActuatorIo> acts;
  std::mt19937_64 rng;
  std::normal_distribution<double> normal{0.0, 1.0};

  // Controllers.
  struct Ctrl {
    ControllerSpec spec;
    std::vector<int> in, out;  // bus signals
    std::vector<double> u, y;
    Ns period = 0, delay = 0, next_tick = 0, publish_at = kNever;
    long long steps = 0;
  };
  std::vector<Ctrl> ctrls;
  std::vector<int> ref_sig;
  std::vector<int> force_link;
  int base_link = 0;

  Eigen::VectorXd currents, torques, q, qd;
  // Readings taken every tick into storage made once (no allocation in the loop).
  Eigen::VectorXd theta_read, spring_read, force_read, current_read;
  std::vector<model::ContactReading> contact_read;
  std::vector<double> velocity_limit;           // per joint: the URDF's (0: none)
  std::vector<VelocityExcess> velocity_excess;  // per joint
  Ns last_sensor_ns = -1;

  Impl(model::Plant& p, SimulationSpec s) : plant(p), spec(std::move(s)), rng(spec.seed) {
    nj = plant.num_joints();
    na = plant.num_actuators();
    // A prismatic joint's coordinate is a length: m, m/s and a force, N.
    std::vector<bool> sliding;
    for (const auto& J : plant.joint_names()) {
      const int d = plant.description().joint_index(J);
      sliding.push_back(d >= 0 && plant.description().joints[static_cast<std::size_t>(d)].type == model::JointType::Prismatic);
    }
    for (int j = 0; j < nj; ++j) {
      const std::string& J = plant.joint_names()[static_cast<std::size_t>(j)];
      sig_q.push_back(add(J + ".q", sliding[static_cast<std::size_t>(j)] ? "m" : "rad"));
      sig_qd.push_back(add(J + ".qd", sliding[static_cast<std::size_t>(j)] ? "m/s" : "rad/s"));
    }
    for (int j = 0; j < nj; ++j)
      sig_torque.push_back(add(plant.joint_names()[static_cast<std::size_t>(j)] + ".torque", sliding[static_cast<std::size_t>(j)] ? "N" : "N m"));
    if (plant.options().base == model::BaseMode::Floating) {
      sig_base = add("base.x", "m");
      for (const char* n : {"base.y", "base.z"}) add(n, "m");
      for (const char* n : {"base.roll", "base.pitch", "base.yaw", "base.tilt"}) add(n, "rad");
      for (const char* n : {"base.wx", "base.wy", "base.wz"}) add(n, "rad/s");
      for (const char* n : {"base.vx", "base.vy", "base.vz"}) add(n, "m/s");
    }
    for (int k = 0; k < na; ++k) {
      const model::ActuatorParams& a = plant.actuator(k);
      int joint = -1;
      for (int j = 0; j < nj; ++j)
        if (plant.actuator_of_joint(j) == k) joint = j;
      const std::string& J = a.joint;
      // The rotary kinds' force is a torque and their spring's deflection an angle; a
      // rigid geared motor has no spring, an actuator may have no potentiometer.
      const char* force_unit = a.is_rotary() ? "N m" : "N";
      ActuatorIo io{joint, add(J + ".current", "A"), add(J + ".q_enc", "rad"), a.has_potentiometer ? add(J + ".q_pot", "rad") : -1,
                    add(J + ".force", force_unit), add(J + ".motor_angle", "rad"),
                    a.has_spring() ? add(J + ".spring_deflection", a.is_rotary() ? "rad" : "m") : -1, -1, -1, -1, -1, -1, -1, -1,
                    model::Encoder(a.motor_encoder), model::Encoder(a.spring_encoder), std::nullopt,
                    model::ThermalModel(a.thermal), model::ThermalModel(a.thermal), 0.0, 0.0};
      if (spec.sensor_noise && a.has_potentiometer) io.pot.emplace(a.potentiometer, spec.seed * 1000003ULL + static_cast<uint64_t>(k));
      acts.push_back(std::move(io));
    }
    // Logged-only signals after the bus ones: per actuator, and the force on each contact
    // sphere (so that a report can draw them after the run).
    if (!plant.contacts().empty()) {
      sig_contact = static_cast<int>(names.size());
      for (std::size_t k = 0; k < plant.contacts().size(); ++k)
        for (const char* axis : {"fx", "fy", "fz"}) add(fmt::format("contact.{}.{}", k, axis), "N");
    }
    for (auto& io : acts) {
      const std::string& J = plant.actuator(static_cast<int>(&io - acts.data())).joint;
      io.force_true = add(J + ".force_true", plant.actuator(static_cast<int>(&io - acts.data())).is_rotary() ? "N m" : "N");
      io.current_applied = add(J + ".current_applied", "A");
      io.i2t = add(J + ".i2t", "A^2 s");
      if (spec.cooling != Cooling::Off) {
        io.temp_on = add(J + (spec.cooling == Cooling::Both ? ".T_winding_cooled" : ".T_winding"), "degC");
        io.housing_on = add(J + (spec.cooling == Cooling::Both ? ".T_housing_cooled" : ".T_housing"), "degC");
      }
      if (spec.cooling != Cooling::On) {
        io.temp_off = add(J + (spec.cooling == Cooling::Both ? ".T_winding_uncooled" : ".T_winding"), "degC");
        io.housing_off = add(J + (spec.cooling == Cooling::Both ? ".T_housing_uncooled" : ".T_housing"), "degC");
      }
    }
    plant_signals = static_cast<int>(names.size());
    // A reference either defines a new bus signal or drives a plant command directly
    // (e.g. a current chirp on "l_knee.current" for system identification).
    for (const auto& r : spec.references) {
      const int existing = find(r.name);
      const bool command = r.name.size() > 8 && (r.name.rfind(".current") == r.name.size() - 8 || r.name.rfind(".torque") == r.name.size() - 7);
      if (existing >= 0 && !command) throw InputError(at(r.where) + "reference '" + r.name + "': the name is already a bus signal");
      ref_sig.push_back(existing >= 0 ? existing : add(r.name, ""));
    }
    if (spec.support) {
      if (plant.options().base != model::BaseMode::Floating) throw InputError("support: the robot's base is not floating");
      base_link = 0;  // the root link is the floating base
    }
    for (const auto& f : spec.forces) {
      const int l = plant.description().link_index(f.link);
      if (l < 0) throw InputError(at(f.where) + "force on link '" + f.link + "': the robot has no such link");
      force_link.push_back(l);
    }
    // Controllers: outputs first (they define bus signals), then check inputs.
    for (const auto& c : spec.controllers) declare_outputs(c);
    for (const auto& c : spec.controllers)
      for (const auto& o : c.outputs)
        for (const auto& r : spec.references)
          if (o == r.name) throw InputError(at(r.where) + "controller '" + c.name + "' and a reference both drive '" + o + "'");
    for (const auto& c : spec.controllers) ctrls.push_back(bind(c));
    bind_triggers();
    currents = Eigen::VectorXd::Zero(na);
    torques = Eigen::VectorXd::Zero(nj);
    q = qd = Eigen::VectorXd::Zero(nj);
    theta_read = spring_read = force_read = current_read = Eigen::VectorXd::Zero(na);
    plant.contacts(contact_read);
    for (const auto& J : plant.joint_names()) {
      const int d = plant.description().joint_index(J);
      velocity_limit.push_back(d < 0 ? 0.0 : plant.description().joints[static_cast<std::size_t>(d)].velocity);
    }
    velocity_excess.assign(velocity_limit.size(), VelocityExcess{});
    for (auto& io : acts) {
      io.thermal_on.reset();
      io.thermal_off.reset();
    }
  }

  std::string output_signal(const ControllerSpec& c, std::size_t k) const {
    return c.outputs[k].empty() ? c.name + "." + c.controller->output_name(static_cast<int>(k)) : c.outputs[k];
  }
  void declare_outputs(const ControllerSpec& c) {
    if (!c.controller) throw InputError(at(c.where) + "controller '" + c.name + "': no controller");
    const Controller& p = *c.controller;
    if (static_cast<int>(c.outputs.size()) != p.num_outputs())
      throw InputError(at(c.where) + fmt::format("controller '{}': {} outputs bound for {} controller outputs", c.name, c.outputs.size(), p.num_outputs()));
    if (static_cast<int>(c.inputs.size()) != p.num_inputs())
      throw InputError(at(c.where) + fmt::format("controller '{}': {} inputs bound for {} controller inputs", c.name, c.inputs.size(), p.num_inputs()));
    for (std::size_t k = 0; k < c.outputs.size(); ++k) {
      const std::string signal = output_signal(c, k);
      check_driver(c, signal);
      add(signal, p.output_unit(static_cast<int>(k)));
    }
  }
  // A controller output drives a plant command (J.current, J.torque) or a signal of its
  // own: never one of the plant's other signals (its sensors, its state: the sensor's
  // value would be overwritten in silence), never one another controller drives.
  void check_driver(const ControllerSpec& c, const std::string& signal) {
    const int existing = find(signal);
    if (existing >= 0 && existing < plant_signals && !is_command(existing))
      throw InputError(at(c.where) + "controller '" + c.name + "': output bound to '" + signal +
                       "', a signal the plant provides (a sensor or its state): expected a command (J.current, J.torque) or a new signal");
    const auto [it, first] = driver.emplace(signal, c.name);
    if (!first) throw InputError(at(c.where) + "controllers '" + it->second + "' and '" + c.name + "' both drive '" + signal + "'");
  }
  bool is_command(int signal) const {
    if (std::find(sig_torque.begin(), sig_torque.end(), signal) != sig_torque.end()) return true;
    return std::any_of(acts.begin(), acts.end(), [&](const ActuatorIo& io) { return io.current == signal; });
  }
  // The controller's ports on the bus, its period and delay on the event grid.
  Ctrl bind(const ControllerSpec& c) {
    const Controller& p = *c.controller;
    Ctrl k{c, {}, {}, std::vector<double>(c.inputs.size()), std::vector<double>(c.outputs.size()),
           period_ns(p.rate_hz(), at(c.where) + "controller '" + c.name + "'"), 0, 0, kNever, 0};
    k.delay = static_cast<Ns>(std::llround(c.delay_s * 1e9));
    if (k.delay < 0 || k.delay > k.period)
      throw InputError(at(c.where) + fmt::format("controller '{}': delay {} s must be between 0 and one period ({} s)", c.name, c.delay_s, 1.0 / p.rate_hz()));
    for (std::size_t i = 0; i < c.inputs.size(); ++i) {
      const int sig = find(c.inputs[i]);
      if (sig < 0)
        throw InputError(at(i < c.input_where.size() ? c.input_where[i] : c.where) + "controller '" + c.name + "': input '" +
                         p.input_name(static_cast<int>(i)) + "' is bound to '" + c.inputs[i] + "', which no sensor, reference or controller provides");
      k.in.push_back(sig);
    }
    for (std::size_t i = 0; i < c.outputs.size(); ++i) k.out.push_back(find(output_signal(c, i)));
    return k;
  }

  double t_of(Ns t) const { return static_cast<double>(t) * 1e-9; }

  // Counts the joints beyond their URDF velocity limit (after a plant advance).
  void watch_velocity_limits() {
    for (int j = 0; j < nj; ++j) {
      const double lim = velocity_limit[static_cast<std::size_t>(j)], v = std::abs(qd[j]);
      if (!(lim > 0) || !(v > lim)) continue;
      VelocityExcess& e = velocity_excess[static_cast<std::size_t>(j)];
      e.limit = lim;
      e.peak = std::max(e.peak, v);
      ++e.samples;
    }
  }

  void refresh_true() {
    plant.joint_positions(q);
    plant.joint_velocities(qd);
    for (int j = 0; j < nj; ++j) {
      bus[static_cast<std::size_t>(sig_q[static_cast<std::size_t>(j)])] = q[j];
      bus[static_cast<std::size_t>(sig_qd[static_cast<std::size_t>(j)])] = qd[j];
    }
    if (sig_base >= 0) refresh_base();
  }
  // The torso's position and its roll, pitch, yaw (R = Rz(yaw) Ry(pitch) Rx(roll)) and
  // tilt (the angle of its z axis from the vertical), its angular velocity (an ideal
  // gyro, world axes) and its origin's velocity (world).
  void refresh_base() {
    const Eigen::Isometry3d X = plant.base_pose();
    const Eigen::Matrix3d& R = X.linear();
    const Eigen::Matrix<double, 6, 1> V = plant.base_velocity();
    const double v[13] = {X.translation().x(), X.translation().y(), X.translation().z(), std::atan2(R(2, 1), R(2, 2)),
                          std::asin(std::clamp(-R(2, 0), -1.0, 1.0)), std::atan2(R(1, 0), R(0, 0)), std::acos(std::clamp(R(2, 2), -1.0, 1.0)),
                          V[0], V[1], V[2], V[3], V[4], V[5]};
    for (int k = 0; k < 13; ++k) bus[static_cast<std::size_t>(sig_base + k)] = v[k];
  }
  void refresh_references(double t) {
    for (std::size_t r = 0; r < ref_sig.size(); ++r) bus[static_cast<std::size_t>(ref_sig[r])] = spec.references[r].source.value(t);
  }
  // The potentiometer's reading of joint angle q (exact without sensor noise).
  static double potentiometer(ActuatorIo& io, double q, bool first, double dt) {
    if (!io.pot) return q;
    if (first) io.pot->reset(q);
    return io.pot->read(q, first ? 1e-3 : dt);
  }
  // Samples every sensor (once per controller instant; dt for the filters).
  void refresh_sensors(Ns t) {
    const bool first = last_sensor_ns < 0;
    const double dt = first ? 0.0 : t_of(t - last_sensor_ns);
    last_sensor_ns = t;
    if (na == 0) return;
    plant.motor_angles(theta_read);
    plant.spring_deflections(spring_read);
    plant.actuator_forces(force_read);
    const Eigen::VectorXd &theta = theta_read, &xs = spring_read, &f = force_read;
    for (int k = 0; k < na; ++k) {
      ActuatorIo& io = acts[static_cast<std::size_t>(k)];
      const model::ActuatorParams& a = plant.actuator(k);
      const double th = spec.sensor_noise ? io.motor_enc.read(theta[k]) : theta[k];
      const double x = !a.has_spring() ? 0.0 : (spec.sensor_noise ? io.spring_enc.read(xs[k]) : xs[k]);
      bus[static_cast<std::size_t>(io.motor)] = th;
      if (io.spring >= 0) bus[static_cast<std::size_t>(io.spring)] = x;
      // The spring's sensed force (torque), or a rigid motor's estimate from its current.
      double force = a.has_spring() ? a.K_s_N_per_m * x : f[k];
      if (spec.sensor_noise && spec.force_noise_N > 0) force += spec.force_noise_N * normal(rng);
      bus[static_cast<std::size_t>(io.force)] = force;
      bus[static_cast<std::size_t>(io.force_true)] = f[k];
      const double qj = io.joint >= 0 ? q[io.joint] : 0.0;
      if (first) io.q_enc_last = qj;  // the first reading's branch (the firmware's lookup then follows its last reading)
      io.q_enc_last = a.angle_for_travel(th / a.N_m_rad_per_m - x, io.q_enc_last);
      bus[static_cast<std::size_t>(io.q_enc)] = io.q_enc_last;
      if (io.q_pot >= 0) bus[static_cast<std::size_t>(io.q_pot)] = potentiometer(io, qj, first, dt);
    }
  }

  void publish(Ctrl& c) {
    for (std::size_t k = 0; k < c.out.size(); ++k) bus[static_cast<std::size_t>(c.out[k])] = c.y[k];
    c.publish_at = kNever;
  }
  void step(Ctrl& c) {
    for (std::size_t k = 0; k < c.in.size(); ++k) c.u[k] = bus[static_cast<std::size_t>(c.in[k])];
    c.spec.controller->step(c.u.data(), c.y.data());
    ++c.steps;
  }
  // Applies the command signals to the plant (held until the next change).
  void apply_commands() {
    bool changed = false;
    for (int k = 0; k < na; ++k) {
      const double v = bus[static_cast<std::size_t>(acts[static_cast<std::size_t>(k)].current)];
      if (v != currents[k]) {
        currents[k] = v;
        changed = true;
      }
    }
    if (changed) plant.set_currents(currents);
    changed = false;
    for (int j = 0; j < nj; ++j) {
      const double v = bus[static_cast<std::size_t>(sig_torque[static_cast<std::size_t>(j)])];
      if (v != torques[j]) {
        torques[j] = v;
        changed = true;
      }
    }
    if (changed) plant.set_joint_torques(torques);
  }
  // Forces started by a bus event (ForceSpec::Trigger): per force, its signal (-1: none),
  // the logged start, the signal's last value, the changes seen and the start T (kNever
  // until known).
  struct TriggerState {
    int signal = -1, start_sig = -1;
    double last = 0;
    int seen = 0;
    Ns start = kNever;
  };
  std::vector<TriggerState> triggers;
  // The bus signals the log keeps, in bus order: every one, or those matching spec.log_only.
  std::vector<int> logged_signals() const {
    std::vector<int> out;
    std::vector<bool> used(spec.log_only.size(), false);
    for (std::size_t s = 0; s < names.size(); ++s) {
      bool keep = spec.log_only.empty();
      for (std::size_t p = 0; p < spec.log_only.size(); ++p)
        if (fnmatch(spec.log_only[p].pattern.c_str(), names[s].c_str(), 0) == 0) keep = used[p] = true;
      if (keep) out.push_back(static_cast<int>(s));
    }
    for (std::size_t p = 0; p < used.size(); ++p)
      if (!used[p]) {
        const std::string close = closest_name(spec.log_only[p].pattern, names);
        throw InputError(at(spec.log_only[p].where) + "log_only: '" + spec.log_only[p].pattern + "' matches no signal" +
                         (close.empty() ? std::string() : " (the closest: '" + close + "')"));
      }
    return out;
  }
  void bind_triggers() {
    for (std::size_t f = 0; f < spec.forces.size(); ++f) {
      triggers.emplace_back();
      const auto& tr = spec.forces[f].trigger;
      if (!tr) continue;
      const int s = find(tr->signal);
      if (s < 0) {
        const std::string close = closest_name(tr->signal, names);
        throw InputError(at(spec.forces[f].where) + "force on link '" + spec.forces[f].link + "': trigger signal '" + tr->signal +
                         "' is not on the bus" + (close.empty() ? std::string() : " (the closest: '" + close + "')"));
      }
      triggers.back().signal = s;
      triggers.back().start_sig = add(fmt::format("forces.{}.start_s", f), "s");
      bus[static_cast<std::size_t>(triggers.back().start_sig)] = std::nan("");
    }
  }
  void init_triggers() {
    for (auto& tr : triggers)
      if (tr.signal >= 0) tr.last = bus[static_cast<std::size_t>(tr.signal)];
  }
  // The triggers' signals at event t (after its publications): true when a force started.
  bool check_triggers(Ns t) {
    bool started = false;
    for (std::size_t f = 0; f < triggers.size(); ++f) {
      TriggerState& tr = triggers[f];
      if (tr.signal < 0 || tr.start != kNever) continue;
      const double v = bus[static_cast<std::size_t>(tr.signal)];
      if (v != tr.last && ++tr.seen == spec.forces[f].trigger->occurrence) {
        tr.start = t + static_cast<Ns>(std::llround(spec.forces[f].trigger->after_s * 1e9));
        bus[static_cast<std::size_t>(tr.start_sig)] = t_of(tr.start);
        started = true;
      }
      tr.last = v;
    }
    return started;
  }
  // Force f's magnitude at t: its source on the simulation's clock, or from its trigger's start.
  double force_value(std::size_t f, Ns t) const {
    const TriggerState& tr = triggers[f];
    if (tr.signal < 0) return spec.forces[f].source.value(t_of(t));
    return tr.start != kNever && t >= tr.start ? spec.forces[f].source.value(t_of(t - tr.start)) : 0.0;
  }
  std::vector<double> force_values;
  // Forces are held between events; the plant is only touched when one changes (each
  // change restarts its integrator).
  void apply_forces(Ns t_ns) {
    if (spec.forces.empty() && !spec.support) return;
    const double t = t_of(t_ns);
    bool changed = force_values.size() != spec.forces.size();
    force_values.resize(spec.forces.size());
    for (std::size_t f = 0; f < spec.forces.size(); ++f) {
      const double v = force_value(f, t_ns);
      changed = changed || v != force_values[f];
      force_values[f] = v;
    }
    const bool support = supported(t);
    if (!changed && !support && !support_active) return;
    plant.clear_external_forces();
    for (std::size_t f = 0; f < spec.forces.size(); ++f)
      plant.set_external_force(force_link[f], spec.forces[f].point_L, spec.forces[f].direction_W * force_values[f]);
    support_active = support;
    if (support) apply_support();
  }
  bool down = false;
  bool is_down() const {
    if (!spec.end_on_fall || sig_base < 0) return false;
    const double z = bus[static_cast<std::size_t>(sig_base + 2)], tilt = bus[static_cast<std::size_t>(sig_base + 6)];
    return z < spec.end_on_fall->torso_below_m || tilt > spec.end_on_fall->tilt_above_rad;
  }
  bool supported(double t) const { return spec.support && t < spec.support->release_s; }
  // SupportSpec: at each of the two points, f = −k (p − p₀) − c ṗ, horizontal; p₀ where
  // the point was on the first call.
  Eigen::Vector3d support_anchor[2];
  bool anchors_set = false, support_active = false;
  void apply_support() {
    const Eigen::Isometry3d X = plant.base_pose();
    const Eigen::Matrix<double, 6, 1> V = plant.base_velocity();
    const SupportSpec& s = *spec.support;
    for (int k = 0; k < 2; ++k) {
      const Eigen::Vector3d p_L(0, 0, k * s.height_m);
      const Eigen::Vector3d p = X * p_L;
      if (!anchors_set) support_anchor[k] = p;
      const Eigen::Vector3d v = V.tail<3>() + V.head<3>().cross(p - X.translation());
      Eigen::Vector3d f = -s.stiffness_N_per_m * (p - support_anchor[k]) - s.damping_N_s_per_m * v;
      f.z() = 0.0;
      plant.set_external_force(base_link, p_L, f);
    }
    anchors_set = true;
  }
  void advance_thermal(double dt) {
    if (dt <= 0 || na == 0) return;
    plant.applied_currents(current_read);
    const Eigen::VectorXd& i = current_read;
    for (int k = 0; k < na; ++k) {
      ActuatorIo& io = acts[static_cast<std::size_t>(k)];
      io.thermal_on.step(i[k], dt, true);
      io.thermal_off.step(i[k], dt, false);
      io.i2t_A2s += i[k] * i[k] * dt;  // exact: the applied current is held between events
    }
  }
  void fill_logged() {
    if (sig_contact >= 0) {
      plant.contacts(contact_read);
      const std::vector<model::ContactReading>& c = contact_read;
      for (std::size_t k = 0; k < c.size(); ++k)
        for (int i = 0; i < 3; ++i) bus[static_cast<std::size_t>(sig_contact) + 3 * k + static_cast<std::size_t>(i)] = c[k].force_W[i];
    }
    if (na == 0) return;
    plant.applied_currents(current_read);
    plant.actuator_forces(force_read);
    const Eigen::VectorXd &i = current_read, &f = force_read;
    for (int k = 0; k < na; ++k) {
      ActuatorIo& io = acts[static_cast<std::size_t>(k)];
      bus[static_cast<std::size_t>(io.current_applied)] = i[k];
      bus[static_cast<std::size_t>(io.i2t)] = io.i2t_A2s;
      bus[static_cast<std::size_t>(io.force_true)] = f[k];
      if (io.temp_on >= 0) {
        bus[static_cast<std::size_t>(io.temp_on)] = io.thermal_on.state().T_winding_C;
        bus[static_cast<std::size_t>(io.housing_on)] = io.thermal_on.state().T_housing_C;
      }
      if (io.temp_off >= 0) {
        bus[static_cast<std::size_t>(io.temp_off)] = io.thermal_off.state().T_winding_C;
        bus[static_cast<std::size_t>(io.housing_off)] = io.thermal_off.state().T_housing_C;
      }
    }
  }

  std::string state_text() const {
    std::string s;
    for (int j = 0; j < nj && j < static_cast<int>(q.size()); ++j)
      s += fmt::format("{}{} q = {:.4g} rad, qd = {:.4g} rad/s", j ? "; " : "", plant.joint_names()[static_cast<std::size_t>(j)], q[j], qd[j]);
    return s;
  }
};

Simulation::Simulation(model::Plant& plant, SimulationSpec spec) : impl_(std::make_unique<Impl>(plant, std::move(spec))) {}
Simulation::~Simulation() = default;

std::vector<std::string> Simulation::signal_names() const { return impl_->names; }
std::vector<long long> Simulation::controller_steps() const {
  std::vector<long long> r;
  for (const auto& c : impl_->ctrls) r.push_back(c.steps);
  return r;
}
std::vector<unsigned long long> Simulation::controller_clamp_events() const {
  std::vector<unsigned long long> r;
  for (const auto& c : impl_->ctrls) r.push_back(c.spec.controller->clamp_events());
  return r;
}

std::map<std::string, VelocityExcess> Simulation::velocity_limit_exceeded() const {
  std::map<std::string, VelocityExcess> out;
  for (std::size_t j = 0; j < impl_->velocity_excess.size(); ++j)
    if (impl_->velocity_excess[j].samples > 0) out[impl_->plant.joint_names()[j]] = impl_->velocity_excess[j];
  return out;
}

std::vector<std::string> Simulation::unfired_triggers() const {
  std::vector<std::string> out;
  for (std::size_t f = 0; f < impl_->triggers.size(); ++f) {
    const auto& tr = impl_->triggers[f];
    if (tr.signal < 0 || tr.start != kNever) continue;
    const ForceSpec& spec = impl_->spec.forces[f];
    out.push_back(fmt::format("{}force {} on link '{}': its trigger '{}' changed {} time(s), never reaching occurrence {}: the force was not applied",
                              at(spec.where), f, spec.link, spec.trigger->signal, tr.seen, spec.trigger->occurrence));
  }
  return out;
}

Log Simulation::run(const std::function<void(double)>& on_progress) {
  Impl& m = *impl_;
  if (!(m.spec.duration_s < kMaxDurationS))
    throw InputError(fmt::format("duration {} s is out of range (the event grid counts nanoseconds: below 1e9 s)", m.spec.duration_s));
  const Ns end = static_cast<Ns>(std::llround(m.spec.duration_s * 1e9));
  if (end <= 0) throw InputError(fmt::format("duration {} s is not positive", m.spec.duration_s));
  const Ns log_period = period_ns(m.spec.log_rate_hz, "log");
  const Ns t0 = static_cast<Ns>(std::llround(m.plant.time() * 1e9));

  const std::vector<int> logged = m.logged_signals();
  // The log is kept in memory: refuse one that cannot fit rather than fail midway.
  const double values = (static_cast<double>(end / log_period) + 2) * static_cast<double>(logged.size() + 1);
  constexpr double kMaxLogValues = 2.5e8;  // 2 GB of doubles
  if (values > kMaxLogValues)
    throw InputError(fmt::format("a {} s run logged at {} Hz would hold {:.3g} values ({:.3g} GB, the limit is 2 GB): shorten duration_s "
                                 "or lower log_rate_hz", m.spec.duration_s, m.spec.log_rate_hz, values, values * 8 / 1e9));
  Log log;
  for (int s : logged) log.add_column(m.names[static_cast<std::size_t>(s)], m.units[static_cast<std::size_t>(s)]);
  log.reserve(static_cast<std::size_t>(end / log_period) + 2);

  for (auto& c : m.ctrls) c.next_tick = 0;
  Ns next_log = 0;
  Ns next_progress = end / 100;
  Ns t = 0;
  m.refresh_true();
  m.init_triggers();
  m.apply_forces(0);
  for (;;) {
    // Events at t: publications, then controller ticks (then the forces the bus's changes start), then the log.
    for (auto& c : m.ctrls)
      if (c.publish_at == t) m.publish(c);
    bool tick = false;
    for (auto& c : m.ctrls) tick = tick || c.next_tick == t;
    // The true joint state (m.q, m.qd and their bus signals) was read right after the
    // plant last advanced (or before the loop): it is current at t.
    if (tick) {
      m.refresh_sensors(t);
      m.refresh_references(m.t_of(t));
      for (auto& c : m.ctrls) {
        if (c.next_tick != t) continue;
        m.step(c);
        c.next_tick += c.period;
        if (c.delay == 0) m.publish(c);
        else c.publish_at = t + c.delay;
      }
    }
    // References are evaluated at controller ticks and log ticks: one that drives a
    // command directly is held from log tick to log tick (zero-order hold at the log rate).
    if (tick || t == next_log) m.refresh_references(m.t_of(t));
    if (m.check_triggers(t)) m.apply_forces(t);  // a change published or referenced at t starts its forces at t
    m.apply_commands();
    if (t == next_log) {
      // Sensors are sampled at controller ticks only, so that what a controller sees
      // (and the sensors' noise sequence) does not depend on the log rate: the log
      // holds the last sample. With no controller (a reference drives the plant) they
      // are sampled at log ticks.
      if (m.ctrls.empty() && m.last_sensor_ns != t) m.refresh_sensors(t);
      m.refresh_references(m.t_of(t));
      m.fill_logged();
      log.begin_row(m.t_of(t));
      for (std::size_t c = 0; c < logged.size(); ++c) log.set(static_cast<int>(c) + 1, m.bus[static_cast<std::size_t>(logged[c])]);
      next_log += log_period;
    }
    if (on_progress && t >= next_progress) {
      on_progress(static_cast<double>(t) / static_cast<double>(end));
      next_progress += std::max<Ns>(end / 100, 1);
    }
    if (t >= end || m.down) break;
    Ns next = std::min(end, next_log);
    for (const auto& c : m.ctrls) next = std::min({next, c.next_tick, c.publish_at});
    try {
      m.plant.advance_to(m.t_of(t0 + next));
    } catch (model::ModelError& e) {  // the plant's own divergence: add the joints' state, keep the error
      m.refresh_true();
      e.append(" (" + m.state_text() + ")");
      throw;
    }
    m.advance_thermal(m.t_of(next - t));
    t = next;
    m.apply_forces(t);
    m.refresh_true();
    if (m.is_down()) {  // log this instant, then end
      m.down = true;
      next_log = t;
      continue;
    }
    for (int j = 0; j < m.nj; ++j)
      if (!std::isfinite(m.q[j]) || std::abs(m.qd[j]) > m.spec.max_joint_rate_rad_s)
        throw DivergenceError(fmt::format("simulation diverged at t = {:.6g} s: joint '{}' runs away ({})", m.t_of(t),
                                          m.plant.joint_names()[static_cast<std::size_t>(j)], m.state_text()));
    m.watch_velocity_limits();
  }
  if (on_progress) on_progress(1.0);
  return log;
}

}  // namespace dmbd::sim
