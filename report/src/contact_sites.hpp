#pragma once
// Internal to report/: where the frames draw a logged contact force (contact.K.fx/fy/fz).
// One site per shape the plant lets collide, numbered as model::Plant::contacts() and
// the log number them: links in order, collision shapes in URDF order, a shape counted
// when it has contact elements (model/src/contact_elements.cpp, mirrored here: a
// sphere; a box; a cylinder of positive radius; a mesh with contact points, i.e. with
// hull points or loaded vertices).
//
// The log holds each shape's force but not where it acts, so the frames find that
// point from the frame's pose, the ground being the plane z = 0:
//   sphere:  its lowest point, c - r z (as the plant's reading);
//   others:  the centre of pressure of the elastic part of the normal loads,
//            p = sum_i x_i p_i / sum_i x_i over the shape's points p_i below the ground
//            at depth x_i = -z_i > 0 (the plant's linear law F = k x (1 + d xdot) without
//            its damping term: exact in statics); its lowest point when none is below.
//            The points: a box's 8 corners and a mesh's hull points (the plant's own
//            contact points; a mesh without hull points, built in code, uses all its
//            vertices), a cylinder's two rim circles sampled every 5 deg (its rings'
//            load per unit length is kappa x, so the sum approximates the plant's ring
//            integral; exact for a cylinder standing on an end by symmetry).
#include <vector>

#include <Eigen/Geometry>

#include "dmbd/model/robot_description.hpp"

namespace dmbd::report::detail {

struct ContactSite {
  int link = -1;   // robot.links index
  int shape = -1;  // index into robot.links[link].collisions
  model::Geometry::Kind kind = model::Geometry::Kind::Sphere;
  Eigen::Vector3d center_L = Eigen::Vector3d::Zero();  // sphere: centre, link frame, m
  double radius_m = 0;                                 // sphere
  std::vector<Eigen::Vector3d> points_L;               // other shapes: their points, link frame, m
};

constexpr int kRimSamples = 72;  // per cylinder rim (every 5 deg)

// The sites of every colliding shape, in the plant's order.
std::vector<ContactSite> contact_sites(const model::RobotDescription& robot);

// Where the site's force is drawn with its link at X_WL (world, m), as stated above.
Eigen::Vector3d contact_point(const ContactSite& site, const Eigen::Isometry3d& X_WL);

}  // namespace dmbd::report::detail
