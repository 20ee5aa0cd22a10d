// Co-simulation (dmbd::sim::Simulation), its signals and its log.
//
// The plant is the knee-only table robot of the shipped scenarios: DRACO's torso fixed
// 1.3 m above the table, every 1-dof joint but the left knee welded, the knee driven by
// its RFSEA. Controllers are tiny diagrams parsed from text (Diagram::parse) or the
// shipped controller diagrams, lowered at their rate. Runs are a few tens of
// milliseconds long: the knee plant runs several times faster than real time.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "robot_files.hpp"
#include "dmbd/blocks/error.hpp"
#include "dmbd/codegen/fixed.hpp"
#include "dmbd/codegen/interpreter.hpp"
#include "dmbd/codegen/loop_program.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/model/actuator.hpp"
#include "dmbd/model/plant.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/sim/log.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "dmbd/sim/signals.hpp"
#include "dmbd/sim/simulation.hpp"
#include "sim_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::sim::test::read_text;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;
using dmbd::InputError;
using dmbd::sim::ControllerSpec;
using dmbd::sim::DivergenceError;
using dmbd::sim::Log;
using dmbd::sim::ReferenceSpec;
using dmbd::sim::Scalar;
using dmbd::sim::Simulation;
using dmbd::sim::SimulationSpec;
using dmbd::sim::Source;

constexpr double kPi = 3.14159265358979323846;
const std::string kSourceDir = DMBD_SOURCE_DIR;

// The knee-only table robot (as robot: {name: draco, moving: [l_knee], actuators: [l_knee]} with the
// torso fixed at 1.3 m), the knee at q0.
std::unique_ptr<dmbd::model::Plant> knee_plant(double q0 = 1.0) {
  namespace m = dmbd::model;
  m::UrdfOptions uo;
  uo.load_meshes = false;  // no rendering, no contact: the meshes are not needed
  m::RobotDescription robot = m::load_urdf(std::string(DMBD_ROBOTS_DIR "/draco") + "/draco.urdf", uo);
  std::vector<std::pair<std::string, double>> freeze;
  for (const auto& j : robot.joints) {
    const bool one_dof = j.type == m::JointType::Revolute || j.type == m::JointType::Continuous || j.type == m::JointType::Prismatic;
    if (!one_dof || j.name == "l_knee") continue;
    freeze.emplace_back(j.name, j.has_limits ? std::clamp(0.0, j.lower, j.upper) : 0.0);
  }
  robot = m::freeze_joints(robot, freeze);
  m::PlantOptions po;
  po.base = m::BaseMode::Fixed;
  po.X_WB.translation() = Eigen::Vector3d(0, 0, 1.3);
  po.contact = false;
  for (const auto& a : dmbd::test::draco_actuators())
    if (a.joint == "l_knee") po.actuators.push_back(a);
  auto plant = std::make_unique<m::Plant>(robot, po);
  plant->reset();
  Eigen::VectorXd q = plant->joint_positions();
  q[plant->joint_index("l_knee")] = q0;
  plant->set_joint_positions(q);
  return plant;
}

std::shared_ptr<const dmbd::codegen::LoopProgram> lower_text(const std::string& yaml, double rate_hz) {
  const auto d = dmbd::diagrams::Diagram::parse(yaml, "<test>");
  dmbd::codegen::LowerOptions lo;
  lo.rate_hz = rate_hz;
  return std::make_shared<dmbd::codegen::LoopProgram>(dmbd::codegen::lower(*d, lo));
}

std::shared_ptr<const dmbd::codegen::LoopProgram> lower_file(const std::string& path, double rate_hz) {
  const auto d = dmbd::diagrams::Diagram::load(path);
  dmbd::codegen::LowerOptions lo;
  lo.rate_hz = rate_hz;
  if (d->discretization()) lo.method = *d->discretization();
  return std::make_shared<dmbd::codegen::LoopProgram>(dmbd::codegen::lower(*d, lo));
}

// y = k u.
std::string gain_diagram(double k, const std::string& unit_in = "A", const std::string& unit_out = "A") {
  std::ostringstream s;
  s.precision(17);
  s << "name: gain\n"
       "inputs:\n  u: {unit: "
    << unit_in << "}\noutputs:\n  y: {unit: " << unit_out << "}\nblocks:\n  K: {type: gain, k: " << k
    << "}\nconnections:\n  - u -> K\n  - K -> y\n";
  return s.str();
}

// A loop program on the bus (it runs at the rate it was lowered at).
ControllerSpec controller(const std::string& name, std::shared_ptr<const dmbd::codegen::LoopProgram> p, double delay_s,
                          std::vector<std::string> in, std::vector<std::string> out, Scalar scalar = Scalar::Double,
                          std::shared_ptr<const dmbd::codegen::FixedProgram> fixed = nullptr) {
  ControllerSpec c;
  c.name = name;
  c.controller = dmbd::sim::loop_program_controller(std::move(p), scalar, std::move(fixed));
  c.delay_s = delay_s;
  c.inputs = std::move(in);
  c.outputs = std::move(out);
  return c;
}

