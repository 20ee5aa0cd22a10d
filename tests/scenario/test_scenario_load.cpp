// Scenarios: loading (errors with file:line), variants and matrices, run directories
// (run_scenario, read_run), the `dmbd simulate` command line, and end-to-end checks of
// the shipped scenarios against what the paper reports. Reports and frames drawn from
// runs: tests/report/.
//
// Scenarios are written into a temporary folder; they run the knee-only table robot
// (robot: {name: draco, moving: [l_knee], actuators: [l_knee]}) for a few tens of milliseconds.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "dmbd/blocks/error.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/scenario/run_directory.hpp"
#include "dmbd/control/balance_controller.hpp"
#include "dmbd/control/osc_controller.hpp"
#include "dmbd/scenario/evaluate.hpp"
#include "dmbd/scenario/scenario.hpp"
#include "sim_test_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::sim::test::read_text;
using dmbd::sim::test::TempDir;
using dmbd::sim::test::write_text;
using dmbd::InputError;
using dmbd::scenario::load_scenario;
using dmbd::scenario::Scenario;

const std::string kSourceDir = DMBD_SOURCE_DIR;
const std::string kEncoderController = kSourceDir + "/examples/diagrams/position_encoder_controller.yaml";

// Comma-separated cells, empty ones (also trailing) kept.
std::vector<std::string> split_csv(const std::string& line) {
  std::vector<std::string> cells(1);
  for (char c : line) {
    if (c == ',') cells.emplace_back();
    else cells.back() += c;
  }
  return cells;
}

// A valid scenario: the encoder PD holding the knee at 1 rad. Error cases edit one line.
std::string base_scenario() {
  return "name: knee_hold\n"
         "robot:\n"
         "  name: draco\n"
         "  base: fixed\n"
         "  base_pose: {xyz: [0, 0, 1.3]}\n"
         "  moving: [l_knee]\n"
         "  actuators: [l_knee]\n"
         "  initial: {l_knee: 1.0}\n"
         "duration_s: 0.05\n"
         "log_rate_hz: 1000\n"
         "references:\n"
         "  q_d: {type: steps, offset: 1.0, steps: [[0.01, 0.05]]}\n"
         "controllers:\n"
         "  - name: position\n"
         "    diagram: " +
         kEncoderController +
         "\n"
         "    rate_hz: 1000\n"
         "    delay_s: 0.001\n"
         "    inputs: {q_d: q_d, q_m: l_knee.q_enc}\n"
         "    outputs: {i: l_knee.current}\n";
}

std::string replace_line(std::string text, const std::string& old_line, const std::string& new_lines) {
  const auto at = text.find(old_line + "\n");
  if (at == std::string::npos) throw std::logic_error("no line '" + old_line + "'");
  return text.replace(at, old_line.size(), new_lines);
}

