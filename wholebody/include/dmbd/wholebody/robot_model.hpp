#pragma once
// The robot model a whole-body controller reads (Pinocchio's Model/Data split, TSID's
// "compute all terms" update): a constant description (Layout, the registered frames)
// and, per control tick, every dynamic quantity at one state written into storage
// allocated once (ModelData). Implementations: sim::DynamicsModel over
// model::RobotDynamics (Simbody behind it), and hand-derived models in the tests.
//
// Coordinates (the convention of model::RobotDynamics):
//   floating base (base_dofs = 6): q = [quaternion w x y z of the base in world (4),
//     base origin in world (3), joints], v = [base angular velocity in world (3),
//     base origin velocity in world (3), joint rates]; nq = nv + 1;
//   fixed base (base_dofs = 0): q = [joints], v = [joint rates]; nq = nv.
// Dynamics: A(q) v̇ + b(q, v) + g(q) = τ + Σ Jᵀ f. Frame Jacobians are 6 x nv,
// [angular; linear] in world axes at the frame's origin; Jdot_v is J̇ v.
#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace dmbd::wholebody {

struct JointLimits {
  double lower_rad = -std::numeric_limits<double>::infinity();
  double upper_rad = std::numeric_limits<double>::infinity();
  double effort_Nm = std::numeric_limits<double>::infinity();
  double velocity_rad_s = std::numeric_limits<double>::infinity();
};

struct Joint {
  std::string name;
  int q_index = 0;   // its entry in q
  int v_index = 0;   // its entry in v
  JointLimits limits;
};

struct Layout {
  int nq = 0, nv = 0;
  int base_dofs = 0;           // 0 fixed base, 6 floating base
  std::vector<Joint> joints;   // the joint coordinates (every one is actuated), in v order
  int joint_index(const std::string& name) const;  // into joints, or -1
};

// A frame fixed in a link: its origin at p_L in the link's frame, its axes the link's.
struct FrameSpec {
  std::string link;
  Eigen::Vector3d p_L = Eigen::Vector3d::Zero();
};

// One frame's quantities at the model's current state.
struct FrameData {
  Eigen::Isometry3d X_WF = Eigen::Isometry3d::Identity();
  Eigen::Matrix<double, 6, Eigen::Dynamic> J;         // 6 x nv, [angular; linear]
  Eigen::Matrix<double, 6, 1> Jdot_v = Eigen::Matrix<double, 6, 1>::Zero();
};

// Everything a controller reads at one state. Sized by RobotModel::make_data(); update()
// only writes into it.
struct ModelData {
  Eigen::VectorXd q, v;        // the state the terms below are for
  Eigen::MatrixXd A;           // nv x nv mass matrix
  Eigen::VectorXd bg;          // b + g (Coriolis, centrifugal and gravity), nv
  Eigen::VectorXd g;           // gravity alone, nv
  std::vector<FrameData> frames;  // one per registered frame, in registration order
  Eigen::Vector3d com = Eigen::Vector3d::Zero();    // world
  Eigen::Matrix<double, 3, Eigen::Dynamic> J_com;   // 3 x nv
  Eigen::Vector3d com_Jdot_v = Eigen::Vector3d::Zero();
};

class RobotModel {
 public:
  virtual ~RobotModel() = default;
  virtual const Layout& layout() const = 0;
  // Registers a frame and returns its index into ModelData::frames. Frames are
  // registered before make_data(); an unknown link throws InputError.
  virtual int add_frame(const FrameSpec& frame) = 0;
  virtual int num_frames() const = 0;
  // Storage for every quantity, for the frames registered so far.
  ModelData make_data() const;
  // Writes every quantity at (q, v) into `data` (made by make_data()). Allocation-free.
  virtual void update(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& v,
                      ModelData& data) = 0;
};

// Configuration-space arithmetic for the Layout's convention (a floating base's
// quaternion integrated on the sphere, its angular velocity in world axes).
// integrate: q_out = q ⊕ v dt.   difference: v_out with q0 ⊕ v_out = q1 (dt = 1).
void integrate(const Layout& layout, const Eigen::Ref<const Eigen::VectorXd>& q,
               const Eigen::Ref<const Eigen::VectorXd>& v, double dt, Eigen::Ref<Eigen::VectorXd> q_out);
void difference(const Layout& layout, const Eigen::Ref<const Eigen::VectorXd>& q0,
                const Eigen::Ref<const Eigen::VectorXd>& q1, Eigen::Ref<Eigen::VectorXd> v_out);

}  // namespace dmbd::wholebody