// A reference that takes a different value at every millisecond (37 Hz is not a
// divisor of 1 kHz, and sin(2 pi 37 a) = sin(2 pi 37 b) has no solution with a, b
// distinct whole milliseconds below 1 s): a shifted copy cannot be mistaken for the
// original.
Source test_sine() {
  Source s;
  s.kind = Source::Kind::Sine;
  s.amplitude = 1.5;
  s.freq_hz = 37;
  s.offset = 0.25;
  return s;
}

// The knee reference of the closed-loop tests: 1 rad, stepping by 0.1 rad at 20 ms.
Source knee_step() {
  Source r;
  r.kind = Source::Kind::Steps;
  r.offset = 1.0;
  r.steps = {{0.02, 0.1}};
  return r;
}

Log run_gain(double delay_s, double log_rate_hz, double duration_s = 0.05) {
  auto plant = knee_plant();
  SimulationSpec spec;
  spec.references.push_back({"r", test_sine()});
  spec.controllers.push_back(controller("gain", lower_text(gain_diagram(2.0), 1000), delay_s, {"r"}, {"l_knee.current"}));
  spec.duration_s = duration_s;
  spec.log_rate_hz = log_rate_hz;
  Simulation sim(*plant, spec);
  return sim.run();
}

// ------------------------------------------------------------------------- signals

TEST(SimSignals, StepsHoldTheLastStepWhoseTimeHasPassed) {
  Source s;
  s.kind = Source::Kind::Steps;
  s.offset = 1.0;
  s.steps = {{0.5, 0.3}, {2.0, -0.1}};
  // Exact: the value is offset + one step value, no arithmetic on time.
  EXPECT_EQ(s.value(-1.0), 1.0);
  EXPECT_EQ(s.value(0.0), 1.0);
  EXPECT_EQ(s.value(0.4999), 1.0);
  EXPECT_EQ(s.value(0.5), 1.0 + 0.3);
  EXPECT_EQ(s.value(1.9999), 1.0 + 0.3);
  EXPECT_EQ(s.value(2.0), 1.0 - 0.1);  // not cumulative: the last step's value alone
  EXPECT_EQ(s.value(100.0), 1.0 - 0.1);
  EXPECT_EQ(s.frequency_hz(1.0), 0.0);
}

TEST(SimSignals, SineMatchesItsClosedForm) {
  Source s;
  s.kind = Source::Kind::Sine;
  s.offset = 0.5;
  s.amplitude = 2.0;
  s.freq_hz = 3.0;
  s.start_s = 1.0;
  s.duration_s = 2.0;
  // 1e-12 absolute: the same formula in double; the phase 2 pi f tau < 40 rad carries
  // rounding of a few 1e-15 into the sine.
  for (double t : {1.0, 1.01, 1.3, 1.77, 2.5, 2.999})
    EXPECT_NEAR(s.value(t), 0.5 + 2.0 * std::sin(2 * kPi * 3.0 * (t - 1.0)), 1e-12) << "t = " << t;
  EXPECT_EQ(s.value(0.999), 0.5);  // before the start: the offset
  EXPECT_EQ(s.value(3.001), 0.5);  // after start + duration: the offset
  EXPECT_EQ(s.frequency_hz(1.5), 3.0);

  // Cosine fade-in over ramp_s: half the amplitude half-way through the ramp, and the
  // full amplitude after it; symmetric fade-out before the end.
  s.ramp_s = 0.2;
  const double tau = 0.1;
  EXPECT_NEAR(s.value(1.0 + tau), 0.5 + 2.0 * 0.5 * std::sin(2 * kPi * 3.0 * tau), 1e-12);
  EXPECT_NEAR(s.value(1.0 + 0.25), 0.5 + 2.0 * std::sin(2 * kPi * 3.0 * 0.25), 1e-12);
  const double tau_end = 2.0 - 0.1;
  EXPECT_NEAR(s.value(1.0 + tau_end), 0.5 + 2.0 * 0.5 * std::sin(2 * kPi * 3.0 * tau_end), 1e-12);
}

