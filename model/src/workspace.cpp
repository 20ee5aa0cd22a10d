// A link's workspace by sampling the joint space: the chain, the sampler, the positions.
#include "dmbd/model/workspace.hpp"

#include <algorithm>
#include <cmath>
#include <random>
#include <set>

#include "dmbd/model/error.hpp"

namespace dmbd::model {

namespace {

constexpr double kPi = 3.14159265358979323846;

bool moves(JointType t) {
  return t == JointType::Revolute || t == JointType::Continuous || t == JointType::Prismatic;
}

// Joints from the root down to `link` (their indices).
std::set<int> joints_above(const RobotDescription& robot, int link) {
  std::set<int> out;
  for (int j = robot.parent_joint_of_link(link); j >= 0;
       j = robot.parent_joint_of_link(robot.link_index(robot.joints[static_cast<std::size_t>(j)].parent)))
    if (!out.insert(j).second) break;  // a loop cannot happen in a loaded tree; stop anyway
  return out;
}

int find_link(const RobotDescription& robot, const std::string& name) {
  const int i = robot.link_index(name);
  if (i < 0) throw ModelError("no link '" + name + "' in robot '" + robot.name + "'");
  return i;
}

}  // namespace

std::vector<ChainJoint> moving_chain(const RobotDescription& robot, const std::string& link,
                                     const std::string& reference) {
  const std::set<int> a = joints_above(robot, find_link(robot, link));
  const std::set<int> b = joints_above(robot, find_link(robot, reference));
  std::vector<int> path;  // in one set only: the path between the two links
  std::set_symmetric_difference(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(path));
  std::vector<ChainJoint> chain;
  for (int j : path) {  // robot.joints is parent before child: root side first
    const Joint& joint = robot.joints[static_cast<std::size_t>(j)];
    if (!moves(joint.type)) continue;
    ChainJoint c{j, joint.name, joint.lower, joint.upper, !joint.has_limits};
    if (c.unlimited) c.lower = -kPi, c.upper = kPi;
    chain.push_back(c);
  }
  if (chain.empty())
    throw ModelError("link '" + link + "' is not below a moving joint (none between it and '" + reference + "')");
  return chain;
}

std::vector<double> rest_positions(const RobotDescription& robot) {
  std::vector<double> q(robot.joints.size(), 0.0);
  for (std::size_t j = 0; j < q.size(); ++j)
    if (robot.joints[j].has_limits && robot.joints[j].lower <= robot.joints[j].upper)
      q[j] = std::clamp(0.0, robot.joints[j].lower, robot.joints[j].upper);
  return q;
}

Eigen::MatrixXd sample_joint_space(const std::vector<ChainJoint>& chain, std::size_t n, std::uint64_t seed) {
  if (n < 1) throw ModelError("the number of samples must be at least 1 (got " + std::to_string(n) + ")");
  std::mt19937_64 rng(seed);
  Eigen::MatrixXd q(static_cast<Eigen::Index>(n), static_cast<Eigen::Index>(chain.size()));
  for (Eigen::Index k = 0; k < q.rows(); ++k)
    for (Eigen::Index i = 0; i < q.cols(); ++i) {
      const double u = static_cast<double>(rng() >> 11) * 0x1.0p-53;  // [0, 1), 53 bits
      const ChainJoint& c = chain[static_cast<std::size_t>(i)];
      q(k, i) = c.lower + u * (c.upper - c.lower);
    }
  return q;
}

Workspace sample_workspace(const RobotDescription& robot, const std::string& link, const std::string& reference,
                           const WorkspaceOptions& options) {
  Workspace ws;
  ws.link = link;
  ws.reference = reference;
  ws.chain = moving_chain(robot, link, reference);
  ws.samples = options.samples;
  ws.seed = options.seed;
  const Eigen::MatrixXd qs = sample_joint_space(ws.chain, options.samples, options.seed);
  const std::size_t L = static_cast<std::size_t>(robot.link_index(link));
  const std::size_t R = static_cast<std::size_t>(robot.link_index(reference));
  std::vector<double> q = rest_positions(robot);
  ws.points.reserve(options.samples);
  for (Eigen::Index k = 0; k < qs.rows(); ++k) {
    for (std::size_t i = 0; i < ws.chain.size(); ++i)
      q[static_cast<std::size_t>(ws.chain[i].joint)] = qs(k, static_cast<Eigen::Index>(i));
    const std::vector<Eigen::Isometry3d> X_WL = link_frames(robot, q);
    ws.points.push_back(X_WL[R].inverse() * X_WL[L].translation());
  }
  ws.min = ws.max = ws.points.front();
  for (const Eigen::Vector3d& p : ws.points) {
    ws.min = ws.min.cwiseMin(p);
    ws.max = ws.max.cwiseMax(p);
  }
  return ws;
}

}  // namespace dmbd::model
