#pragma once
// The whole robot's momentum from the model's mass matrix (robot_model.hpp's floating-base
// convention): the base's rows of A v are the generalised momentum conjugate to the base's
// angular velocity and origin velocity in world axes, i.e. the angular momentum about the
// base origin o and the linear momentum P, both in world axes. About any point p:
// L_p = L_o + (o − p) × P. Allocation-free.
#include <Eigen/Core>

#include "dmbd/wholebody/robot_model.hpp"

namespace dmbd::wholebody {

// The angular momentum about the world point p (kg m²/s, world axes) at data's state.
// The layout must have a floating base (base_dofs = 6); data must be up to date.
Eigen::Vector3d angular_momentum_about(const ModelData& data, const Eigen::Vector3d& p);

// The pendulum velocity of a point foot at p: (L_y, −L_x)/(m h), m the robot's mass,
// h the pendulum's height. Over a point contact with no ankle torque
// L̇_p = (c − p) × m g exactly, so (in x and y) it obeys the linear inverted pendulum's
// velocity equation whatever the legs and torso do inside (the ALIP state; Gong and
// Grizzle, "Angular momentum about the contact point for control of bipedal locomotion:
// validation in a LIP-based controller", 2021).
Eigen::Vector2d contact_pendulum_velocity(const ModelData& data, const Eigen::Vector3d& p, double height_m);

}  // namespace dmbd::wholebody