TEST(SimSignals, ChirpFollowsTheExponentialSweep) {
  const double f0 = 0.5, f1 = 200.0, T = 20.0, start = 1.0;
  Source s;
  s.kind = Source::Kind::Chirp;
  s.amplitude = 3.0;
  s.offset = -1.0;
  s.f0_hz = f0;
  s.f1_hz = f1;
  s.duration_s = T;
  s.start_s = start;
  const double k = std::log(f1 / f0) / T;
  for (double tau : {0.25, 1.0, 5.0, 10.0, 15.5, 19.9}) {
    const double t = start + tau;
    // Instantaneous frequency f0 (f1/f0)^(tau/T): relative 1e-12 (pow against exp of a
    // product, a few ulps).
    const double f_expected = f0 * std::pow(f1 / f0, tau / T);
    EXPECT_NEAR(s.frequency_hz(t), f_expected, 1e-12 * f_expected) << "tau = " << tau;
    // The phase's derivative is 2 pi f(tau): central difference with h = 1e-6 s. The
    // truncation error h^2/6 phi''' is relative (h k)^2 / 6 ~ 1e-13; the rounding error
    // eps |phi| / h <= 2.2e-16 * 1.7e3 rad / 1e-6 s = 4e-7 rad/s against 2 pi f >= 3 rad/s:
    // relative 1e-6 is 10x that.
    const double h = 1e-6;
    const double dphi = (dmbd::sim::exponential_chirp_phase(f0, f1, T, tau + h) - dmbd::sim::exponential_chirp_phase(f0, f1, T, tau - h)) / (2 * h);
    EXPECT_NEAR(dphi / (2 * kPi), f_expected, 1e-6 * f_expected) << "tau = " << tau;
    // The closed-form phase 2 pi f0 T / ln(f1/f0) (exp(tau ln(f1/f0) / T) - 1): relative 1e-12.
    const double phase = 2 * kPi * f0 / k * (std::exp(k * tau) - 1);
    EXPECT_NEAR(dmbd::sim::exponential_chirp_phase(f0, f1, T, tau), phase, 1e-12 * phase);
    // The value: offset + amplitude sin(phase); the phase is below 1.7e3 rad, so its
    // rounding moves the sine by less than 1e-12.
    EXPECT_NEAR(s.value(t), -1.0 + 3.0 * std::sin(phase), 3.0 * 1e-11) << "tau = " << tau;
  }
  EXPECT_EQ(s.value(start - 0.01), -1.0);
  EXPECT_EQ(s.value(start + T + 0.01), -1.0);
  EXPECT_EQ(s.frequency_hz(start - 0.01), 0.0);
  EXPECT_NEAR(s.frequency_hz(start), f0, 1e-15);
  EXPECT_NEAR(s.frequency_hz(start + T), f1, 1e-12 * f1);
}

TEST(SimSignals, AListOfSourcesSums) {
  Source steps;
  steps.kind = Source::Kind::Steps;
  steps.offset = 1.0;
  steps.steps = {{0.5, 0.3}};
  Source sine;
  sine.kind = Source::Kind::Sine;
  sine.amplitude = 0.2;
  sine.freq_hz = 0.5;
  sine.start_s = 0.25;
  Source constant;
  constant.offset = -0.125;
  Source sum = steps;
  sum.plus = {sine, constant};
  for (double t : {0.0, 0.3, 0.5, 0.9, 3.7}) {
    // Three terms: at most 2 roundings of values below 2 in magnitude.
    EXPECT_NEAR(sum.value(t), steps.value(t) + sine.value(t) + constant.value(t), 1e-15) << "t = " << t;
    EXPECT_EQ(sum.own_value(t), steps.value(t));
  }
  EXPECT_NEAR(sum.value(1.0), 1.3 + 0.2 * std::sin(2 * kPi * 0.5 * 0.75) - 0.125, 1e-15);
}

// ------------------------------------------------------------------------- log

TEST(SimLog, CsvHeaderHasUnitsAndValuesRoundTripExactly) {
  Log log;
  const int a = log.add_column("l_knee.current", "A");
  const int b = log.add_column("l_knee.q", "rad");
  const std::vector<double> values = {0.1, 1.0 / 3.0, -2.5e17, 5e-324, 6.02214076e23, -0.0, std::nextafter(1.0, 2.0)};
  for (std::size_t k = 0; k < values.size(); ++k) {
    log.begin_row(static_cast<double>(k) * 1e-3);
    log.set(a, values[k]);
    log.set(b, -values[k] * kPi);
  }
  log.begin_row(1.0);  // a row whose cells are never set: NaN
  EXPECT_EQ(log.rows(), values.size() + 1);
  EXPECT_EQ(log.columns(), 3u);
  EXPECT_EQ(log.name(0), "t");
  EXPECT_EQ(log.unit(0), "s");
  EXPECT_EQ(log.find("l_knee.q"), b);
  EXPECT_EQ(log.find("nope"), -1);
  EXPECT_THROW(log.add_column("late", "A"), std::logic_error);
  try {
    (void)log.column("nope");
    ADD_FAILURE() << "no exception for a missing column";
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("nope"), std::string::npos) << e.what();
  }

  const std::string csv = log.to_csv();
  std::istringstream in(csv);
  std::string line;
  ASSERT_TRUE(std::getline(in, line));
  EXPECT_EQ(line, "t [s],l_knee.current [A],l_knee.q [rad]");
  for (std::size_t r = 0; r < log.rows(); ++r) {
    ASSERT_TRUE(std::getline(in, line)) << "row " << r;
    std::vector<double> cells;
    std::stringstream ls(line);
    std::string cell;
    while (std::getline(ls, cell, ',')) cells.push_back(std::strtod(cell.c_str(), nullptr));
    ASSERT_EQ(cells.size(), 3u) << line;
    for (int c = 0; c < 3; ++c) {
      const double v = log.column(c)[r];
      if (std::isnan(v)) {
        EXPECT_TRUE(std::isnan(cells[static_cast<std::size_t>(c)])) << line;
      } else {
        // Bit for bit (sign of zero included).
        EXPECT_EQ(std::memcmp(&v, &cells[static_cast<std::size_t>(c)], sizeof v), 0) << line << " column " << c;
      }
    }
  }
  EXPECT_FALSE(std::getline(in, line));
}