// 1-based number of the first line containing `marker`.
int line_of(const std::string& text, const std::string& marker) {
  const auto at = text.find(marker);
  if (at == std::string::npos) throw std::logic_error("no marker '" + marker + "'");
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

// Loads the scenario and runs each variant for 2 ms (some mistakes can only be seen
// once the robot and the controllers are built); the InputError's message, or "".
std::string scenario_error(const std::string& path, const std::string& yaml) {
  write_text(path, yaml);
  try {
    const Scenario s = load_scenario(path);
    dmbd::scenario::RunOptions o;
    o.duration_s = 0.002;
    for (const auto& v : s.variants) (void)dmbd::scenario::run_variant(s, v, o);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

struct ErrorCase {
  const char* what;
  std::string yaml;
  std::string marker;    // text on the line the message must name
  std::string expected;  // text the message must contain
};

void check_error(const std::string& path, const ErrorCase& c) {
  SCOPED_TRACE(c.what);
  const std::string msg = scenario_error(path, c.yaml);
  ASSERT_FALSE(msg.empty()) << "no error";
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
  const std::string where = path + ":" + std::to_string(line_of(c.yaml, c.marker)) + ":";
  EXPECT_EQ(msg.rfind(where, 0), 0u) << "expected the message to start with '" << where << "': " << msg;
  EXPECT_NE(msg.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << msg;
}

// ------------------------------------------------------------------------- loading

TEST(SimScenarioLoad, BaseScenarioLoadsAndRuns) {
  TempDir dir;
  const std::string path = dir.file("ok.yaml");
  write_text(path, base_scenario());
  const Scenario s = load_scenario(path);
  EXPECT_EQ(s.name, "knee_hold");
  EXPECT_EQ(s.file, path);
  ASSERT_EQ(s.variants.size(), 1u);
  EXPECT_EQ(s.variants[0].name, "base");
  EXPECT_EQ(s.variants[0].duration_s, 0.05);
  ASSERT_EQ(s.variants[0].controllers.size(), 1u);
  EXPECT_EQ(s.variants[0].controllers[0].diagram, kEncoderController);
  EXPECT_EQ(s.variants[0].controllers[0].delay_s, 0.001);
  EXPECT_TRUE(s.variants[0].robot.freeze_all_others);
  EXPECT_EQ(scenario_error(path, base_scenario()), "");
}

TEST(SimScenarioLoad, MalformedYaml) {
  TempDir dir;
  // A flow sequence closed by '}': the parser stops on that line.
  const std::string yaml = replace_line(base_scenario(), "  moving: [l_knee]", "  moving: [l_knee}");
  check_error(dir.file("s.yaml"), {"malformed YAML", yaml, "moving: [l_knee}", "malformed YAML"});
}

TEST(SimScenarioLoad, UnknownKey) {
  TempDir dir;
  const std::string yaml = replace_line(base_scenario(), "duration_s: 0.05", "durations: 0.05");
  check_error(dir.file("s.yaml"), {"unknown key", yaml, "durations:", "unknown key 'durations'"});
  const std::string yaml2 = replace_line(base_scenario(), "    rate_hz: 1000", "    rate: 1000");
  check_error(dir.file("s.yaml"), {"unknown controller key", yaml2, "rate: 1000", "unknown key 'rate'"});
}

TEST(SimScenarioLoad, UnknownSourceType) {
  TempDir dir;
  const std::string yaml = replace_line(base_scenario(), "  q_d: {type: steps, offset: 1.0, steps: [[0.01, 0.05]]}",
                                        "  q_d: {type: square, offset: 1.0, steps: [[0.01, 0.05]]}");
  check_error(dir.file("s.yaml"), {"unknown source type", yaml, "square", "unknown source type 'square'"});
}

TEST(SimScenarioLoad, MatrixValueWithoutName) {
  TempDir dir;
  const std::string yaml = base_scenario() +
                           "matrix:\n"
                           "  load:\n"
                           "    - name: light\n"
                           "    - {duration_s: 0.2}\n";
  check_error(dir.file("s.yaml"), {"matrix value without a name", yaml, "- {duration_s: 0.2}", "needs a 'name'"});
}

TEST(SimScenarioLoad, DiagramFileThatDoesNotExist) {
  TempDir dir;
  const std::string yaml = replace_line(base_scenario(), "    diagram: " + kEncoderController, "    diagram: no_such_controller.yaml");
  check_error(dir.file("s.yaml"), {"missing diagram", yaml, "no_such_controller.yaml", "does not exist"});
}

// The next ones are only found once the robot and the controllers are built
// (run_variant); they must still name the line of the scenario that is wrong.
TEST(SimScenarioLoad, ControllerInputBoundToNothing) {
  TempDir dir;
  const std::string yaml = replace_line(base_scenario(), "    inputs: {q_d: q_d, q_m: l_knee.q_enc}", "    inputs: {q_d: q_d, q_m: l_knee.q_encoder}");
  check_error(dir.file("s.yaml"), {"input bound to nothing", yaml, "l_knee.q_encoder", "'l_knee.q_encoder'"});
}

TEST(SimScenarioLoad, JointThatDoesNotExist) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  check_error(path, {"moving", replace_line(base_scenario(), "  moving: [l_knee]", "  moving: [l_knee, l_kneecap]"), "l_kneecap",
                     "'l_kneecap'"});
  check_error(path, {"initial", replace_line(base_scenario(), "  initial: {l_knee: 1.0}", "  initial: {l_knee: 1.0, l_kneecap: 0.5}"),
                     "l_kneecap", "'l_kneecap'"});
  check_error(path, {"lock", replace_line(base_scenario(), "  initial: {l_knee: 1.0}", "  initial: {l_knee: 1.0}\n  lock: {l_kneecap: 0.5}"),
                     "l_kneecap", "'l_kneecap'"});
}

TEST(SimScenarioLoad, FreezeOutsideJointLimits) {
  TempDir dir;
  // The knee's limits are [0, 2.14] rad (draco.urdf); the ankle is welded here at 5 rad.
  const std::string yaml = replace_line(base_scenario(), "  initial: {l_knee: 1.0}", "  initial: {l_knee: 1.0}\n  freeze: {l_ankle: 5.0}");
  check_error(dir.file("s.yaml"), {"freeze outside limits", yaml, "l_ankle: 5.0", "outside its limits"});
}

TEST(SimScenarioLoad, ControllerPortThatTheDiagramLacks) {
  TempDir dir;
  const std::string yaml =
      replace_line(base_scenario(), "    inputs: {q_d: q_d, q_m: l_knee.q_enc}", "    inputs: {q_d: q_d, q_m: l_knee.q_enc, q_x: l_knee.q}");
  check_error(dir.file("s.yaml"), {"unknown port", yaml, "q_x: l_knee.q", "has no input 'q_x'"});
}

// Issue 28, row 17: a diagram port wider than one element did not bind (one bus
// signal per port: "1 inputs bound for 2 controller inputs" at the controller). A
// list binds element by element, in order; a list of the wrong length (or one signal
// for a wider port) is one error on the binding's line.
const char* const kPairDiagram =
    "name: pair\n"
    "inputs:\n  q: {unit: rad, size: 2}\n"
    "outputs:\n  y: {size: 2}\n"
    "blocks:\n  K: {type: gain, k: [[0, 1], [2, 0]]}\n"
    "connections:\n  - q -> K\n  - K -> y\n";

std::string pair_scenario(const std::string& inputs, const std::string& outputs) {
  return "name: pair_binding\n"
         "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], "
         "initial: {l_knee: 1.0}, lock: {l_knee: 1.0}}\n"
         "duration_s: 0.02\n"
         "log_rate_hz: 1000\n"
         "log: [probe_a, probe_b]\n"
         "references:\n  q_d: 0.25\n"
         "controllers:\n"
         "  - name: pair\n"
         "    diagram: pair.yaml\n"
         "    rate_hz: 1000\n"
         "    inputs: " + inputs + "\n"
         "    outputs: " + outputs + "\n";
}

// Issue 28, row 10: controller 1 with D_q: 0 (a P-only position loop) was refused
// when the scenario lowered it ("an improper transfer function has no second-order
// sections", no line). It runs, and the knee follows the reference's step from 1 to
// 1.05 rad at 10 ms upwards as a P loop does (1.017 rad at 50 ms when written: above
// 1.005, below the 1.06 an overshoot of 20 % would reach).
TEST(SimScenarioLoad, ControllerWithItsDerivativeGainAtZeroRuns) {
  TempDir dir;
  const std::string path = dir.file("p_only.yaml");
  write_text(path, replace_line(base_scenario(), "    rate_hz: 1000", "    rate_hz: 1000\n    parameters: {D_q: 0}"));
  const Scenario s = load_scenario(path);
  ASSERT_EQ(s.variants[0].controllers[0].parameters.size(), 1u);
  const auto r = dmbd::scenario::run_variant(s, s.variants[0], {});
  const auto& q = r.log.column("l_knee.q");
  ASSERT_FALSE(q.empty());
  EXPECT_GT(q.back(), 1.005);
  EXPECT_LT(q.back(), 1.06);
}

// A controller its diagram cannot be lowered for (a discrete diagram at another rate)
// is one error at the controller's line (before, the lowering's message had no line).
TEST(SimScenarioLoad, AControllerThatCannotBeLoweredIsLocated) {
  TempDir dir;
  write_text(dir.file("discrete.yaml"),
             "name: discrete\nsample_time: 0.002\ninputs:\n  q_d: {}\n  q_m: {}\noutputs:\n  i: {}\n"
             "blocks:\n  e: {type: sum, signs: \"+-\"}\nconnections: [q_d -> e.in1, q_m -> e.in2, e -> i]\n");
  const std::string yaml = replace_line(base_scenario(), "  - name: position", "  - name: position_at_500_hz") ;
  const std::string with = replace_line(yaml, "    diagram: " + kEncoderController, "    diagram: discrete.yaml");
  check_error(dir.file("s.yaml"), {"discrete at another rate", with, "- name: position_at_500_hz",
                                   "controller 'position_at_500_hz': diagram 'discrete' is discrete at 500"});
}

TEST(SimScenarioLoad, AWidePortBindsElementByElement) {
  TempDir dir;
  write_text(dir.file("pair.yaml"), kPairDiagram);
  const std::string path = dir.file("s.yaml");
  write_text(path, pair_scenario("{q: [l_knee.q, q_d]}", "{y: [probe_a, probe_b]}"));
  const Scenario s = load_scenario(path);
  const auto r = dmbd::scenario::run_variant(s, s.variants[0], {});
  // y = K q = [q_d, 2 q]: probe_a is the reference exactly; probe_b twice the locked
  // knee angle (held to < 1 mrad by the lock's stiff constraint: 2e-3).
  const auto& a = r.log.column("probe_a");
  const auto& b = r.log.column("probe_b");
  ASSERT_GE(a.size(), 10u);
  EXPECT_EQ(a.back(), 0.25);
  EXPECT_NEAR(b.back(), 2.0, 2e-3);
  // Bound the other way round, the elements swap: order is the list's.
  write_text(path, pair_scenario("{q: [q_d, l_knee.q]}", "{y: [probe_b, probe_a]}"));
  const Scenario t = load_scenario(path);
  const auto r2 = dmbd::scenario::run_variant(t, t.variants[0], {});  // kept: the column lives in it
  EXPECT_NEAR(r2.log.column("probe_a").back(), 0.5, 1e-15);  // 2 q_d
}

TEST(SimScenarioLoad, AWidePortBoundToTheWrongNumberOfSignalsIsOneLocatedError) {
  TempDir dir;
  write_text(dir.file("pair.yaml"), kPairDiagram);
  const std::string path = dir.file("s.yaml");
  check_error(path, {"one signal for two elements", pair_scenario("{q: l_knee.q}", "{y: [probe_a, probe_b]}"), "inputs: {q: l_knee.q}",
                     "pair.yaml has 2 elements: expected a list of 2 bus signals, one per element in order, got 1 bus signal"});
  check_error(path, {"three signals for two elements", pair_scenario("{q: [l_knee.q, q_d]}", "{y: [probe_a, probe_b, probe_a]}"),
                     "outputs: {y: [probe_a", "pair.yaml has 2 elements: expected a list of 2 bus signals, one per element in order, got 3"});
  check_error(path, {"empty list", pair_scenario("{q: []}", "{y: [probe_a, probe_b]}"), "inputs: {q: []}",
                     "controller 'pair'.inputs.q: expected a bus signal, or a list of them (one per element)"});
  // A list for a port of one element.
  check_error(path, {"two signals for one element",
                     replace_line(base_scenario(), "    inputs: {q_d: q_d, q_m: l_knee.q_enc}", "    inputs: {q_d: [q_d, q_d], q_m: l_knee.q_enc}"),
                     "inputs: {q_d: [q_d, q_d]", "input 'q_d' of " + kEncoderController + " has 1 element: expected one bus signal, got 2"});
}

TEST(SimScenarioLoad, ThermalWithoutCooling) {
  TempDir dir;
  const std::string yaml = replace_line(base_scenario(), "duration_s: 0.05", "duration_s: 0.05\nthermal: {}");
  check_error(dir.file("s.yaml"), {"thermal without cooling", yaml, "thermal: {}", "expected 'cooling"});
}

TEST(SimScenarioLoad, ListEntryWithoutItsRequiredKey) {
  TempDir dir;
  const std::string yaml = replace_line(base_scenario(), "  initial: {l_knee: 1.0}", "  initial: {l_knee: 1.0}\n  payloads: [{mass_kg: 2}]");
  check_error(dir.file("s.yaml"), {"payload without link", yaml, "payloads:", "expected 'link'"});
  const std::string yaml2 = base_scenario() + "forces:\n  - {link: l_foot}\n";
  check_error(dir.file("s.yaml"), {"force without source", yaml2, "{link: l_foot}", "expected 'source'"});
}

// The experiment's keys are those of its type: a misspelt window must not silently
// fall back to its default.
TEST(SimScenarioLoad, IntegrationModeAndStepAreChecked) {
  TempDir dir;
  const std::string base = base_scenario();
  check_error(dir.file("s.yaml"), {"unknown mode", base + "integration: {mode: implicit}\n", "mode: implicit", "expected fixed or accurate"});
  check_error(dir.file("s.yaml"), {"step too long", base + "integration: {mode: fixed, step_s: 0.05}\n", "step_s: 0.05", "longer than 10 ms"});
  check_error(dir.file("s.yaml"), {"unknown key", base + "integration: {mode: fixed, dt: 0.001}\n", "dt: 0.001", "unknown key 'dt'"});
  // A valid one reaches the variant (and a variant may override it).
  write_text(dir.file("ok.yaml"), base + "integration: {mode: fixed, step_s: 0.00025}\nvariants:\n  - name: fixed\n"
                                         "  - name: accurate\n    integration: {mode: accurate, accuracy: 1.0e-6}\n");
  const Scenario s = load_scenario(dir.file("ok.yaml"));
  ASSERT_EQ(s.variants.size(), 2u);
  EXPECT_EQ(s.variants[0].integration.mode, dmbd::model::Integration::Fixed);
  EXPECT_EQ(s.variants[0].integration.step_s, 0.00025);
  EXPECT_EQ(s.variants[1].integration.mode, dmbd::model::Integration::Accurate);
  EXPECT_EQ(s.variants[1].integration.accuracy, 1e-6);
}

// The knee following a step under the encoder PD for 0.5 s: the fixed 0.5 ms step and
// the accurate integrator give the same closed loop (joint angle within 1 mrad while it
// moves 0.044 rad; measured 0.39 mrad, in the first 50 ms where the elastomer mode rings
// and backward Euler damps it), the fixed one in exactly 2 steps a millisecond.
TEST(SimScenarioRun, FixedStepAndAccurateIntegrationAgreeOnTheKnee) {
  TempDir dir;
  write_text(dir.file("s.yaml"), base_scenario() + "variants:\n  - name: accurate\n  - name: fixed\n"
                                                 "    integration: {mode: fixed, step_s: 0.0005}\n");
  const Scenario s = load_scenario(dir.file("s.yaml"));
  dmbd::scenario::RunOptions o;
  o.duration_s = 0.5;
  const auto a = dmbd::scenario::run_variant(s, s.variants[0], o), f = dmbd::scenario::run_variant(s, s.variants[1], o);
  const auto& qa = a.log.column("l_knee.q");
  const auto& qf = f.log.column("l_knee.q");
  ASSERT_EQ(qa.size(), qf.size());
  double worst = 0;
  for (std::size_t k = 0; k < qa.size(); ++k) worst = std::max(worst, std::abs(qa[k] - qf[k]));
  std::printf("knee step, fixed 0.5 ms vs accurate: %.2e rad (moved %.3f rad)\n", worst, qa.back() - qa.front());
  EXPECT_GT(qa.back() - qa.front(), 0.03);  // the step moves the knee
  EXPECT_LT(worst, 1e-3);
  EXPECT_EQ(f.integrator_steps, 1000);
}

TEST(SimScenarioLoad, ExperimentKeysAreChecked) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  const std::string misspelt = base_scenario() + "experiment:\n  type: step_response\n  step_start: 0.01\n";
  check_error(path, {"misspelt experiment key", misspelt, "step_start: 0.01", "unknown key 'step_start'"});
  const std::string not_a_number = base_scenario() + "experiment:\n  type: step_response\n  step_end_s: late\n";
  check_error(path, {"experiment window not a number", not_a_number, "step_end_s: late", "expected a number"});
  const std::string wrong_type = base_scenario() + "experiment:\n  type: thermal\n  start_s: 0.1\n";
  check_error(path, {"key of another experiment", wrong_type, "start_s: 0.1", "unknown key 'start_s'"});
  // The shipped scenarios use only known keys (they load).
  for (const char* f : {"sysid_knee", "force_dob", "position_controllers", "thermal"})
    EXPECT_NO_THROW(load_scenario(kSourceDir + "/examples/scenarios/" + f + ".yaml")) << f;
}

// Issue 13 item 9: shapes that yaml-cpp used to throw on (exit 1, "internal error").
// Each is now an InputError naming file:line:col, found by load_scenario alone.
void check_load_error(const std::string& path, const ErrorCase& c) {
  SCOPED_TRACE(c.what);
  write_text(path, c.yaml);
  std::string msg;
  try {
    (void)load_scenario(path);
  } catch (const InputError& e) {
    msg = e.what();
  }  // any other exception fails the test
  ASSERT_FALSE(msg.empty()) << "no error";
  EXPECT_EQ(msg.find('\n'), std::string::npos) << "not one line: " << msg;
  const std::string where = path + ":" + std::to_string(line_of(c.yaml, c.marker)) + ":";
  EXPECT_EQ(msg.rfind(where, 0), 0u) << "expected the message to start with '" << where << "': " << msg;
  EXPECT_NE(msg.find(c.expected), std::string::npos) << "expected '" << c.expected << "' in: " << msg;
}

TEST(SimScenarioLoad, ListsGivenAsAMapOrEmptyAreLocatedErrors) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  const std::string robot = "  initial: {l_knee: 1.0}";
  for (const std::string value : {"{link: l_foot}", "", "{}", "''"}) {
    check_load_error(path, {"forces", base_scenario() + "forces: " + value + "\n", "forces:", "forces: expected a list"});
    check_load_error(path, {"payloads", replace_line(base_scenario(), robot, robot + "\n  payloads: " + value), "payloads:",
                            "robot.payloads: expected a list"});
    check_load_error(path, {"loads", replace_line(base_scenario(), robot, robot + "\n  loads: " + value), "loads:",
                            "robot.loads: expected a list"});
  }
  check_load_error(path, {"plots", base_scenario() + "plots: {file: a.png}\n", "plots:", "plots: expected a list"});
  // An empty list is still no forces.
  write_text(path, base_scenario() + "forces: []\n");
  EXPECT_TRUE(load_scenario(path).variants[0].forces.empty());
}

TEST(SimScenarioLoad, KeysThatAreNotNamesAreLocatedErrors) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  const std::string b = base_scenario();
  check_load_error(path, {"top level {}", b + "{}: 1\n", "{}: 1", "scenario: a key must be a name"});
  check_load_error(path, {"top level ~", b + "~: 1\n", "~: 1", "scenario: a key must be a name"});
  check_load_error(path, {"whole file", "{[1]: 2}\n", "{[1]: 2}", "scenario: a key must be a name"});
  check_load_error(path, {"references", replace_line(b, "  q_d: {type: steps, offset: 1.0, steps: [[0.01, 0.05]]}", "  [q_d]: 1.0"),
                          "[q_d]: 1.0", "references: a key must be a name"});
  check_load_error(path, {"matrix", b + "matrix:\n  {[1]: 2}: [{name: a}]\n", "{[1]: 2}", "matrix: a key must be a name"});
  check_load_error(path, {"controller inputs", replace_line(b, "    inputs: {q_d: q_d, q_m: l_knee.q_enc}", "    inputs: {[q_d]: q_d}"),
                          "inputs: {[q_d]", "controller 'position'.inputs: a key must be a name"});
  check_load_error(path, {"controller outputs", replace_line(b, "    outputs: {i: l_knee.current}", "    outputs: {{}: l_knee.current}"),
                          "outputs: {{}", "controller 'position'.outputs: a key must be a name"});
  check_load_error(path, {"controller parameters", replace_line(b, "    rate_hz: 1000", "    rate_hz: 1000\n    parameters: {[Kp]: 1}"),
                          "parameters:", "parameters: a key must be a name"});
  check_load_error(path, {"controller map", replace_line(b, "    rate_hz: 1000", "    {}: 1000"), "    {}: 1000",
                          "controller: a key must be a name"});
  check_load_error(path, {"robot.initial", replace_line(b, "  initial: {l_knee: 1.0}", "  initial: {[l_knee]: 1.0}"), "initial:",
                          "robot.initial: a key must be a name"});
  check_load_error(path, {"experiment", b + "experiment:\n  type: thermal\n  [k]: 1\n", "[k]: 1", "experiment: a key must be a name"});
}

