#pragma once
// A renderable scene of a robot description (one scene body per link, same index as
// robot.links). Poses come from model::link_frames (or a simulation's log).
//
//   const auto robot = dmbd::model::load_urdf(DMBD_DRACO_DIR "/draco.urdf");
//   const dmbd::viz::Scene scene = dmbd::report::scene_from_robot(robot);
//   auto X_WB = dmbd::model::link_frames(robot, q);
//   dmbd::viz::place_on_ground(scene, X_WB);               // lowest point on z = 0
//   const auto camera = dmbd::viz::default_robot_camera(1.3);
#include "dmbd/model/robot_description.hpp"
#include "dmbd/viz/renderer.hpp"

namespace dmbd::report {

struct RobotSceneOptions {
  int cylinder_segments = 24;  // around the axis (>= 3)
  int sphere_segments = 24;    // around the axis; half as many from pole to pole (>= 4)
};

// One SceneBody per link (name = link name), one SceneMesh per visual, in the link
// frame (the visual's X_LG applied) with the visual's rgba. Boxes, cylinders (along
// their z, centred) and spheres are tessellated; a Mesh visual whose triangles were not
// loaded (geometry.mesh null) is skipped. Collision geometry is not drawn.
// Throws std::invalid_argument for a non-positive primitive size or too few segments.
viz::Scene scene_from_robot(const model::RobotDescription& robot, const RobotSceneOptions& options = {});

}  // namespace dmbd::report