TEST(SimLog, DuplicateColumnIsRejected) {
  Log log;
  log.add_column("x", "m");
  EXPECT_THROW(log.add_column("x", "m"), std::logic_error);
  EXPECT_THROW(log.add_column("t", "s"), std::logic_error);
}

TEST(SimLog, WriteCsvIsAtomic) {
  TempDir dir;
  Log log;
  const int c = log.add_column("x", "m");
  for (int k = 0; k < 1000; ++k) {
    log.begin_row(k * 1e-3);
    log.set(c, std::sin(k * 0.1));
  }
  const std::string path = dir.file("log.csv");
  write_text(path, "an older file\n");
  log.write_csv(path);
  std::ifstream f(path, std::ios::binary);
  std::stringstream content;
  content << f.rdbuf();
  EXPECT_EQ(content.str(), log.to_csv());
  // Nothing but the file itself: no temporary left behind.
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path())) names.push_back(e.path().filename().string());
  EXPECT_EQ(names, std::vector<std::string>{"log.csv"});
}

// ------------------------------------------------------------------------- timing

// A pure gain at 1 kHz on a reference: with a 1 ms computation delay, the command
// logged at 1 kHz is exactly the delay-free command one sample later (and 0 before the
// first publication). The plant does not enter the command: exact equality.
TEST(SimTiming, OnePeriodDelayShiftsTheCommandByOneSample) {
  const Log now = run_gain(0.0, 1000);
  const Log late = run_gain(1e-3, 1000);
  ASSERT_EQ(now.rows(), 51u);  // 0.05 s at 1 kHz, t = 0 included
  ASSERT_EQ(late.rows(), now.rows());
  const auto& r = now.column("r");
  const auto& i0 = now.column("l_knee.current");
  const auto& i1 = late.column("l_knee.current");
  EXPECT_EQ(r, late.column("r"));
  for (std::size_t k = 0; k < now.rows(); ++k) {
    EXPECT_EQ(now.time()[k], static_cast<double>(k * 1000000) * 1e-9) << k;  // the ns grid
    EXPECT_EQ(i0[k], 2.0 * r[k]) << "delay 0, row " << k;              // y = 2 r, published at once
    EXPECT_EQ(i1[k], k == 0 ? 0.0 : i0[k - 1]) << "delay 1 ms, row " << k;
  }
  // The shifted command is not the same signal (the test can fail).
  EXPECT_NE(i1[10], i0[10]);
}

// Zero-order hold: logged at 4 kHz, the command of a 1 kHz controller changes only at
// its ticks (every 4th row) and holds in between; a half-period delay moves the
// changes by two rows.
TEST(SimTiming, CommandIsHeldBetweenControllerTicks) {
  const Log now = run_gain(0.0, 4000, 0.02);
  const Log half = run_gain(0.5e-3, 4000, 0.02);
  ASSERT_EQ(now.rows(), 81u);
  const auto& i0 = now.column("l_knee.current");
  const auto& ih = half.column("l_knee.current");
  const auto& r = now.column("r");
  for (std::size_t k = 0; k < now.rows(); ++k) {
    const std::size_t tick = 4 * (k / 4);
    EXPECT_EQ(i0[k], 2.0 * r[tick]) << "row " << k;  // sampled at the tick, held
    if (k % 4 == 0 && k > 0) {
      EXPECT_NE(i0[k], i0[k - 1]) << "row " << k;  // and it does change at ticks
    }
    // Published 0.5 ms (2 rows) after the tick.
    EXPECT_EQ(ih[k], k < 2 ? 0.0 : i0[4 * ((k - 2) / 4)]) << "row " << k;
  }
  // The reference itself is evaluated at every log tick (not held).
  EXPECT_NE(r[1], r[0]);
}