TEST(SimScenarioLoad, WholeNumbersAreCheckedBeforeTheyAreConverted) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  const std::string b = base_scenario();
  // Converting 1e300 or -1 to an integer was undefined behaviour (UBSan in the fuzzer).
  check_load_error(path, {"frames.width", b + "frames: {width: 1e300}\n", "width: 1e300", "frames.width: expected a whole number from 1 to 16384"});
  check_load_error(path, {"frames.height", b + "frames: {height: 2.5}\n", "height: 2.5", "expected a whole number"});
  check_load_error(path, {"frames.max_frames", b + "frames: {max_frames: 1e12}\n", "max_frames: 1e12", "frames.max_frames: expected a whole number"});
  check_load_error(path, {"seed", b + "sensors: {seed: -1}\n", "seed: -1", "sensors.seed: expected a whole number from 0 to"});
  check_load_error(path, {"word_bits range", replace_line(b, "    rate_hz: 1000", "    rate_hz: 1000\n    word_bits: 1e300"), "word_bits:",
                          "controller.word_bits: expected a whole number from 16 to 32"});
  check_load_error(path, {"word_bits 17", replace_line(b, "    rate_hz: 1000", "    rate_hz: 1000\n    word_bits: 17"), "word_bits:",
                          "controller.word_bits: expected 16 or 32"});
  write_text(path, replace_line(b, "    rate_hz: 1000", "    rate_hz: 1000\n    word_bits: 16") + "frames: {width: 640, height: 480}\n");
  const Scenario s = load_scenario(path);
  EXPECT_EQ(s.variants[0].controllers[0].word_bits, 16);
  EXPECT_EQ(s.frames.width_px, 640);
}

