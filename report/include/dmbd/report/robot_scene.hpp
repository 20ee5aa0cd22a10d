#pragma once
// A renderable scene of a robot description (one scene body per link, same index as
// robot.links). Poses come from model::link_frames (or a simulation's log).
//
//   const auto robot = dmbd::model::load_urdf(DMBD_DRACO_DIR "/draco.urdf");
//   const dmbd::viz::Scene scene = dmbd::report::scene_from_robot(robot);
//   auto X_WB = dmbd::model::link_frames(robot, q);
//   dmbd::viz::place_on_ground(scene, X_WB);               // lowest point on z = 0
//   const auto camera = dmbd::viz::default_robot_camera(1.3);
#include <string>
#include <vector>

#include "dmbd/model/robot_description.hpp"
#include "dmbd/viz/renderer.hpp"

namespace dmbd::report {

struct RobotSceneOptions {
  int cylinder_segments = 24;  // around the axis (>= 3)
  int sphere_segments = 24;    // around the axis; half as many from pole to pole (>= 4)
  // Display (sRGB) colour of a link drawn from its collision shapes (a URDF gives
  // collisions no colour): a muted teal (hue 169 deg), unlike the grey a visual without
  // material gets, the ground, the sky, the table's wood and the overlays' colours, so
  // that a viewer sees which links are stand-ins.
  Eigen::Vector4f collision_rgba{0.30f, 0.62f, 0.56f, 1.0f};
};

// True when the link is drawn from its collision shapes: one of its visuals is a mesh
// whose file was not loaded (geometry.mesh null), or it has no visual, and at least one
// of its collision shapes can be drawn (a box, cylinder or sphere with positive sizes, or
// a mesh that loaded). A description read without meshes (UrdfOptions::load_meshes
// false) has every mesh visual unloaded, so its links are drawn this way too.
bool drawn_from_collisions(const model::Link& link);
// The names of the links drawn from their collision shapes, in link order.
std::vector<std::string> links_drawn_from_collisions(const model::RobotDescription& robot);

// One SceneBody per link (name = link name), one SceneMesh per drawn shape, in the link
// frame (the shape's X_LG applied). A link's visuals with their rgba; boxes, cylinders
// (along their z, centred) and spheres are tessellated; a Mesh visual whose triangles
// were not loaded is skipped. A link that drawn_from_collisions() names is drawn from
// its collision shapes instead, in options.collision_rgba (a collision shape with a zero
// size, or a mesh that did not load, has nothing to draw and is skipped); it is the
// robot whose meshes are not installed that stays visible this way.
// Throws std::invalid_argument for a visual with a non-positive primitive size or too
// few segments.
viz::Scene scene_from_robot(const model::RobotDescription& robot, const RobotSceneOptions& options = {});

}  // namespace dmbd::report