// Two controllers chained through a bus signal: an outer one at 1 kHz (gain 2, one
// period of delay) feeding "x.bus", an inner one at 2 kHz (gain 1/2, no delay) driving
// the current. Both gains are powers of two: the chain reproduces the reference
// exactly, one outer period late, sampled at the inner rate.
TEST(SimMultiRate, ChainedControllersAtTwoRates) {
  auto plant = knee_plant();
  SimulationSpec spec;
  spec.references.push_back({"r", test_sine()});
  spec.controllers.push_back(controller("outer", lower_text(gain_diagram(2.0), 1000), 1e-3, {"r"}, {"x.bus"}));
  spec.controllers.push_back(controller("inner", lower_text(gain_diagram(0.5), 2000), 0.0, {"x.bus"}, {"l_knee.current"}));
  spec.duration_s = 0.05;
  spec.log_rate_hz = 2000;
  Simulation sim(*plant, spec);
  const auto names = sim.signal_names();
  EXPECT_NE(std::find(names.begin(), names.end(), "x.bus"), names.end());
  const Log log = sim.run();
  // Steps: duration x rate, +1 for t = 0 (the tick at t = duration runs too).
  EXPECT_EQ(sim.controller_steps(), (std::vector<long long>{51, 101}));
  EXPECT_EQ(sim.controller_clamp_events(), (std::vector<unsigned long long>{0, 0}));
  ASSERT_EQ(log.rows(), 101u);
  // The log's columns follow the bus.
  ASSERT_EQ(log.columns(), names.size() + 1);
  for (std::size_t k = 0; k < names.size(); ++k) EXPECT_EQ(log.name(static_cast<int>(k) + 1), names[k]);
  const auto& r = log.column("r");  // r at row j is r(j / 2 kHz)
  const auto& x = log.column("x.bus");
  const auto& i = log.column("l_knee.current");
  for (std::size_t k = 0; k < log.rows(); ++k) {
    // The outer output computed at m ms is on the bus over [m + 1, m + 2) ms.
    const std::size_t m = k / 2;
    const double x_expected = m == 0 ? 0.0 : 2.0 * r[2 * (m - 1)];
    EXPECT_EQ(x[k], x_expected) << "row " << k;
    EXPECT_EQ(i[k], 0.5 * x_expected) << "row " << k;
  }
}

TEST(SimSetup, BadSpecificationsAreInputErrors) {
  auto plant = knee_plant();
  auto expect_error = [&](SimulationSpec spec, const std::string& needle) {
    try {
      Simulation sim(*plant, spec);
      (void)sim.run();
      ADD_FAILURE() << "no error; expected one mentioning '" << needle << "'";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(needle), std::string::npos) << e.what();
    }
  };
  const auto p1k = lower_text(gain_diagram(1.0), 1000);
  SimulationSpec spec;
  spec.duration_s = 0.01;
  spec.controllers = {controller("c", p1k, 0, {"no.such.signal"}, {"l_knee.current"})};
  expect_error(spec, "no.such.signal");
  // (A rate disagreeing with the program's cannot be given: the controller states its own.)
  spec.controllers = {controller("c", p1k, 2e-3, {"l_knee.q"}, {"l_knee.current"})};
  expect_error(spec, "delay");
  spec.controllers = {controller("c", p1k, 0, {"l_knee.q", "l_knee.qd"}, {"l_knee.current"})};
  expect_error(spec, "2 inputs bound for 1 controller inputs");
  spec.controllers = {controller("c", p1k, 0, {"r"}, {"l_knee.current"})};
  spec.references = {{"r", Source{}}, {"l_knee.current", Source{}}};
  expect_error(spec, "both drive 'l_knee.current'");
  spec.references.clear();
  // A controller output never overwrites a sensor in silence, nor another controller's.
  spec.controllers = {controller("c", p1k, 0, {"l_knee.q"}, {"l_knee.q_enc"})};
  expect_error(spec, "controller 'c': output bound to 'l_knee.q_enc', a signal the plant provides");
  spec.controllers = {controller("c", p1k, 0, {"l_knee.q"}, {"l_knee.current"}), controller("d", p1k, 0, {"l_knee.q"}, {"l_knee.current"})};
  expect_error(spec, "controllers 'c' and 'd' both drive 'l_knee.current'");
  spec.controllers = {controller("c", p1k, 0, {"l_knee.q"}, {"x"}), controller("d", p1k, 0, {"x"}, {"x"})};
  expect_error(spec, "controllers 'c' and 'd' both drive 'x'");
  spec.controllers.clear();
  spec.references = {{"l_knee.q", Source{}}};
  expect_error(spec, "already a bus signal");
  spec.references.clear();
  dmbd::sim::ForceSpec f;
  f.link = "no_such_link";
  spec.forces = {f};
  expect_error(spec, "no_such_link");
}