// Found by fuzzing: a file name longer than the system allows made fs::exists throw
// std::filesystem::filesystem_error (exit 1, "internal error").
TEST(SimScenarioLoad, FileNamesTooLongForTheSystemAreLocatedErrors) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  const std::string long_name = std::string(300, 'a') + ".yaml";
  check_load_error(path, {"urdf", replace_line(base_scenario(), "  name: draco", "  urdf: " + long_name), "urdf:",
                          "robot.urdf: cannot use the file"});
  check_load_error(path, {"diagram", replace_line(base_scenario(), "    diagram: " + kEncoderController, "    diagram: " + long_name),
                          "diagram: aaa", "cannot use the file"});
  try {
    (void)load_scenario(dir.file(long_name));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("cannot read the scenario file"), std::string::npos) << e.what();
  }
}

TEST(SimScenarioLoad, AMatrixOfMoreThanAThousandVariantsIsALocatedError) {
  TempDir dir;
  // Ten axes of two values: 1024 variants (each a copy of the whole setup); an alias
  // makes such a file short, so the count is checked before the variants are built.
  std::string yaml = base_scenario() + "matrix:\n  a0: &two [{name: x}, {name: y}]\n";
  for (int k = 1; k < 10; ++k) yaml += "  a" + std::to_string(k) + ": *two\n";
  check_load_error(dir.file("s.yaml"), {"1024 variants", yaml, "a9: *two", "matrix.a9: 1024 variants (more than 1000)"});
}

// Issue 13, build 2: the scenario is read by the located YAML reader (base): numbers
// may be expressions, each limit is checked at the line that gives the value, every
// problem is reported.
TEST(SimScenarioLoad, ExpressionsAreAcceptedWhereverANumberIs) {
  TempDir dir;
  std::string yaml = replace_line(base_scenario(), "    rate_hz: 1000", "    rate_hz: 2*1000");
  yaml = replace_line(yaml, "    delay_s: 0.001", "    delay_s: 1/(2*1000)");
  yaml = replace_line(yaml, "  initial: {l_knee: 1.0}", "  initial: {l_knee: pi/3}");
  yaml = replace_line(yaml, "duration_s: 0.05", "duration_s: 50e-3");
  write_text(dir.file("s.yaml"), yaml);
  const Scenario s = load_scenario(dir.file("s.yaml"));
  EXPECT_EQ(s.variants[0].controllers[0].rate_hz, 2000.0);
  EXPECT_EQ(s.variants[0].controllers[0].delay_s, 0.0005);
  EXPECT_DOUBLE_EQ(s.variants[0].robot.initial[0].second, M_PI / 3);
  EXPECT_EQ(s.variants[0].duration_s, 0.05);
  check_load_error(dir.file("s.yaml"), {"unknown name", replace_line(base_scenario(), "    rate_hz: 1000", "    rate_hz: 2*khz"),
                                        "rate_hz: 2*khz", "controller.rate_hz: expected a number, got '2*khz' ('khz' is not a number or a known constant)"});
}

TEST(SimScenarioLoad, LimitsAreCheckedAtTheirLine) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  const std::string b = base_scenario();
  check_load_error(path, {"duration beyond the nanosecond grid", replace_line(b, "duration_s: 0.05", "duration_s: 1e12"),
                          "duration_s: 1e12", "duration_s: 1e+12 s is too long (the simulation counts nanoseconds: below 1e9 s)"});
  check_load_error(path, {"rate off the grid", replace_line(b, "    rate_hz: 1000", "    rate_hz: 1500.5"), "rate_hz: 1500.5",
                          "not a whole number of nanoseconds per period"});
  check_load_error(path, {"log rate above 1 GHz", replace_line(b, "log_rate_hz: 1000", "log_rate_hz: 3e9"), "log_rate_hz: 3e9",
                          "log_rate_hz: a rate of 3000000000 Hz is not a whole number"});
  check_load_error(path, {"delay longer than a period", replace_line(b, "    delay_s: 0.001", "    delay_s: 0.002"), "delay_s: 0.002",
                          "controller.delay_s: 0.002 s is longer than one period of 1000 Hz"});
  check_load_error(path, {"negative noise", b + "sensors: {force_noise_N: -1}\n", "force_noise_N: -1",
                          "sensors.force_noise_N: expected a number from 0 to"});
}

TEST(SimScenarioLoad, EveryProblemIsReportedEachAtItsLine) {
  TempDir dir;
  std::string yaml = replace_line(base_scenario(), "    rate_hz: 1000", "    rate_hz: fast\n    word_bits: 17");
  yaml = replace_line(yaml, "duration_s: 0.05", "duration_s: -1");
  write_text(dir.file("s.yaml"), yaml);
  try {
    (void)load_scenario(dir.file("s.yaml"));
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    const std::string msg = e.what();
    const std::string at = dir.file("s.yaml") + ":";
    EXPECT_EQ(std::count(msg.begin(), msg.end(), '\n'), 2) << msg;
    for (const std::string& line : {at + std::to_string(line_of(yaml, "rate_hz: fast")) + ":",
                                   at + std::to_string(line_of(yaml, "word_bits: 17")) + ":",
                                   at + std::to_string(line_of(yaml, "duration_s: -1")) + ":"})
      EXPECT_NE(msg.find(line), std::string::npos) << line << " in " << msg;
  }
}

