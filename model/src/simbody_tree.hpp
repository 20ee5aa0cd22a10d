#pragma once
// Internal to model/: builds a robot description's multibody tree in Simbody. Included
// only by model/src/*.cpp (Simbody stays out of the public headers).

#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/robot_description.hpp"

#include <Simbody.h>

#include <string>
#include <vector>

namespace dmbd::model::detail {

inline SimTK::Vec3 to_simtk(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }
inline Eigen::Vector3d to_eigen(const SimTK::Vec3& v) { return {v[0], v[1], v[2]}; }
SimTK::Transform to_simtk(const Eigen::Isometry3d& X);
Eigen::Isometry3d to_eigen(const SimTK::Transform& X);

struct Tree {
  std::vector<SimTK::MobilizedBodyIndex> link_body;  // per description link
  std::vector<int> coord_joint;                      // description joint per joint coordinate
  std::vector<SimTK::MobilizedBodyIndex> coord_body; // its mobilized body (one q, one u)
  std::vector<std::string> joint_names;              // per joint coordinate
  std::vector<std::string> welded;                   // 1-dof joints moving only massless links
  std::vector<double> link_mass;                     // as built (after mass moved to actuators)
  SimTK::MobilizedBodyIndex root;
  int base_dofs = 0;
};

// Adds the tree to `matter`. `mass_taken[l]` (kg, may be empty) is removed from link l
// at its centre of mass (inertia scaled by the remaining fraction): actuator housings
// built as separate bodies carry it instead.
Tree build_tree(const RobotDescription& robot, SimTK::SimbodyMatterSubsystem& matter, BaseMode base,
                const Eigen::Isometry3d& X_WB, const std::vector<double>& mass_taken = {});

// Simbody's q/u of the tree's joint coordinates and base in the layout of dynamics.hpp.
Eigen::VectorXd gather_q(const Tree& t, const SimTK::SimbodyMatterSubsystem& m, const SimTK::State& s);
Eigen::VectorXd gather_u(const Tree& t, const SimTK::SimbodyMatterSubsystem& m, const SimTK::State& s);
void scatter_q(const Tree& t, const SimTK::SimbodyMatterSubsystem& m, SimTK::State& s, const Eigen::VectorXd& q);
void scatter_u(const Tree& t, const SimTK::SimbodyMatterSubsystem& m, SimTK::State& s, const Eigen::VectorXd& u);

}  // namespace dmbd::model::detail
