// The workspace sampler (model/workspace.hpp) on DRACO: the chain and its limits, the
// joint-space sampler, the positions against Simbody's forward kinematics, and the
// sampled extents against the exact reachable extremes found by another method
// (exact coordinate ascent over the joint box from a grid of starts).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "dmbd/model/dynamics.hpp"
#include "dmbd/model/error.hpp"
#include "dmbd/model/robot_description.hpp"
#include "dmbd/model/workspace.hpp"

namespace dmbd::model {
namespace {

constexpr double kPi = 3.14159265358979323846;

const RobotDescription& draco() {
  static const RobotDescription robot = [] {
    UrdfOptions o;
    o.load_meshes = false;
    return load_urdf(std::string(DMBD_ROBOTS_DIR "/draco") + "/draco.urdf", o);
  }();
  return robot;
}

std::vector<std::string> names(const std::vector<ChainJoint>& chain) {
  std::vector<std::string> out;
  for (const ChainJoint& c : chain) out.push_back(c.name);
  return out;
}

TEST(Workspace, ChainIsTheMovingJointsBetweenTheLinksWithTheirUrdfLimits) {
  const auto chain = moving_chain(draco(), "l_foot", "torso");
  EXPECT_EQ(names(chain), (std::vector<std::string>{"l_hip_yaw", "l_hip_roll", "l_hip_pitch", "l_knee", "l_ankle"}));
  for (const ChainJoint& c : chain) {
    const Joint& j = draco().joints[static_cast<std::size_t>(c.joint)];
    EXPECT_EQ(j.name, c.name);
    EXPECT_EQ(c.lower, j.lower);
    EXPECT_EQ(c.upper, j.upper);
    EXPECT_FALSE(c.unlimited);
  }
  EXPECT_EQ(names(moving_chain(draco(), "l_foot", "l_thigh")), (std::vector<std::string>{"l_knee", "l_ankle"}));
  EXPECT_EQ(moving_chain(draco(), "l_foot", "r_foot").size(), 10u);  // up one leg, down the other
}

TEST(Workspace, UnknownLinksAndLinksNotBelowAMovingJointAreNamed) {
  try {
    moving_chain(draco(), "l_fot", "torso");
    FAIL() << "no throw";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("no link 'l_fot'"), std::string::npos) << e.what();
  }
  try {
    moving_chain(draco(), "torso", "torso");
    FAIL() << "no throw";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'torso' is not below a moving joint"), std::string::npos) << e.what();
  }
  EXPECT_THROW(sample_joint_space(moving_chain(draco(), "l_foot", "torso"), 0, 1), ModelError);
}

// A continuous joint is sampled over [-pi, pi]; a joint whose range excludes 0 rests
// at the nearer limit.
TEST(Workspace, ContinuousJointsSpanMinusPiToPiAndRestIsClampedIntoTheLimits) {
  const std::string xml = R"(<robot name="arm">
    <link name="base"/><link name="a"/><link name="b"/>
    <joint name="spin" type="continuous"><parent link="base"/><child link="a"/><axis xyz="0 0 1"/></joint>
    <joint name="lift" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0.3 0 0"/>
      <axis xyz="0 1 0"/><limit lower="0.2" upper="0.5" effort="1" velocity="1"/></joint></robot>)";
  const RobotDescription r = parse_urdf(xml, ".", "arm.urdf");
  const auto chain = moving_chain(r, "b", "base");
  ASSERT_EQ(chain.size(), 2u);
  EXPECT_TRUE(chain[0].unlimited);
  EXPECT_EQ(chain[0].lower, -kPi);
  EXPECT_EQ(chain[0].upper, kPi);
  EXPECT_EQ(rest_positions(r), (std::vector<double>{0.0, 0.2}));
}

// Uniform within each interval: never outside it, and each end approached within
// range * ln(10^6) / N (the chance that none of N samples falls into the first
// ln(10^6)/N of the range is (1 - ln(10^6)/N)^N < 10^-6); the mean within 5 standard
// errors (range / sqrt(12 N)) of the middle. The same seed gives the same samples.
TEST(Workspace, SamplerIsUniformWithinTheLimitsAndRepeatableBySeed) {
  const auto chain = moving_chain(draco(), "l_foot", "torso");
  const std::size_t n = 100000;
  const Eigen::MatrixXd q = sample_joint_space(chain, n, 7);
  EXPECT_EQ(q, sample_joint_space(chain, n, 7));
  EXPECT_NE(q, sample_joint_space(chain, n, 8));
  for (std::size_t i = 0; i < chain.size(); ++i) {
    const auto col = q.col(static_cast<Eigen::Index>(i));
    const double r = chain[i].upper - chain[i].lower, edge = r * std::log(1e6) / n;
    EXPECT_GE(col.minCoeff(), chain[i].lower);
    EXPECT_LT(col.maxCoeff(), chain[i].upper);
    EXPECT_LT(col.minCoeff() - chain[i].lower, edge) << chain[i].name;
    EXPECT_LT(chain[i].upper - col.maxCoeff(), edge) << chain[i].name;
    EXPECT_NEAR(col.mean(), 0.5 * (chain[i].lower + chain[i].upper), 5 * r / std::sqrt(12.0 * n)) << chain[i].name;
  }
}