TEST(SimScenarioLoad, FilesThatAreNotScenariosSayWhy) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  check_load_error(path, {"tab", replace_line(base_scenario(), "  moving: [l_knee]", "\tmoving: [l_knee]"), "\tmoving",
                          "tabs are not allowed in YAML indentation"});
  check_load_error(path, {"binary", base_scenario() + "x: \x1b[31m\n", "x: ", "the file is not text"});
  auto error_of = [](const std::string& p) {
    try {
      (void)load_scenario(p);
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_EQ(error_of(dir.path().string()), dir.path().string() + ": cannot read the scenario file: it is a directory");
  EXPECT_EQ(error_of(dir.file("none.yaml")), dir.file("none.yaml") + ": cannot read the scenario file: No such file or directory");
}

// ------------------------------------------------------------------------- variants and matrix

TEST(SimScenarioVariants, MatrixNamesOverridesAndCombinedCsv) {
  TempDir dir;
  const std::string path = dir.file("m.yaml");
  write_text(path, replace_line(base_scenario(), "duration_s: 0.05", "duration_s: 0.02") +
                       "matrix:\n"
                       "  ctrl:\n"
                       "    - name: a\n"
                       "    - name: b\n"
                       "      duration_s: 0.03\n"
                       "  load:\n"
                       "    - name: x\n"
                       "    - name: y\n"
                       "      robot: {name: draco, lock: {l_knee: 1.0}}\n");
  const Scenario s = load_scenario(path);
  ASSERT_EQ(s.variants.size(), 4u);
  const std::vector<std::string> names = {"a/x", "a/y", "b/x", "b/y"};
  for (std::size_t k = 0; k < 4; ++k) {
    const auto& v = s.variants[k];
    EXPECT_EQ(v.name, names[k]);
    ASSERT_EQ(v.axes.size(), 2u);
    EXPECT_EQ(v.axes[0], (std::pair<std::string, std::string>("ctrl", names[k].substr(0, 1))));
    EXPECT_EQ(v.axes[1], (std::pair<std::string, std::string>("load", names[k].substr(2, 1))));
    EXPECT_EQ(v.duration_s, k < 2 ? 0.02 : 0.03) << v.name;
    EXPECT_EQ(v.robot.lock.size(), k % 2 == 1 ? 1u : 0u) << v.name;
    // What a value does not override comes from the base.
    EXPECT_EQ(v.robot.initial, (std::vector<std::pair<std::string, double>>{{"l_knee", 1.0}})) << v.name;
    ASSERT_EQ(v.controllers.size(), 1u);
    EXPECT_EQ(v.controllers[0].rate_hz, 1000);
  }

  std::vector<dmbd::sim::VariantResult> runs;
  for (const auto& v : s.variants) runs.push_back(dmbd::scenario::run_variant(s, v, {}));
  EXPECT_EQ(runs[0].log.rows(), 21u);
  EXPECT_EQ(runs[2].log.rows(), 31u);
  EXPECT_EQ(runs[2].controller_steps, (std::vector<long long>{31}));
  // The locked variant's knee does not move.
  for (double q : runs[1].log.column("l_knee.q")) EXPECT_NEAR(q, 1.0, 1e-3);  // lock: stiff constraint, held to < 1 mrad

  const std::string csv = dmbd::scenario::combined_csv(runs);
  std::istringstream in(csv);
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header.rfind("t [s],a/x/l_knee.q [rad],a/x/l_knee.qd [rad/s],", 0), 0u) << header.substr(0, 200);
  for (const auto& n : names) {
    EXPECT_NE(header.find("," + n + "/l_knee.current [A]"), std::string::npos) << n;
    EXPECT_NE(header.find("," + n + "/q_d []"), std::string::npos) << n;
  }
  const std::size_t columns = static_cast<std::size_t>(std::count(header.begin(), header.end(), ',')) + 1;
  std::size_t expected_columns = 1;
  for (const auto& r : runs) expected_columns += r.log.columns() - 1;
  EXPECT_EQ(columns, expected_columns);
  // One line per row of the longest run; every line has every column; a shorter run's
  // cells are empty past its end.
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  ASSERT_EQ(lines.size(), 31u);
  const std::size_t ax_q = 1;  // column of a/x/l_knee.q
  for (std::size_t r = 0; r < lines.size(); ++r) {
    const std::vector<std::string> cells = split_csv(lines[r]);
    ASSERT_EQ(cells.size(), columns) << "row " << r;
    EXPECT_EQ(std::strtod(cells[0].c_str(), nullptr), runs[2].log.time()[r]);
    if (r < 21) {
      EXPECT_EQ(std::strtod(cells[ax_q].c_str(), nullptr), runs[0].log.column("l_knee.q")[r]) << "row " << r;
    } else {
      EXPECT_EQ(cells[ax_q], "") << "row " << r;
    }
  }
  // A single run keeps the plain names.
  EXPECT_EQ(dmbd::scenario::combined_csv({runs[0]}), runs[0].log.to_csv());
}

// outputs.hpp: combined_csv puts every variant "on the time base of the longest run".
// Variants may override log_rate_hz; a cell must then hold the value logged at that
// row's time (or be empty when the variant logged nothing at that time), not the
// value of the variant's row with the same index.
TEST(SimScenarioVariants, CombinedCsvAlignsVariantsWithDifferentLogRates) {
  TempDir dir;
  const std::string path = dir.file("rates.yaml");
  write_text(path, replace_line(base_scenario(), "duration_s: 0.05", "duration_s: 0.02") +
                       "variants:\n"
                       "  - name: fast\n"
                       "  - name: slow\n"
                       "    log_rate_hz: 500\n");
  const Scenario s = load_scenario(path);
  std::vector<dmbd::sim::VariantResult> runs;
  for (const auto& v : s.variants) runs.push_back(dmbd::scenario::run_variant(s, v, {}));
  ASSERT_EQ(runs[0].log.rows(), 21u);
  ASSERT_EQ(runs[1].log.rows(), 11u);
  std::istringstream in(dmbd::scenario::combined_csv(runs));
  std::string header;
  std::getline(in, header);
  const std::vector<std::string> cols = split_csv(header);
  const auto slow_t = static_cast<std::size_t>(std::find(cols.begin(), cols.end(), "slow/q_d []") - cols.begin());
  ASSERT_LT(slow_t, cols.size());
  // q_d steps from 1.0 to 1.05 at 10 ms: at t = 15 ms (row 15 of the 1 kHz base) the
  // slow variant's value is 1.05, its row 15 does not exist.
  std::string line;
  for (int r = 0; r <= 15; ++r) std::getline(in, line);
  std::vector<std::string> cells = split_csv(line);
  ASSERT_EQ(cells.size(), cols.size());
  ASSERT_GT(cells.size(), slow_t);
  EXPECT_EQ(std::strtod(cells[0].c_str(), nullptr), runs[0].log.time()[15]);
  const std::string cell = cells[slow_t];
  EXPECT_TRUE(cell.empty() || std::strtod(cell.c_str(), nullptr) == 1.05)
      << "slow/q_d at t = 15 ms is '" << cell << "' (the slow run's row 15 is t = 30 ms, past its end)";
  // Row 5 (t = 5 ms): the slow run's row 5 is t = 10 ms, after the step.
  std::istringstream in2(dmbd::scenario::combined_csv(runs));
  for (int r = 0; r <= 6; ++r) std::getline(in2, line);
  cells = split_csv(line);
  EXPECT_EQ(std::strtod(cells[0].c_str(), nullptr), runs[0].log.time()[5]);
  EXPECT_TRUE(cells[slow_t].empty() || std::strtod(cells[slow_t].c_str(), nullptr) == 1.0)
      << "slow/q_d at t = 5 ms is '" << cells[slow_t] << "'";
}

