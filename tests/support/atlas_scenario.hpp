#pragma once
// Simbody's Atlas example (atlas_v4_free_pelvis.urdf as Debian's simbody docs ship it,
// gzip-compressed, without its meshes) standing, as a scenario written in code: a
// floating base with the ground under every collision shape; the pelvis held
// horizontally by the start-up support (robot.support, never released in the run:
// horizontal springs only, so the legs carry the weight); each of the 29 moving joints
// held at its initial angle by its own PD law on an ideal joint torque
// (examples/diagrams/joint_pd_torque.yaml at 1 kHz), the knees bent 0.3 rad and the hip
// and ankle pitch -0.15 rad each (the feet parallel to the pelvis); fixed step 0.5 ms.
// Shared by tests/scenario/test_scenario_atlas.cpp and bench/bench_sim.cpp (needs
// DMBD_SOURCE_DIR).
#include <algorithm>
#include <cmath>
#include <string>

#include <fmt/format.h>

#include "dmbd/base/process.hpp"
#include "dmbd/model/robot_description.hpp"

namespace dmbd::test::atlas {

inline const char* const kAtlasGz =
    "/usr/share/doc/simbody/examples/src/TaskSpaceControl-Atlas/models/atlas_v4_free_pelvis.urdf.gz";

// Decompresses kAtlasGz into urdf_path (gzip, started without a shell); false if that fails.
inline bool decompress_atlas(const std::string& urdf_path) {
  return run_program({"gzip", "-dc", kAtlasGz}, urdf_path, "").ok();
}

constexpr double kBend = 0.3;  // knee bend, rad

// The initial (and held) angle: the knees bent, the hip and ankle pitch each taking back
// half of it (all three about the leg's y axis), every other joint at 0.
inline double initial(const std::string& joint) {
  if (joint == "l_leg_kny" || joint == "r_leg_kny") return kBend;
  for (const char* j : {"l_leg_hpy", "r_leg_hpy", "l_leg_aky", "r_leg_aky"})
    if (joint == j) return -0.5 * kBend;
  return 0.0;
}

inline bool moving(const model::Joint& j) { return j.type == model::JointType::Revolute || j.type == model::JointType::Continuous; }

// Gains per joint from I, the inertia about its axis of the links it moves
// (model::subtree_axis_inertia, zero pose): Kp = I w^2, Kd = 2 zeta I w, w = 2 pi 8 Hz,
// zeta = 1 (I from the lidar spindle's 4e-4 kg m^2 to the upper body's 14-22 kg m^2
// about the back joints), capped at Kp <= 3000 N m/rad and Kd <= 50 N m s/rad. Measured without the caps: the back and hip
// joints, whose subtrees are heavy but which in stance swing the light pelvis held only
// by the support's springs, chatter at 250 Hz (a quarter of the 1 kHz control rate) with
// the summed contact force 32 N rms and its mean 0.9 % above the weight; Kd <= 100 still
// chatters; with these caps it is steady (0.01 N rms).
constexpr double kOmega = 2 * M_PI * 8, kZeta = 1, kKpMax = 3000, kKdMax = 50;

// The scenario text: the URDF at `urdf`, every moving joint of `robot` held.
inline std::string scenario_text(const model::RobotDescription& robot, const std::string& urdf, double duration_s,
                          const std::string& frames) {
  std::string init, refs = "  zero: {type: constant, value: 0}\n", ctrls;
  for (std::size_t k = 0; k < robot.joints.size(); ++k) {
    const model::Joint& j = robot.joints[k];
    if (!moving(j)) continue;
    const double q0 = initial(j.name), I = model::subtree_axis_inertia(robot, static_cast<int>(k));
    if (q0 != 0.0) init += fmt::format("{}{}: {}", init.empty() ? "" : ", ", j.name, q0);
    refs += fmt::format("  {}.q_d: {{type: constant, value: {}}}\n", j.name, q0);
    ctrls += fmt::format(
        "  - {{name: {0}_pd, diagram: '{1}/examples/diagrams/joint_pd_torque.yaml', rate_hz: 1000, "
        "parameters: {{Kp: {2:.6g}, Kd: {3:.6g}, tau_max: 1000}}, "
        "inputs: {{q_d: {0}.q_d, qd_d: zero, tau_ff: zero, q: {0}.q, qd: {0}.qd}}, outputs: {{torque: {0}.torque}}}}\n",
        j.name, DMBD_SOURCE_DIR, std::min(I * kOmega * kOmega, kKpMax), std::min(2 * kZeta * I * kOmega, kKdMax));
  }
  return "name: atlas\n"
         "robot: {urdf: '" + urdf + "', base: floating, contact: true, support: {release_s: 1000}, initial: {" + init + "}}\n" +
         fmt::format("integration: {{mode: fixed, step_s: 0.0005}}\nduration_s: {}\nlog_rate_hz: 200\n", duration_s) +
         "references:\n" + refs + "controllers:\n" + ctrls + frames;
}

}  // namespace dmbd::test::atlas