// simulation.hpp: "Throws InputError naming ... a rate that is not a whole number of
// nanoseconds". 1500 Hz is a period of 666666.67 ns, 3 kHz one of 333333.33 ns: run
// as given, the controller would tick at 1500.0008 Hz / 3000.003 Hz while its program
// was discretised at 1500 / 3000 Hz. 7 kHz (142857.14 ns) must be rejected the same way.
TEST(SimSetup, RateThatIsNotAWholeNumberOfNanosecondsIsRejected) {
  for (double rate : {7000.0, 3000.0, 1500.0}) {
    auto plant = knee_plant();
    SimulationSpec spec;
    spec.duration_s = 0.01;
    spec.controllers = {controller("c", lower_text(gain_diagram(1.0), rate), 0, {"l_knee.q"}, {"l_knee.current"})};
    try {
      Simulation sim(*plant, spec);
      ADD_FAILURE() << rate << " Hz accepted";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("whole number of nanoseconds"), std::string::npos) << e.what();
    }
  }
}

// ------------------------------------------------------------------------- determinism

// The same scenario with sensor noise (potentiometer noise in the loop, force noise)
// run twice gives the same log to the last bit; another seed does not.
TEST(SimDeterminism, NoisyRunsRepeatBitForBit) {
  TempDir dir;
  const std::string path = dir.file("noisy.yaml");
  auto scenario_text = [&](int seed) {
    return "name: noisy\n"
           "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], initial: {l_knee: 1.0}}\n"
           "sensors: {noise: true, seed: " +
           std::to_string(seed) +
           ", force_noise_N: 5}\n"
           "duration_s: 0.15\n"
           "log_rate_hz: 1000\n"
           "references:\n"
           "  q_d: {type: steps, offset: 1.0, steps: [[0.02, 0.1]]}\n"
           "controllers:\n"
           "  - name: position\n"
           "    diagram: " +
           kSourceDir +
           "/examples/diagrams/position_potentiometer_controller.yaml\n"
           "    rate_hz: 1000\n"
           "    delay_s: 0.001\n"
           "    inputs: {q_d: q_d, q_pot: l_knee.q_pot}\n"
           "    outputs: {i: l_knee.current}\n";
  };
  write_text(path, scenario_text(7));
  const auto s = dmbd::scenario::load_scenario(path);
  ASSERT_EQ(s.variants.size(), 1u);
  const auto a = dmbd::scenario::run_variant(s, s.variants[0], {});
  const auto b = dmbd::scenario::run_variant(s, s.variants[0], {});
  ASSERT_EQ(a.log.rows(), 151u);
  EXPECT_TRUE(a.log.to_csv() == b.log.to_csv()) << "two runs of the same scenario differ";
  EXPECT_EQ(a.controller_steps, b.controller_steps);
  EXPECT_EQ(a.integrator_steps, b.integrator_steps);
  // The noise is really on: the potentiometer reading is not the true angle, and a
  // different seed changes it.
  const auto& q = a.log.column("l_knee.q");
  const auto& pot = a.log.column("l_knee.q_pot");
  double max_dev = 0;
  for (std::size_t k = 0; k < q.size(); ++k) max_dev = std::max(max_dev, std::abs(pot[k] - q[k]));
  EXPECT_GT(max_dev, 1e-4);  // noise 2e-3 rad and a 1.6e-3 rad ADC step
  write_text(path, scenario_text(8));
  const auto s2 = dmbd::scenario::load_scenario(path);
  const auto c = dmbd::scenario::run_variant(s2, s2.variants[0], {});
  EXPECT_NE(c.log.column("l_knee.q_pot"), a.log.column("l_knee.q_pot"));
}

// ------------------------------------------------------------------------- interpreter cross-check

struct ClosedLoop {
  Log log;
  std::vector<long long> steps;
};

// The encoder PD (controller 1) on the knee: a 0.1 rad step at 20 ms, exact sensors.
ClosedLoop run_encoder_pd(Scalar scalar, double delay_s, bool noise, double duration_s = 0.2) {
  const std::string file = kSourceDir + "/examples/diagrams/position_encoder_controller.yaml";
  auto program = lower_file(file, 1000);
  auto plant = knee_plant();
  SimulationSpec spec;
  spec.references.push_back({"q_d", knee_step()});
  std::shared_ptr<const dmbd::codegen::FixedProgram> fixed;
  if (scalar == Scalar::Fixed) {
    const auto d = dmbd::diagrams::Diagram::load(file);
    std::vector<std::pair<double, double>> ranges;
    for (const auto& in : d->inputs()) ranges.push_back(*in.range);
    fixed = std::make_shared<dmbd::codegen::FixedProgram>(dmbd::codegen::make_fixed(*program, ranges, 32));
  }
  spec.controllers.push_back(controller("position", program, delay_s, {"q_d", "l_knee.q_enc"}, {"l_knee.current"}, scalar, fixed));
  spec.duration_s = duration_s;
  spec.log_rate_hz = 1000;
  spec.sensor_noise = noise;
  Simulation sim(*plant, spec);
  ClosedLoop out{sim.run(), sim.controller_steps()};
  return out;
}