TEST(SimScenarioVariants, VariantListOverridesTheBase) {
  TempDir dir;
  const std::string path = dir.file("v.yaml");
  write_text(path, base_scenario() +
                       "variants:\n"
                       "  - name: short\n"
                       "    duration_s: 0.01\n"
                       "  - name: noisy\n"
                       "    sensors: {noise: true, seed: 3}\n"
                       "frames: {variant: noisy}\n");
  const Scenario s = load_scenario(path);
  ASSERT_EQ(s.variants.size(), 2u);
  EXPECT_EQ(s.variants[0].name, "short");
  EXPECT_EQ(s.variants[0].duration_s, 0.01);
  EXPECT_FALSE(s.variants[0].sensor_noise);
  EXPECT_EQ(s.variants[1].name, "noisy");
  EXPECT_EQ(s.variants[1].duration_s, 0.05);
  EXPECT_TRUE(s.variants[1].sensor_noise);
  EXPECT_EQ(s.variants[1].seed, 3u);
  EXPECT_EQ(s.frames.variant, "noisy");
  const auto r = dmbd::scenario::run_variant(s, s.variants[0], {});
  EXPECT_EQ(r.log.rows(), 11u);
  // RunOptions::duration_s overrides the variant's.
  dmbd::scenario::RunOptions o;
  o.duration_s = 0.004;
  EXPECT_EQ(dmbd::scenario::run_variant(s, s.variants[1], o).log.rows(), 5u);

  // frames.variant must name a variant (on its line).
  const std::string bad = base_scenario() + "variants:\n  - name: short\nframes: {variant: long}\n";
  check_error(path, {"frames.variant", bad, "frames: {variant: long}", "no variant is named 'long'"});
}

// ------------------------------------------------------------------------- divergence

TEST(SimScenarioDivergence, ADivergingVariantIsAnInputErrorNamingScenarioAndVariant) {
  TempDir dir;
  // Positive feedback of the knee angle onto the knee torque with a huge gain.
  write_text(dir.file("runaway.yaml"),
             "name: runaway\n"
             "inputs:\n  q: {unit: rad}\noutputs:\n  tau: {unit: N m}\n"
             "blocks:\n  K: {type: gain, k: 1e6}\n"
             "connections:\n  - q -> K\n  - K -> tau\n");
  const std::string path = dir.file("unstable.yaml");
  write_text(path,
             "name: unstable\n"
             "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], initial: {l_knee: 1.0}}\n"
             "duration_s: 0.5\n"
             "variants:\n"
             "  - name: calm\n"
             "    duration_s: 0.01\n"
             "  - name: wild\n"
             "    controllers:\n"
             "      - name: feedback\n"
             "        diagram: runaway.yaml\n"
             "        inputs: {q: l_knee.q}\n"
             "        outputs: {tau: l_knee.torque}\n");
  const Scenario s = load_scenario(path);
  try {
    (void)dmbd::scenario::run_scenario(s, dir.file("out"));
    FAIL() << "no error";
  } catch (const InputError& e) {
    // The divergence itself, with where it happened added (not re-wrapped).
    EXPECT_TRUE(dynamic_cast<const dmbd::sim::DivergenceError*>(&e) || dynamic_cast<const dmbd::model::ModelError*>(&e)) << e.what();
    const std::string msg = e.what();
    EXPECT_EQ(msg.rfind(path, 0), 0u) << msg;
    EXPECT_NE(msg.find("variant 'wild'"), std::string::npos) << msg;
    EXPECT_NE(msg.find("t = "), std::string::npos) << msg;
    EXPECT_NE(msg.find("l_knee"), std::string::npos) << msg;
    EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  }
}

// ------------------------------------------------------------------------- thermal experiment

// The thermal experiment's RMS current comes from the exact integral J.i2t. A 3 A,
// 10 Hz sine driven on the current directly (no controller: held at the 2 kHz log
// rate) over one period: the held samples' squares sum to exactly half the count
// (sum over a whole period of sin^2 at 200 points is 100), so RMS = 3 / sqrt(2); the
// cooled and uncooled peaks rise from the 20 degC start and the uncooled is higher.
TEST(SimScenarioExperiments, ThermalRmsCurrentIsExact) {
  TempDir dir;
  const std::string path = dir.file("heat.yaml");
  write_text(path,
             "name: heat\n"
             "robot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], initial: {l_knee: 1.0}, "
             "lock: {l_knee: 1.0}}\n"
             "duration_s: 0.1\n"
             "log_rate_hz: 2000\n"
             "thermal: {cooling: both}\n"
             "references:\n"
             "  l_knee.current: {type: sine, amplitude: 3.0, freq_hz: 10}\n"
             "experiment: {type: thermal, joint: l_knee}\n");
  const auto r = dmbd::scenario::run_scenario(load_scenario(path), dir.file("out"));
  const auto& m = r.experiment.metrics;
  // 1e-12 relative: 200 rounded products summed.
  EXPECT_NEAR(m["rms_current_A"].get<double>(), 3.0 / std::sqrt(2.0), 1e-12 * 3.0);
  const auto& log = r.runs[0].log;
  const auto& i2t = log.column("l_knee.i2t");
  const auto& i = log.column("l_knee.current_applied");
  // Row k holds the integral up to t_k of the current held from each earlier row.
  double sum = 0;
  for (std::size_t k = 0; k < log.rows(); ++k) {
    EXPECT_NEAR(i2t[k], sum, 1e-14 + 1e-12 * sum) << "row " << k;
    sum += i[k] * i[k] * 5e-4;
  }
  const double cooled = m["peak_winding_C"]["cooled"].get<double>(), uncooled = m["peak_winding_C"]["uncooled"].get<double>();
  EXPECT_GT(cooled, log.column("l_knee.T_winding_cooled").front());
  EXPECT_GE(uncooled, cooled);
}

// ------------------------------------------------------------------------- run_scenario and the CLI

// The run directory: log.csv and metrics.json and nothing else (sim draws nothing),
// read back by read_run with the same logs (to the last bit: 17 digits), run figures,
// true values and experiment.
TEST(SimScenarioRun, WritesTheRunDirectoryAndReadsItBack) {
  TempDir dir;
  const std::string path = dir.file("hold.yaml");
  write_text(path, base_scenario() + "plots:\n  - {title: Knee, y_label: rad, file: knee.png, signals: [l_knee.q, q_d]}\n");
  dmbd::scenario::ScenarioRunOptions o;
  o.duration_s = 0.03;
  const auto out = dir.file("out");
  const auto r = dmbd::scenario::run_scenario(load_scenario(path), out, o);
  ASSERT_EQ(r.runs.size(), 1u);
  EXPECT_EQ(r.runs[0].log.rows(), 31u);
  EXPECT_EQ(r.files, (std::vector<std::string>{"log.csv", "metrics.json"}));
  for (const auto& e : fs::recursive_directory_iterator(out)) EXPECT_TRUE(e.path().filename() == "log.csv" || e.path().filename() == "metrics.json") << e.path();
  EXPECT_EQ(read_text(out + "/log.csv"), r.runs[0].log.to_csv());
  const auto metrics = nlohmann::json::parse(read_text(out + "/metrics.json"));
  EXPECT_EQ(metrics["scenario"], "knee_hold");
  EXPECT_EQ(metrics["runs"]["base"]["controller_steps"][0], 31);
  EXPECT_EQ(metrics["scenario_file"], fs::absolute(path).lexically_normal().string());

  const auto back = dmbd::scenario::read_run(out);
  ASSERT_EQ(back.runs.size(), 1u);
  const auto& a = r.runs[0].log;
  const auto& b = back.runs[0].log;
  ASSERT_EQ(a.columns(), b.columns());
  for (std::size_t c = 0; c < a.columns(); ++c) {
    EXPECT_EQ(a.name(static_cast<int>(c)), b.name(static_cast<int>(c)));
    EXPECT_EQ(a.unit(static_cast<int>(c)), b.unit(static_cast<int>(c)));
    EXPECT_EQ(a.column(static_cast<int>(c)), b.column(static_cast<int>(c))) << a.name(static_cast<int>(c));  // bit for bit
  }
  EXPECT_EQ(back.runs[0].wall_s, r.runs[0].wall_s);
  EXPECT_EQ(back.runs[0].controller_steps, r.runs[0].controller_steps);
  EXPECT_EQ(back.experiment.metrics, r.experiment.metrics);
  ASSERT_EQ(back.experiment.figures.size(), 1u);  // the scenario's plot
  EXPECT_EQ(back.experiment.figures[0].second.axes()[0].series[0].y, r.experiment.figures[0].second.axes()[0].series[0].y);
}

