// dmbd simulate refuses what would otherwise run in silence (issue 26 item 9), each with
// exit status 2, one line naming the file, the line and what was expected, nothing
// written: a controller output bound to a misspelt signal (the closest plant input
// named), an initial angle outside the joint's limits (degrees meant), an experiment
// joint the robot lacks, a bus controller whose joint commands nothing takes; and it
// prints the scenario's notes and its robot's URDF warnings on stderr before the runs.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>

#include "cli_support.hpp"

namespace {

namespace fs = std::filesystem;
using dmbd::cli_testing::Result;
using dmbd::cli_testing::slurp;

const std::string kSource = DMBD_SOURCE_DIR;
const std::string kArm = kSource + "/tests/scenario/data/arm3.urdf";
const std::string kPd = kSource + "/examples/diagrams/joint_pd_torque.yaml";

class SimulateChecks : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("dmbd_simulate_checks_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) +
                                        "_" + std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_ / "work");
  }
  void TearDown() override { fs::remove_all(dir_); }

  Result simulate(const std::string& yaml) {
    std::ofstream(dir_ / "s.yaml") << yaml;
    return dmbd::cli_testing::run_dmbd({"simulate", (dir_ / "s.yaml").string(), "--out", "out", "--no-frames"}, dir_, dir_ / "work");
  }
  // Exit 2, one line "dmbd: error: FILE: variant 'base': FILE:LINE:COL: ..." holding
  // `fragment`, nothing written.
  void expect_refused(const std::string& yaml, int line, const std::string& fragment) {
    const Result r = simulate(yaml);
    EXPECT_EQ(r.code, 2) << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    const std::string file = (dir_ / "s.yaml").string();
    const std::string at = "dmbd: error: " + file + ": variant 'base': " + file + ":" + std::to_string(line) + ":";
    EXPECT_EQ(r.err.rfind(at, 0), 0u) << "expected '" << at << "' in: " << r.err;
    EXPECT_NE(r.err.find(fragment), std::string::npos) << "missing '" << fragment << "' in: " << r.err;
    EXPECT_TRUE(fs::is_empty(dir_ / "work"));
  }

  fs::path dir_;
};

// The arm held by a PD diagram on its shoulder; `extra` appended.
std::string arm(const std::string& robot_extra, const std::string& output, const std::string& extra = "") {
  return "name: arm\nrobot: {urdf: " + kArm + ", base: fixed" + robot_extra + "}\nduration_s: 0.05\n"
         "references: {q_d: -0.4, zero: 0}\ncontrollers:\n"
         "  - {name: shoulder, diagram: " + kPd + ", rate_hz: 1000,\n"
         "     inputs: {q_d: q_d, qd_d: zero, tau_ff: zero, q: shoulder.q, qd: shoulder.qd}, outputs: {torque: " + output + "}}\n" + extra;
}

TEST_F(SimulateChecks, AMisspeltOutputIsRefusedNamingTheClosestPlantInput) {
  expect_refused(arm("", "sholder.torque"), 7, "controller 'shoulder': output 'torque' is bound to 'sholder.torque', which is no plant input "
                 "and nothing reads (a controller, a plot, the experiment, an overlay, the scenario's log: list); the closest plant input "
                 "is 'shoulder.torque'");
  // Kept for the log on purpose: it runs.
  const Result r = simulate(arm("", "shoulder.torque_wanted", "log: [shoulder.torque_wanted]\n"));
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(simulate(arm("", "shoulder.torque")).code, 0);
}

TEST_F(SimulateChecks, AnInitialAngleOutsideTheLimitsIsRefused) {
  expect_refused(arm(", initial: {shoulder: 30}", "shoulder.torque"), 2,
                 "robot.initial: joint 'shoulder' at 30 rad, outside its limits [-2.5, 2.5]");
  expect_refused(arm(", lock: {elbow: -3}", "shoulder.torque"), 2, "robot.lock: joint 'elbow' at -3 rad, outside its limits [-2.8, 2.8]");
}

TEST_F(SimulateChecks, AnExperimentJointTheRobotLacksIsRefused) {
  expect_refused(arm("", "shoulder.torque", "experiment: {type: step_response, joint: sholder, reference: q_d, output: shoulder.q}\n"), 8,
                 "experiment.joint: the robot has no joint 'sholder'");
}

// DRACO on its actuators under operational space control without its force loops: the
// controller's force commands reach nothing.
TEST_F(SimulateChecks, ABusControllerWhoseCommandsReachNothingIsRefused) {
  expect_refused("name: osc\nrobot: {name: draco, base: fixed, base_pose: {xyz: [0, 0, 1.3]}, actuators: all}\nduration_s: 0.01\n"
                 "bus_controllers: [{type: osc}]\n",
                 4, "osc: the command for joint 'l_hip_yaw' reaches nothing: no controller reads l_hip_yaw.force_d");
}

// Deprecated keys and the URDF's warnings are printed before the run, on stderr.
TEST_F(SimulateChecks, NotesAndUrdfWarningsGoToStderrBeforeTheRun) {
  const Result r = simulate("name: n\nrobot: {urdf: draco, base: fixed}\nduration_s: 0.01\n");
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("dmbd: note: " + (dir_ / "s.yaml").string() + ":2:15: robot.urdf: a robot's name is deprecated there: write robot.name: draco"),
            std::string::npos)
      << r.err;
  std::ofstream(dir_ / "bad_mesh.urdf") << "<robot name=\"r\"><link name=\"a\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" "
                                             "ixz=\"0\" iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial><visual><geometry><mesh "
                                             "filename=\"nowhere.stl\"/></geometry></visual></link></robot>\n";
  const Result w = simulate("name: w\nrobot: {urdf: bad_mesh.urdf, base: fixed}\nduration_s: 0.01\n");
  EXPECT_EQ(w.code, 0) << w.err;
  EXPECT_NE(w.err.find("dmbd: warning: " + (dir_ / "bad_mesh.urdf").string() + ":1:"), std::string::npos) << w.err;
  EXPECT_NE(w.err.find("nowhere.stl"), std::string::npos) << w.err;
  EXPECT_EQ(w.out.find("warning"), std::string::npos) << w.out;
}

}  // namespace