// The logged command equals the interpreter stepped by hand on the logged inputs (the
// sensor readings are sampled at the controller tick, which is also the log tick).
TEST(SimInterpreter, LoggedCommandsEqualTheInterpreterOnTheLoggedInputs) {
  const std::string file = kSourceDir + "/examples/diagrams/position_encoder_controller.yaml";
  const auto program = lower_file(file, 1000);
  for (double delay : {0.0, 1e-3}) {
    const ClosedLoop run = run_encoder_pd(Scalar::Double, delay, /*noise=*/true);
    const auto& qd = run.log.column("q_d");
    const auto& qm = run.log.column("l_knee.q_enc");
    const auto& i = run.log.column("l_knee.current");
    dmbd::codegen::Interpreter<double> interp(*program);
    std::vector<double> y(run.log.rows());
    for (std::size_t k = 0; k < run.log.rows(); ++k) {
      const double u[2] = {qd[k], qm[k]};
      interp.step(u, &y[k]);
    }
    const int shift = delay > 0 ? 1 : 0;
    for (std::size_t k = 0; k < run.log.rows(); ++k)
      ASSERT_EQ(i[k], k < static_cast<std::size_t>(shift) ? 0.0 : y[k - static_cast<std::size_t>(shift)]) << "delay " << delay << ", row " << k;
    // The loop did something: the step saturated the current and the knee moved.
    EXPECT_EQ(*std::max_element(i.begin(), i.end()), 22.0);
    EXPECT_GT(run.log.column("l_knee.q").back(), 1.05);
  }
}

// Float and fixed point: the logged command equals that interpreter replayed on the
// logged inputs (exact), and the closed loop stays close to the double one.
TEST(SimInterpreter, FloatAndFixedRunAndStayCloseToDouble) {
  const std::string file = kSourceDir + "/examples/diagrams/position_encoder_controller.yaml";
  const auto program = lower_file(file, 1000);
  const ClosedLoop dbl = run_encoder_pd(Scalar::Double, 1e-3, false);
  const ClosedLoop flt = run_encoder_pd(Scalar::Float, 1e-3, false);
  const ClosedLoop fix = run_encoder_pd(Scalar::Fixed, 1e-3, false);

  // Replays.
  {
    dmbd::codegen::Interpreter<float> interp(*program);
    const auto& qd = flt.log.column("q_d");
    const auto& qm = flt.log.column("l_knee.q_enc");
    const auto& i = flt.log.column("l_knee.current");
    float y = 0;
    for (std::size_t k = 0; k + 1 < flt.log.rows(); ++k) {
      const float u[2] = {static_cast<float>(qd[k]), static_cast<float>(qm[k])};
      interp.step(u, &y);
      ASSERT_EQ(i[k + 1], static_cast<double>(y)) << "float, row " << k + 1;
    }
  }
  {
    const auto d = dmbd::diagrams::Diagram::load(file);
    std::vector<std::pair<double, double>> ranges;
    for (const auto& in : d->inputs()) ranges.push_back(*in.range);
    const auto fixed = dmbd::codegen::make_fixed(*program, ranges, 32);
    dmbd::codegen::FixedInterpreter interp(*program, fixed);
    const auto& qd = fix.log.column("q_d");
    const auto& qm = fix.log.column("l_knee.q_enc");
    const auto& i = fix.log.column("l_knee.current");
    double y = 0;
    for (std::size_t k = 0; k + 1 < fix.log.rows(); ++k) {
      const double u[2] = {qd[k], qm[k]};
      interp.step_real(u, &y);
      ASSERT_EQ(i[k + 1], y) << "fixed, row " << k + 1;
    }
  }

  // Closed loop against double. The float program rounds its inputs to 24 bits
  // (6e-8 rad near 1 rad) and its arithmetic to float; the PD loop turns a measurement
  // error into a joint-angle error of the same order (measured: 1.4e-7 rad). The 32-bit
  // fixed program's input LSB is 2^-30 ~ 1e-9 rad (range +-1.07 rad, one bit of
  // headroom) (measured: 8e-9 rad). Tolerances 1e-5 rad (float) and 1e-6 rad (fixed):
  // about 100x the expected effect, and 1e-4 and 1e-5 of the 0.1 rad step.
  const auto& q = dbl.log.column("l_knee.q");
  double dev_f = 0, dev_x = 0;
  for (std::size_t k = 0; k < q.size(); ++k) {
    dev_f = std::max(dev_f, std::abs(flt.log.column("l_knee.q")[k] - q[k]));
    dev_x = std::max(dev_x, std::abs(fix.log.column("l_knee.q")[k] - q[k]));
  }
  EXPECT_LT(dev_f, 1e-5) << "float";
  EXPECT_LT(dev_x, 1e-6) << "fixed";
  EXPECT_EQ(flt.steps, dbl.steps);
  EXPECT_EQ(fix.steps, dbl.steps);
  // And the arithmetic really differs (the option is not ignored).
  EXPECT_NE(flt.log.column("l_knee.current"), dbl.log.column("l_knee.current"));
  EXPECT_NE(fix.log.column("l_knee.current"), dbl.log.column("l_knee.current"));
  std::printf("closed-loop max |q - q_double|: float %.3g rad, fixed %.3g rad\n", dev_f, dev_x);
}