// Issue 13, item 7: a fixed-point controller's predicted error bound over the run is in
// metrics.json (and read back), and a bound beyond the output's range is a warning. The
// DOB force controller in 16 bits: its bound over 0.2 s at 2 kHz (53 A with the state
// update's words widened to 32 bits by the range analysis, the default; 380 A with every
// word 16 bits; docs/codegen.md, "Wider states") exceeds its +-22 A; in 32 bits it is
// far inside.
TEST(SimScenarioRun, FixedPointBoundIsReportedAndABoundBeyondTheRangeWarns) {
  TempDir dir;
  auto scenario = [&](int bits) {
    const std::string path = dir.file("f" + std::to_string(bits) + ".yaml");
    write_text(path, "name: fd\nrobot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, moving: [l_knee], actuators: [l_knee], "
                     "initial: {l_knee: 1.0}, lock: {l_knee: 1.0}}\nduration_s: 0.2\nreferences:\n  F_d: {type: constant, value: 100}\n"
                     "controllers:\n  - name: force\n    diagram: " + kSourceDir + "/examples/diagrams/dob_controller.yaml\n"
                     "    rate_hz: 2000\n    scalar: fixed\n    word_bits: " + std::to_string(bits) + "\n"
                     "    inputs: {F_d: F_d, F_m: l_knee.force}\n    outputs: {i: l_knee.current}\n");
    return load_scenario(path);
  };
  const auto r16 = dmbd::scenario::run_scenario(scenario(16), dir.file("o16"));
  ASSERT_EQ(r16.runs[0].fixed_point.size(), 1u);
  const auto& f = r16.runs[0].fixed_point[0];
  EXPECT_EQ(f.controller, "force");
  EXPECT_EQ(f.output, "i");
  EXPECT_EQ(f.range, 22.0);
  EXPECT_GT(f.bound, 2.0 * f.range);
  ASSERT_EQ(r16.runs[0].warnings.size(), 1u);
  EXPECT_NE(r16.runs[0].warnings[0].find("16-bit"), std::string::npos);
  const auto back = dmbd::scenario::read_run(dir.file("o16"));
  EXPECT_EQ(back.runs[0].fixed_point[0].bound, f.bound);
  EXPECT_EQ(back.runs[0].warnings, r16.runs[0].warnings);
  const auto r32 = dmbd::scenario::run_scenario(scenario(32), dir.file("o32"));
  EXPECT_LT(r32.runs[0].fixed_point[0].bound, 1.0);
  EXPECT_TRUE(r32.runs[0].warnings.empty());
}

// Several variants, logged at different rates, split back out of the combined table.
TEST(SimScenarioRun, SplitCsvInvertsCombinedCsv) {
  TempDir dir;
  const std::string path = dir.file("two.yaml");
  write_text(path, base_scenario() + "variants:\n  - name: slow/a\n    log_rate_hz: 500\n  - name: fast\n");
  dmbd::scenario::ScenarioRunOptions o;
  o.duration_s = 0.01;
  const auto r = dmbd::scenario::run_scenario(load_scenario(path), dir.file("out"), o);
  const auto logs = dmbd::scenario::split_csv(dmbd::scenario::combined_csv(r.runs), {"slow/a", "fast"}, "log.csv");
  ASSERT_EQ(logs.size(), 2u);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(logs[k].rows(), r.runs[k].log.rows());
    EXPECT_EQ(logs[k].to_csv(), r.runs[k].log.to_csv());
  }
  EXPECT_EQ(logs[0].rows(), 6u);   // 0..10 ms at 2 ms
  EXPECT_EQ(logs[1].rows(), 11u);  // at 1 ms
}

// The dmbd binary of the same build: <build>/apps/dmbd, the test being <build>/tests/sim/test_sim_sim.
fs::path dmbd_binary() { return fs::read_symlink("/proc/self/exe").parent_path().parent_path().parent_path() / "apps" / "dmbd"; }

struct Command {
  int status = -1;
  std::string out, err;
};

Command run_dmbd(const TempDir& dir, const std::string& args) {
  const std::string out = dir.file("stdout.txt"), err = dir.file("stderr.txt");
  const std::string cmd = "'" + dmbd_binary().string() + "' " + args + " > '" + out + "' 2> '" + err + "' < /dev/null";
  const int rc = std::system(cmd.c_str());
  Command c;
  c.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  c.out = read_text(out);
  c.err = read_text(err);
  fs::remove(out);
  fs::remove(err);
  return c;
}

TEST(SimScenarioCli, SimulateWritesOutputsAndReportsErrorsOnOneLine) {
  if (!fs::exists(dmbd_binary())) GTEST_SKIP() << dmbd_binary() << " is not built (target dmbd)";
  TempDir dir;
  const std::string good = dir.file("good.yaml");
  write_text(good, replace_line(base_scenario(), "duration_s: 0.05", "duration_s: 5"));
  const std::string out = dir.file("out");
  const Command ok = run_dmbd(dir, "simulate '" + good + "' --out '" + out + "' --no-frames --duration 0.2");
  EXPECT_EQ(ok.status, 0) << ok.err;
  for (const char* f : {"log.csv", "metrics.json", "report.html"}) EXPECT_TRUE(fs::exists(fs::path(out) / f)) << f;
  EXPECT_FALSE(fs::exists(fs::path(out) / "video.mp4"));
  // --duration replaced the scenario's 5 s: 0.2 s at 1 kHz.
  const std::string csv = read_text(out + "/log.csv");
  EXPECT_EQ(std::count(csv.begin(), csv.end(), '\n'), 1 + 201);

  // A scenario with a mistake: exit status 2, one line on stderr naming file:line, and
  // nothing written.
  const std::string bad = dir.file("bad.yaml");
  const std::string bad_yaml = replace_line(base_scenario(), "duration_s: 0.05", "duration: 0.05");
  write_text(bad, bad_yaml);
  const std::string bad_out = dir.file("bad_out");
  const Command err = run_dmbd(dir, "simulate '" + bad + "' --out '" + bad_out + "' --no-frames --duration 0.2");
  EXPECT_EQ(err.status, 2);
  EXPECT_EQ(std::count(err.err.begin(), err.err.end(), '\n'), 1) << err.err;
  EXPECT_NE(err.err.find(bad + ":" + std::to_string(line_of(bad_yaml, "duration: 0.05")) + ":"), std::string::npos) << err.err;
  EXPECT_TRUE(!fs::exists(bad_out) || fs::is_empty(bad_out)) << "files left in " << bad_out;

  // A missing scenario file.
  const Command missing = run_dmbd(dir, "simulate '" + dir.file("nope.yaml") + "' --out '" + bad_out + "' --no-frames");
  EXPECT_EQ(missing.status, 2);
  EXPECT_EQ(std::count(missing.err.begin(), missing.err.end(), '\n'), 1) << missing.err;
  EXPECT_TRUE(!fs::exists(bad_out) || fs::is_empty(bad_out));
}

// ------------------------------------------------------------------------- shipped scenarios

// A shipped scenario of examples/scenarios/, run without frames into `dir`.
dmbd::scenario::ScenarioRun run_shipped(const TempDir& dir, const std::string& name, std::optional<double> duration_s = std::nullopt) {
  const Scenario s = load_scenario(kSourceDir + "/examples/scenarios/" + name + ".yaml");
  dmbd::scenario::ScenarioRunOptions o;
  o.duration_s = duration_s;
  return dmbd::scenario::run_scenario(s, dir.file("out"), o);
}

// Paper Fig. 5(b): the three position controllers on the knee (7.5 s scenario shortened
// to its 0.3 rad step window, [0.5, 2.0] s). The paper's controllers are tuned for no
// overshoot (2 % allowed: the quantised encoder and the noisy potentiometer), and the
// encoder PD rises faster than the potentiometer PD (its filter and lower gains).
TEST(SimShippedScenarios, PositionControllersStepResponse) {
  TempDir dir;
  const auto r = run_shipped(dir, "position_controllers", 2.0);
  const auto& m = r.experiment.metrics["controllers"];
  for (const char* c : {"encoder", "potentiometer", "encoder_force"}) {
    ASSERT_TRUE(m.contains(c)) << c;
    const double os = m[c]["overshoot_pct"].get<double>(), rise = m[c]["rise_time_s"].get<double>();
    std::printf("%-14s overshoot %.3f %%, rise time %.4f s, steady-state error %.3g rad\n", c, os, rise,
                m[c]["steady_state_error_rad"].get<double>());
    EXPECT_LE(os, 2.0) << c;
    EXPECT_TRUE(std::isfinite(rise) && rise > 0) << c;
  }
  EXPECT_LT(m["encoder"]["rise_time_s"].get<double>(), m["potentiometer"]["rise_time_s"].get<double>());
  for (const auto& run : r.runs) EXPECT_EQ(run.log.time().back(), 2.0) << run.name;
}