// Simbody's forward kinematics (RobotDynamics, fixed base at the identity) of the foot
// at a chain configuration, every other joint at 0.
class SimbodyFoot {
 public:
  SimbodyFoot() : dyn_(draco(), fixed()), chain_(moving_chain(draco(), "l_foot", "torso")) {
    for (const ChainJoint& c : chain_) index_.push_back(dyn_.joint_q_index(dyn_.joint_index(c.name)));
    foot_ = dyn_.link_index("l_foot");
  }
  Eigen::Vector3d operator()(const Eigen::VectorXd& qc) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(dyn_.nq());
    for (std::size_t i = 0; i < index_.size(); ++i) q[index_[i]] = qc[static_cast<Eigen::Index>(i)];
    dyn_.set_state(q, Eigen::VectorXd::Zero(dyn_.nv()));
    return dyn_.link_pose(foot_).translation();
  }
  const std::vector<ChainJoint>& chain() const { return chain_; }

 private:
  static DynamicsOptions fixed() {
    DynamicsOptions o;
    o.base = BaseMode::Fixed;
    return o;
  }
  RobotDynamics dyn_;
  std::vector<ChainJoint> chain_;
  std::vector<int> index_;
  int foot_ = -1;
};

TEST(Workspace, PositionsAgreeWithSimbodysForwardKinematicsAtEverySample) {
  const Workspace ws = sample_workspace(draco(), "l_foot", "torso", {100000, 3});
  const Eigen::MatrixXd q = sample_joint_space(ws.chain, ws.samples, ws.seed);
  ASSERT_EQ(ws.points.size(), ws.samples);
  SimbodyFoot foot;
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(1e9), hi = -lo;
  double worst = 0;
  for (Eigen::Index k = 0; k < q.rows(); ++k) {
    const Eigen::Vector3d p = foot(q.row(k).transpose());
    worst = std::max(worst, (p - ws.points[static_cast<std::size_t>(k)]).norm());
    lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  }
  EXPECT_LT(worst, 1e-12);  // two forward-kinematics routines, double rounding only
  EXPECT_LT((lo - ws.min).norm(), 1e-12);
  EXPECT_LT((hi - ws.max).norm(), 1e-12);
}

// The exact extreme of one coordinate over the joint box: with all but joint i fixed a
// revolute chain's position is C + A cos q_i + B sin q_i (three evaluations give A, B,
// C), maximised exactly over [lower, upper]; coordinate ascent from each point of a
// 3^d grid (limits and middle) until no coordinate gains 1e-12 m.
struct Extreme {
  double value = -1e300;
  Eigen::VectorXd q;
};

Extreme exact_extreme(SimbodyFoot& foot, int axis, double sign) {
  const auto& chain = foot.chain();
  const int d = static_cast<int>(chain.size());
  const auto f = [&](const Eigen::VectorXd& q) { return sign * foot(q)[axis]; };
  Extreme best;
  for (int start = 0; start < static_cast<int>(std::pow(3, d)); ++start) {
    Eigen::VectorXd q(d);
    for (int i = 0, s = start; i < d; ++i, s /= 3)
      q[i] = chain[i].lower + 0.5 * (s % 3) * (chain[i].upper - chain[i].lower);
    double value = f(q);
    for (int sweep = 0; sweep < 200; ++sweep) {
      const double before = value;
      for (int i = 0; i < d; ++i) {
        const auto at = [&](double a) { Eigen::VectorXd u = q; u[i] = a; return f(u); };
        const double g0 = at(0), g1 = at(kPi / 2), g2 = at(kPi);
        const double C = 0.5 * (g0 + g2), A = 0.5 * (g0 - g2), B = g1 - C;
        std::vector<double> candidates{chain[i].lower, chain[i].upper};
        const double phi = std::atan2(B, A);
        for (int k = -2; k <= 2; ++k) {
          const double c = phi + 2 * kPi * k;
          if (c > chain[i].lower && c < chain[i].upper) candidates.push_back(c);
        }
        for (double c : candidates)
          if (C + A * std::cos(c) + B * std::sin(c) > C + A * std::cos(q[i]) + B * std::sin(q[i])) q[i] = c;
        value = f(q);
      }
      if (value - before < 1e-12) break;
    }
    if (value > best.value) best = {value, q};
  }
  return best;
}