// ------------------------------------------------------------------------- divergence

// Positive feedback from the knee angle to the knee torque with a huge gain: the run
// diverges and says when and which joint.
TEST(SimDivergence, RunawayIsADivergenceErrorNamingTimeAndJoint) {
  auto plant = knee_plant();
  SimulationSpec spec;
  spec.controllers.push_back(controller("runaway", lower_text(gain_diagram(1e6, "rad", "N m"), 1000), 0, {"l_knee.q"}, {"l_knee.torque"}));
  spec.duration_s = 1.0;
  Simulation sim(*plant, spec);
  try {
    (void)sim.run();
    FAIL() << "no divergence";
  } catch (const DivergenceError& e) {
    const std::string msg = e.what();
    EXPECT_NE(msg.find("t = "), std::string::npos) << msg;
    EXPECT_NE(msg.find("l_knee"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
    // The time named is inside the run (it diverges within the first few ticks).
    const double t = std::atof(msg.c_str() + msg.find("t = ") + 4);
    EXPECT_GT(t, 0.0) << msg;
    EXPECT_LT(t, 1.0) << msg;
  }
}

// Logging observes the run; it must not change it. The loop is controller 2 (PD on the
// filtered, noisy potentiometer) at 1 kHz; the same run logged at 1 kHz and at 4 kHz
// (extra log ticks between the controller's) must agree at the common instants.
// Tolerance 1e-6 rad: without sensor noise the two runs differ only by the integrator
// stopping at the extra log instants (error control at accuracy 1e-5), measured at
// 2e-8 rad; 1e-6 rad is 50x that, and a thousandth of the 1 mrad effect of the
// potentiometer's noise.
TEST(SimLogging, LogRateDoesNotChangeWhatTheControllerSees) {
  for (bool noise : {false, true}) {
    auto run = [&](double log_rate) {
      auto program = lower_file(kSourceDir + "/examples/diagrams/position_potentiometer_controller.yaml", 1000);
      auto plant = knee_plant();
      SimulationSpec spec;
      spec.references.push_back({"q_d", knee_step()});
      spec.controllers.push_back(controller("position", program, 1e-3, {"q_d", "l_knee.q_pot"}, {"l_knee.current"}));
      spec.duration_s = 0.3;
      spec.log_rate_hz = log_rate;
      spec.sensor_noise = noise;
      spec.seed = 5;
      Simulation sim(*plant, spec);
      return sim.run();
    };
    const Log a = run(1000), b = run(4000);
    ASSERT_EQ(b.rows(), 4 * (a.rows() - 1) + 1);
    double dq = 0, di = 0;
    for (std::size_t k = 0; k < a.rows(); ++k) {
      dq = std::max(dq, std::abs(a.column("l_knee.q")[k] - b.column("l_knee.q")[4 * k]));
      di = std::max(di, std::abs(a.column("l_knee.current")[k] - b.column("l_knee.current")[4 * k]));
    }
    EXPECT_LT(dq, 1e-6) << (noise ? "with" : "without") << " sensor noise; the command differs by up to " << di << " A";
  }
}

// A reference named like a command drives the plant directly (a current chirp for
// system identification); progress rises to 1.
TEST(SimCallbacks, ReferenceAsCommandAndProgress) {
  auto plant = knee_plant();
  SimulationSpec spec;
  Source chirp;
  chirp.kind = Source::Kind::Chirp;
  chirp.amplitude = 3.0;
  chirp.f0_hz = 5;
  chirp.f1_hz = 50;
  chirp.duration_s = 0.05;
  spec.references.push_back({"l_knee.current", chirp});
  spec.duration_s = 0.05;
  spec.log_rate_hz = 2000;
  Simulation sim(*plant, spec);
  std::vector<double> progress;
  const Log log = sim.run([&](double f) { progress.push_back(f); });
  ASSERT_FALSE(progress.empty());
  EXPECT_TRUE(std::is_sorted(progress.begin(), progress.end()));
  EXPECT_EQ(progress.back(), 1.0);
  const auto& t = log.time();
  const auto& i = log.column("l_knee.current");
  const auto& applied = log.column("l_knee.current_applied");
  for (std::size_t k = 0; k < log.rows(); ++k) {
    EXPECT_EQ(i[k], chirp.value(t[k])) << "row " << k;  // evaluated at the log tick
    EXPECT_EQ(applied[k], i[k]) << "row " << k;         // within the 22 A limit: applied as commanded
  }
}

}  // namespace
