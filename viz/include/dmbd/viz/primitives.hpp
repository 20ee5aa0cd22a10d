#pragma once
// Closed primitive meshes, mesh transforms and a default camera for a robot: what any
// scene is built from (report/ builds a robot's from its description).
#include <Eigen/Geometry>

#include "dmbd/viz/renderer.hpp"

namespace dmbd::viz {

// Closed, outward-wound primitive meshes centred at the origin, with vertex normals
// (flat per face for the box and the cylinder caps, smooth on curved surfaces).
// Throw std::invalid_argument for a non-positive size or too few segments.
SceneMesh box_mesh(const Eigen::Vector3d& size_m);                             // full edge lengths
SceneMesh cylinder_mesh(double radius_m, double length_m, int segments = 24);  // along z
SceneMesh sphere_mesh(double radius_m, int segments = 24);

// The mesh with its vertices and normals moved by X.
SceneMesh transformed(SceneMesh m, const Eigen::Isometry3d& X);

// A 3/4 view from the front-left (x forward, y left) of a robot `robot_height_m` tall
// standing on the ground at `ground_point_W`: looks at half its height from 35 deg
// left of straight ahead and 12 deg above, far enough that it fills about 75% of the
// image height.
Camera default_robot_camera(double robot_height_m, int width_px = 1280, int height_px = 720,
                            const Eigen::Vector3d& ground_point_W = Eigen::Vector3d::Zero());

}  // namespace dmbd::viz
