#pragma once
// A renderable Scene from a robot description (one scene body per link, same index as
// robot.links), tessellated primitives, preview kinematics and a default camera.
//
//   const auto robot = dmbd::model::load_urdf(DMBD_DRACO_DIR "/draco.urdf");
//   const dmbd::viz::Scene scene = dmbd::viz::scene_from_robot(robot);
//   auto X_WB = dmbd::viz::link_frames(robot, q);          // or poses from the simulation
//   dmbd::viz::place_on_ground(scene, X_WB);               // lowest point on z = 0
//   const auto camera = dmbd::viz::default_robot_camera(1.3);
#include <vector>

#include <Eigen/Geometry>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/viz/renderer.hpp"

namespace dmbd::viz {

struct RobotSceneOptions {
  int cylinder_segments = 24;  // around the axis (>= 3)
  int sphere_segments = 24;    // around the axis; half as many from pole to pole (>= 4)
};

// One SceneBody per link (name = link name), one SceneMesh per visual, in the link
// frame (the visual's X_LG applied) with the visual's rgba. Boxes, cylinders (along
// their z, centred) and spheres are tessellated; a Mesh visual whose triangles were not
// loaded (geometry.mesh null) is skipped. Collision geometry is not drawn.
// Throws std::invalid_argument for a non-positive primitive size or too few segments.
Scene scene_from_robot(const model::RobotDescription& robot, const RobotSceneOptions& options = {});

// Closed, outward-wound primitive meshes centred at the origin, with vertex normals
// (flat per face for the box and the cylinder caps, smooth on curved surfaces).
SceneMesh box_mesh(const Eigen::Vector3d& size_m);                             // full edge lengths
SceneMesh cylinder_mesh(double radius_m, double length_m, int segments = 24);  // along z
SceneMesh sphere_mesh(double radius_m, int segments = 24);

// Forward kinematics for previews: X_WL for every link, the root link at X_W_root and
// joint j at position q[j] (robot.joints order): rotation about the joint axis for
// revolute and continuous joints (rad), translation along it for prismatic ones (m);
// fixed, floating and planar joints contribute X_PJ only (move a floating base through
// X_W_root). Throws std::invalid_argument if q.size() != robot.joints.size().
std::vector<Eigen::Isometry3d> link_frames(const model::RobotDescription& robot, const std::vector<double>& q,
                                           const Eigen::Isometry3d& X_W_root = Eigen::Isometry3d::Identity());

// A 3/4 view from the front-left (x forward, y left) of a robot `robot_height_m` tall
// standing on the ground at `ground_point_W`: looks at half its height from 35 deg
// left of straight ahead and 12 deg above, far enough that it fills about 75% of the
// image height.
Camera default_robot_camera(double robot_height_m, int width_px = 1280, int height_px = 720,
                            const Eigen::Vector3d& ground_point_W = Eigen::Vector3d::Zero());

}  // namespace dmbd::viz