// The tolerance the sample count gives. A cube C at the extreme q* (relative side 0.3 of
// each joint's range, inside the box, centred on q* where the box allows) holds the
// fraction v = 0.3^d of the box. Of M = 10000 points drawn uniformly in C (Simbody's
// kinematics, a generator of its own), a fraction phi(t) falls short of the extreme by
// less than t; the N samples then miss {short by < t} with probability at most
// (1 - v phi(t))^N < exp(-N v phi(t)). The tolerance is the smallest t with
// N v phi(t) >= 2 ln(10^6): a chance below 10^-12, a factor 10^6 to spare for the
// uncertainty of phi.
double tolerance_from_sample_count(SimbodyFoot& foot, const Extreme& e, int axis, double sign, std::size_t n) {
  const auto& chain = foot.chain();
  const int d = static_cast<int>(chain.size());
  const double side = 0.3, v = std::pow(side, d);
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<double> shortfall;
  for (int m = 0; m < 10000; ++m) {
    Eigen::VectorXd q = e.q;
    for (int i = 0; i < d; ++i) {
      const double lo = chain[static_cast<std::size_t>(i)].lower, hi = chain[static_cast<std::size_t>(i)].upper;
      const double w = side * (hi - lo), start = std::clamp(e.q[i] - w / 2, lo, hi - w);
      q[i] = start + w * u(rng);
    }
    shortfall.push_back(e.value - sign * foot(q)[axis]);
  }
  std::sort(shortfall.begin(), shortfall.end());
  const double phi = 2 * std::log(1e6) / (static_cast<double>(n) * v);
  EXPECT_LT(phi, 1) << "too few samples for this test";
  return shortfall[static_cast<std::size_t>(std::ceil(phi * shortfall.size()))];
}

// The sampled extents never pass the exact extremes, and fall short of them by at most
// the tolerance derived from the sample count (tolerance_from_sample_count).
TEST(Workspace, SampledExtentsLieWithinTheExactExtremesByTheSampleCountsTolerance) {
  const auto t0 = std::chrono::steady_clock::now();
  const std::size_t n = 100000;
  const Workspace ws = sample_workspace(draco(), "l_foot", "torso", {n, 1});
  SimbodyFoot foot;
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {1.0, -1.0}) {
      const Extreme e = exact_extreme(foot, axis, sign);
      const double sampled = sign > 0 ? ws.max[axis] : -ws.min[axis];
      const double tol = tolerance_from_sample_count(foot, e, axis, sign, n);
      const std::string what = std::string("xyz").substr(static_cast<std::size_t>(axis), 1) + (sign > 0 ? " max" : " min");
      EXPECT_LE(sampled, e.value + 1e-12) << what;
      EXPECT_GE(sampled, e.value - tol) << what << ": exact " << sign * e.value << " m, tolerance " << tol << " m";
      std::printf("%s: sampled %.4f m, exact %.4f m, short by %.4f m, tolerance %.4f m\n", what.c_str(),
                  sign * sampled, sign * e.value, e.value - sampled, tol);
    }
  std::printf("took %.2f s\n", std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
}

TEST(Workspace, DensityGridCountsEveryPointOnceInCellsAlignedToTheCellSize) {
  const std::vector<Eigen::Vector3d> p{{0.01, 5, -0.01}, {0.03, 5, -0.01}, {0.031, 5, 0.05}, {0.039, 0, 0.0499}};
  const DensityGrid g = density_grid(p, 0, 2, 0.02);
  EXPECT_DOUBLE_EQ(g.h0, 0.0);
  EXPECT_DOUBLE_EQ(g.v0, -0.02);
  EXPECT_EQ(g.cols, 2);
  EXPECT_EQ(g.rows, 4);  // -0.02 .. 0.06
  EXPECT_EQ(g.count(0, 0), 1);
  EXPECT_EQ(g.count(0, 1), 1);
  EXPECT_EQ(g.count(3, 1), 2);
  EXPECT_EQ(g.count(2, 1), 0);
  EXPECT_EQ(g.max_count, 2);
  double total = 0;
  for (double c : g.counts) total += c;
  EXPECT_EQ(total, 4);
  EXPECT_THROW(density_grid(p, 0, 0, 0.02), ModelError);
  EXPECT_THROW(density_grid(p, 0, 2, 0), ModelError);
  EXPECT_THROW(density_grid({}, 0, 2, 0.02), ModelError);
}

}  // namespace
}  // namespace dmbd::model