// Paper Fig. 3(b) / Sec. III: the disturbance observer tracks force better than the PD
// alone at every load (the plant's 90 % screw efficiency is unknown to both).
TEST(SimShippedScenarios, ForceDobBeatsPdAtEveryLoad) {
  TempDir dir;
  const auto r = run_shipped(dir, "force_dob", 1.0);
  const auto& rms = r.experiment.metrics["rms_error_N"];
  for (const char* load : {"locked", "30000kg", "10000kg", "2953kg"}) {
    const double dob = rms["with_dob"][load].get<double>(), pd = rms["without_dob"][load].get<double>();
    std::printf("load %-8s RMS force error: with DOB %.3f N, without %.3f N\n", load, dob, pd);
    EXPECT_LT(dob, pd) << load;
  }
}

// Paper Sec. II-B / IV-B: the shipped thermal scenario, whole (300 s of squat, about a
// minute of wall time): with liquid cooling the knee winding stays below 60 degC,
// without it passes 100 degC (issue 6's figures; the paper's balancing run passed
// 130 degC uncooled over a longer time). The RMS current (exact, from J.i2t) must be
// a real load and below the cooled continuous current.
TEST(SimShippedScenarios, ThermalCoolingKeepsTheWindingBelow60C) {
  TempDir dir;
  const auto r = run_shipped(dir, "thermal");
  const auto& m = r.experiment.metrics;
  const double cooled = m["peak_winding_C"]["cooled"].get<double>(), uncooled = m["peak_winding_C"]["uncooled"].get<double>();
  const double rms = m["rms_current_A"].get<double>();
  std::printf("RMS current %.3f A, peak winding %.2f degC cooled, %.2f degC uncooled\n", rms, cooled, uncooled);
  EXPECT_LT(cooled, 60.0);
  EXPECT_GT(uncooled, 100.0);
  EXPECT_GT(rms, 3.0);  // the squat loads the knee: a few amperes
  EXPECT_LT(rms, 7.46);  // below the cooled continuous current (docs/model.md)
}

// Issue 12: the shipped standing scenario, whole (10 s, under a second of wall time):
// DRACO on its ten actuators, each joint under the generated controller 1, pushed
// sideways at 5 s, stands (fell false), the push recovered (tilt at the end <= 0.02 rad),
// and the torso barely sinks. Measured (the robot's output damping and its gains, issue
// 27): max tilt 8.4 mrad, final 0.96 mrad, drop 1.6 mm, 10.2 mm sideways after the push.
TEST(SimShippedScenarios, StandingOnTheActuatorsRecoversFromThePush) {
  TempDir dir;
  const auto r = run_shipped(dir, "standing");
  const auto& m = r.experiment.metrics["standing"];
  std::printf("standing: fell %d, max tilt %.4f rad, final tilt %.4f rad, drop %.4f m\n", m["fell"].get<bool>(),
              m["max_tilt_rad"].get<double>(), m["final_tilt_rad"].get<double>(), m["torso_height_drop_m"].get<double>());
  EXPECT_FALSE(m["fell"].get<bool>());
  EXPECT_LE(m["final_tilt_rad"].get<double>(), 0.02);
  EXPECT_LT(m["torso_height_drop_m"].get<double>(), 0.01);
  // The push moved the torso sideways and it came back: largest y excursion after 5 s
  // above 2 mm, the last second within 2 mm of where it settled.
  const auto& t = r.runs[0].log.time();
  const auto& y = r.runs[0].log.column("base.y");
  double swing = 0, late = 0;
  for (std::size_t k = 0; k < t.size(); ++k) {
    if (t[k] >= 5.0) swing = std::max(swing, std::abs(y[k] - y.front()));
    if (t[k] >= 9.0) late = std::max(late, std::abs(y[k] - y.back()));
  }
  EXPECT_GT(swing, 2e-3);
  EXPECT_LT(late, 2e-3);
  EXPECT_EQ(r.runs[0].integrator_steps, 20000);  // fixed 0.5 ms
}

// Paper Table I / Fig. 5(a): the shipped identification scenario, whole (190 s simulated,
// about a minute of wall time): every parameter within 5 % with exact sensors and 15 %
// with their noise (issue 6); measured 0.08 % and 0.35 %.
TEST(SimShippedScenarios, SysidRecoversTableI) {
  TempDir dir;
  const auto r = run_shipped(dir, "sysid_knee");
  const auto& m = r.experiment.metrics;
  for (const char* p : {"J_m", "B_m", "M_r", "B_r", "K_r", "M_l", "B_l"}) {
    const double exact = m["rel_error"][p].get<double>(), noisy = m["noisy"]["rel_error"][p].get<double>();
    std::printf("%-4s relative error: exact %.2e, noisy %.2e\n", p, exact, noisy);
    EXPECT_LT(std::abs(exact), 0.05) << p;
    EXPECT_LT(std::abs(noisy), 0.15) << p;
    // The identified value is compared with the simulator's own (Table I for the knee).
    const double truth = m["true"][p].get<double>(), id = m["identified"][p].get<double>();
    EXPECT_NEAR(std::abs(id - truth) / truth, std::abs(exact), 1e-12) << p;
  }
  EXPECT_EQ(m["true"]["K_r"].get<double>(), 9.5e6);  // Table I
  EXPECT_EQ(m["true"]["M_r"].get<double>(), 1.3);    // Table I
}

}  // namespace

// robot.armature (a rotor reflected onto a joint without an actuator model): set on the
// variant's robot; an actuated joint (its rotor is modelled), a joint the robot lacks, a
// welded joint and a negative inertia are located errors.
TEST(SimScenarioLoad, ArmatureGoesOnJointsWithoutAnActuator) {
  TempDir dir;
  const std::string path = dir.file("s.yaml");
  const std::string robot = "  initial: {l_knee: 1.0}";
  const std::string moving = "  moving: [l_knee]";
  const std::string two = replace_line(base_scenario(), moving, "  moving: [l_knee, l_ankle]");
  write_text(path, replace_line(two, robot, robot + "\n  armature: {l_ankle: 0.55}"));
  const Scenario s = load_scenario(path);
  const dmbd::scenario::VariantPlant vp = dmbd::scenario::variant_plant(s, s.variants[0]);
  const auto& joints = vp.robot.joints;
  const auto ankle = std::find_if(joints.begin(), joints.end(), [](const auto& j) { return j.name == "l_ankle"; });
  ASSERT_NE(ankle, joints.end());
  EXPECT_EQ(ankle->armature, 0.55);
  auto build_error = [&](const std::string& yaml, const std::string& expected) {
    SCOPED_TRACE(expected);
    write_text(path, yaml);
    const Scenario bad = load_scenario(path);
    try {
      (void)dmbd::scenario::variant_plant(bad, bad.variants[0]);
      ADD_FAILURE() << "no error";
    } catch (const InputError& e) {
      const std::string msg = e.what();
      EXPECT_EQ(msg.rfind(path + ":" + std::to_string(line_of(yaml, "armature:")) + ":", 0), 0u) << msg;
      EXPECT_NE(msg.find(expected), std::string::npos) << msg;
    }
  };
  build_error(replace_line(two, robot, robot + "\n  armature: {l_knee: 0.5}"), "'l_knee' is driven by its actuator, whose rotor is already modelled");
  build_error(replace_line(two, robot, robot + "\n  armature: {l_toe: 0.5}"), "robot.armature: 'l_toe' is not a moving joint");
  check_load_error(path, {"negative", replace_line(two, robot, robot + "\n  armature: {l_ankle: -1}"), "armature:",
                          "robot.armature: expected a rotor inertia of 0 to 1e6 kg m² for 'l_ankle'"});
}
