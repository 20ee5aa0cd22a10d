#pragma once
// The repair rule for a rotational inertia that breaks the triangle inequality of its
// principal moments (A + B >= C for every ordering), as published robot files often do
// (Simbody's own Atlas example: link 'head', C above A + B by 13 %).
//
// The rule is MuJoCo's compiler option balanceinertia="true" (src/user/user_objects.cc,
// mjCBody::Compile: `inertia[0] = inertia[1] = inertia[2] = (inertia[0] + inertia[1] +
// inertia[2])/3.0;` applied to the principal moments when any of A + B < C, A + C < B,
// B + C < A holds): every principal moment becomes their mean, trace / 3. The principal
// axes are kept (R diag(mean) R^T), which for three equal moments is mean * identity:
// every axis is a principal axis, the trace (and so the mean moment) is unchanged, and
// the result is positive definite whenever the trace is positive.
#include <Eigen/Core>

namespace dmbd::model {

// The principal moments of a symmetric inertia, ascending (kg m^2).
Eigen::Vector3d principal_moments(const Eigen::Matrix3d& inertia);

// By how much the largest principal moment exceeds the sum of the other two, relative to
// that sum: (C - (A + B)) / (A + B) for ascending moments A <= B <= C. Zero or negative
// when the triangle inequality holds (a sphere gives -0.5, a flat plate 0).
double triangle_excess(const Eigen::Vector3d& ascending_moments);

// balanceinertia: the inertia with the same principal axes and every principal moment
// set to the mean of the three: exactly (trace / 3) times the identity.
Eigen::Matrix3d balance_inertia(const Eigen::Matrix3d& inertia);

}  // namespace dmbd::model
