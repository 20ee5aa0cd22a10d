// The robot model (docs/python.md, "The robot model"): load_robot, RobotModel and its
// description (LinkInfo, JointInfo), Placement and ReferenceFrame. The computations and
// the conventions are robot_model.hpp's; this file only converts arguments and results.
#include "bindings.hpp"
#include "convert.hpp"
#include "robot_model.hpp"

#include <algorithm>
#include <cctype>
#include <limits>
#include <optional>
#include <sstream>

#include "dmbd/base/error.hpp"

namespace dmbd::python {

using namespace pybind11::literals;

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

struct LinkInfo {
  std::string name;
  double mass = 0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  std::optional<std::string> parent_joint;
};

struct JointInfo {
  std::string name, type, parent, child;
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  Eigen::Isometry3d placement = Eigen::Isometry3d::Identity();
  double lower = -kInf, upper = kInf, velocity_limit = kInf, effort_limit = kInf, damping = 0, friction = 0;
  std::optional<int> q_index, v_index;
  bool welded = false;
};

Eigen::VectorXd vec(const py::handle& x, const char* what) {
  const std::vector<double> v = to_vector(x, what);
  return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
}

ReferenceFrame reference_frame_of(const py::handle& x) {
  if (py::isinstance<ReferenceFrame>(x)) return x.cast<ReferenceFrame>();
  if (py::isinstance<py::str>(x)) {
    std::string s = x.cast<std::string>();
    for (char& c : s) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    if (s == "LOCAL") return ReferenceFrame::Local;
    if (s == "WORLD") return ReferenceFrame::World;
    if (s == "LOCAL_WORLD_ALIGNED") return ReferenceFrame::LocalWorldAligned;
    throw InputError("reference_frame '" + x.cast<std::string>() + "': expected LOCAL, WORLD or LOCAL_WORLD_ALIGNED");
  }
  throw py::type_error("reference_frame: expected a dmbd.ReferenceFrame or its name");
}

std::vector<LinkInfo> links_of(const RobotModel& m) {
  const model::RobotDescription& r = m.description();
  std::vector<LinkInfo> out;
  for (int l = 0; l < static_cast<int>(r.links.size()); ++l) {
    const model::Link& link = r.links[static_cast<std::size_t>(l)];
    LinkInfo i{link.name, link.mass_kg, link.com_m, link.inertia_kgm2, std::nullopt};
    const int j = r.parent_joint_of_link(l);
    if (j >= 0) i.parent_joint = r.joints[static_cast<std::size_t>(j)].name;
    out.push_back(i);
  }
  return out;
}

std::vector<JointInfo> joints_of(const RobotModel& m) {
  const model::RobotDescription& r = m.description();
  const auto& welded = m.dynamics().welded_joints();
  std::vector<JointInfo> out;
  for (int j = 0; j < static_cast<int>(r.joints.size()); ++j) {
    const model::Joint& jt = r.joints[static_cast<std::size_t>(j)];
    JointInfo i;
    i.name = jt.name;
    i.type = model::joint_type_name(jt.type);
    i.parent = jt.parent;
    i.child = jt.child;
    i.axis = jt.axis;
    i.placement = jt.X_PJ;
    i.damping = jt.damping;
    i.friction = jt.friction;
    if (jt.has_limits && jt.upper > jt.lower && jt.type != model::JointType::Continuous) {
      i.lower = jt.lower;
      i.upper = jt.upper;
    }
    if (jt.velocity > 0) i.velocity_limit = jt.velocity;
    if (jt.effort > 0) i.effort_limit = jt.effort;
    if (m.joint_q_index(j) >= 0) {
      i.q_index = m.joint_q_index(j);
      i.v_index = m.joint_v_index(j);
    }
    i.welded = std::find(welded.begin(), welded.end(), jt.name) != welded.end();
    out.push_back(i);
  }
  return out;
}

std::string repr(const Eigen::Isometry3d& X) {
  std::ostringstream s;
  s.precision(6);
  const Eigen::IOFormat matrix(Eigen::StreamPrecision, Eigen::DontAlignCols, ", ", ", ", "[", "]", "[", "]");
  const Eigen::IOFormat vector(Eigen::StreamPrecision, Eigen::DontAlignCols, ", ", ", ", "", "", "[", "]");
  s << "Placement(rotation=" << X.linear().format(matrix) << ", translation=" << X.translation().transpose().format(vector) << ")";
  return s.str();
}

void bind_placement(py::module_& m) {
  py::class_<Eigen::Isometry3d>(m, "Placement", R"doc(
A rigid transform X_AB (Pinocchio's SE3): `rotation` R_AB (3 x 3) and `translation` p_AB
(m), the pose of frame B in frame A. X_AC = X_AB * X_BC; X.act(p_B) = R p_B + p = p_A.)doc")
      .def(py::init([](const Eigen::Matrix3d& R, const Eigen::Vector3d& p) {
             Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
             X.linear() = R;
             X.translation() = p;
             return X;
           }),
           "rotation"_a = Eigen::Matrix3d(Eigen::Matrix3d::Identity()), "translation"_a = Eigen::Vector3d(Eigen::Vector3d::Zero()))
      .def_property_readonly("rotation", [](const Eigen::Isometry3d& X) -> Eigen::Matrix3d { return X.linear(); })
      .def_property_readonly("translation", [](const Eigen::Isometry3d& X) -> Eigen::Vector3d { return X.translation(); })
      .def_property_readonly("homogeneous", [](const Eigen::Isometry3d& X) -> Eigen::Matrix4d { return X.matrix(); },
                             "The 4 x 4 homogeneous matrix.")
      .def("inverse", [](const Eigen::Isometry3d& X) -> Eigen::Isometry3d { return X.inverse(); })
      .def("act", [](const Eigen::Isometry3d& X, const Eigen::Vector3d& p) -> Eigen::Vector3d { return X * p; }, "point"_a)
      .def("__mul__", [](const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) -> Eigen::Isometry3d { return a * b; })
      .def("__repr__", [](const Eigen::Isometry3d& X) { return repr(X); });
}

void bind_description(py::module_& m) {
  py::class_<LinkInfo>(m, "LinkInfo", "A link of the URDF: its mass (kg), centre of mass (m, link frame) and inertia (kg m², about the centre of mass, link axes).")
      .def_readonly("name", &LinkInfo::name)
      .def_readonly("mass", &LinkInfo::mass)
      .def_readonly("com", &LinkInfo::com)
      .def_readonly("inertia", &LinkInfo::inertia)
      .def_readonly("parent_joint", &LinkInfo::parent_joint, "The joint whose child it is (None for the root).")
      .def("__repr__", [](const LinkInfo& l) { return "LinkInfo('" + l.name + "', mass=" + std::to_string(l.mass) + ")"; });
  py::class_<JointInfo>(m, "JointInfo", R"doc(
A joint of the URDF: `type` ("revolute", "continuous", "prismatic" or "fixed"), `parent` and
`child` links, `axis` (unit, joint frame), `placement` (the joint frame, which is the child
link's frame, in the parent link's frame), position limits `lower`/`upper` (rad or m),
`velocity_limit` (rad/s or m/s), `effort_limit` (N m or N), ±inf where the URDF gives
none; `damping`, `friction` as in the URDF; `q_index`/`v_index` its entries in q and v,
None when it has no coordinate (fixed, or `welded`: a moving joint that moves only
massless links is welded).)doc")
      .def_readonly("name", &JointInfo::name)
      .def_readonly("type", &JointInfo::type)
      .def_readonly("parent", &JointInfo::parent)
      .def_readonly("child", &JointInfo::child)
      .def_readonly("axis", &JointInfo::axis)
      .def_readonly("placement", &JointInfo::placement)
      .def_readonly("lower", &JointInfo::lower)
      .def_readonly("upper", &JointInfo::upper)
      .def_readonly("velocity_limit", &JointInfo::velocity_limit)
      .def_readonly("effort_limit", &JointInfo::effort_limit)
      .def_readonly("damping", &JointInfo::damping)
      .def_readonly("friction", &JointInfo::friction)
      .def_readonly("q_index", &JointInfo::q_index)
      .def_readonly("v_index", &JointInfo::v_index)
      .def_readonly("welded", &JointInfo::welded)
      .def("__repr__", [](const JointInfo& j) { return "JointInfo('" + j.name + "', " + j.type + ")"; });
}

std::unique_ptr<RobotModel> load(const py::handle& name_or_urdf, const std::string& base, double gravity) {
  return RobotModel::load(to_path(name_or_urdf), base, gravity);
}

const char* const kLoadDoc = R"doc(
A robot by name (a robot folder robots/NAME or on DMBD_ROBOT_PATH, docs/robot-folder.md) or
a URDF file (str or os.PathLike; a name with a '/', ending in .urdf or naming an existing
file is a file): its bare rigid-body tree (no actuators, contact or joint
limits in the dynamics). base: "fixed" (the root link welded at the world origin) or
"floating" (a free 6-dof root: q starts with its quaternion w x y z and position).
gravity: m/s² along -z of the world.)doc";

void bind_robot_model(py::module_& m) {
  py::class_<RobotModel>(m, "RobotModel", R"doc(
A robot's rigid-body model, queried as in Pinocchio: M(q), b(q, v), g(q), frame placements
and Jacobians, the centre of mass, forward and inverse dynamics, as NumPy arrays. The
conventions (coordinates, Jacobian rows, reference frames) are docs/python.md's, "The robot
model". engine="kernel" (default) is the project's tree kernel, engine="simbody" Simbody's
own operators on the same tree (a reference for checks; slower).)doc")
      .def(py::init(&load), "name_or_urdf"_a, "base"_a = "fixed", "gravity"_a = 9.81, kLoadDoc)
      .def_property_readonly("name", [](const RobotModel& r) { return r.description().name; })
      .def_property_readonly("source", [](const RobotModel& r) { return r.description().source; }, "The URDF file read.")
      .def_property_readonly("base", [](const RobotModel& r) { return r.floating() ? "floating" : "fixed"; })
      .def_property_readonly("root_link", [](const RobotModel& r) { return r.description().links.front().name; })
      .def_property_readonly("nq", [](const RobotModel& r) { return r.layout().nq; })
      .def_property_readonly("nv", [](const RobotModel& r) { return r.layout().nv; })
      .def_property_readonly("gravity", &RobotModel::gravity_m_s2, "m/s², along -z of the world.")
      .def_property_readonly("warnings", [](const RobotModel& r) { return r.description().warnings; },
                             "The URDF loader's warnings, one line each (unknown tags, repaired inertias).")
      .def_property_readonly("total_mass", [](const RobotModel& r) { return r.dynamics().total_mass_kg(); }, "kg")
      .def_property_readonly("link_names", &RobotModel::link_names)
      .def_property_readonly("joint_names", [](const RobotModel& r) { return r.dynamics().joint_names(); },
                             "The joints that have a coordinate, in the order of q and v (after the base).")
      .def_property_readonly("frame_names", &RobotModel::frame_names,
                             "What `frame` arguments accept: the links, then every joint (a joint's frame is its child link's).")
      .def_property_readonly("links", &links_of)
      .def_property_readonly("joints", &joints_of, "Every joint of the URDF (fixed ones too), parents first.")
      .def_property_readonly("lower_position_limit", &RobotModel::lower_position_limit, "nq entries; -inf on the base and where none.")
      .def_property_readonly("upper_position_limit", &RobotModel::upper_position_limit, "nq entries; inf on the base and where none.")
      .def_property_readonly("velocity_limit", &RobotModel::velocity_limit, "nv entries; inf on the base and where none.")
      .def_property_readonly("effort_limit", &RobotModel::effort_limit, "nv entries; inf on the base and where none.")
      .def("neutral", &RobotModel::neutral, "The base at the world origin, unrotated (floating), and every joint at 0.")
      .def("integrate", [](const RobotModel& r, const py::handle& q, const py::handle& v) { return r.integrate(vec(q, "q"), vec(v, "v")); },
           "q"_a, "v"_a, "q ⊕ v: the configuration reached from q at the constant generalised velocity v after 1 s.")
      .def("difference", [](const RobotModel& r, const py::handle& q0, const py::handle& q1) { return r.difference(vec(q0, "q0"), vec(q1, "q1")); },
           "q0"_a, "q1"_a, "v with integrate(q0, v) = q1 (the base's rotation the shorter way).")
      .def("mass_matrix", [](RobotModel& r, const py::handle& q, const std::string& e) { return r.mass_matrix(vec(q, "q"), engine_named(e)); },
           "q"_a, "engine"_a = "kernel", "M(q), nv x nv.")
      .def("bias_forces",
           [](RobotModel& r, const py::handle& q, const py::handle& v, const std::string& e) {
             return r.bias_forces(vec(q, "q"), vec(v, "v"), engine_named(e));
           },
           "q"_a, "v"_a, "engine"_a = "kernel", "b(q, v): Coriolis, centrifugal and gravity (Pinocchio's nonLinearEffects).")
      .def("gravity_forces", [](RobotModel& r, const py::handle& q, const std::string& e) { return r.gravity_forces(vec(q, "q"), engine_named(e)); },
           "q"_a, "engine"_a = "kernel", "g(q) (Pinocchio's computeGeneralizedGravity).")
      .def("forward_dynamics",
           [](RobotModel& r, const py::handle& q, const py::handle& v, const py::handle& tau, const std::string& e) {
             return r.forward_dynamics(vec(q, "q"), vec(v, "v"), vec(tau, "tau"), engine_named(e));
           },
           "q"_a, "v"_a, "tau"_a, "engine"_a = "kernel", "a with M(q) a + b(q, v) = tau (Pinocchio's aba).")
      .def("inverse_dynamics",
           [](RobotModel& r, const py::handle& q, const py::handle& v, const py::handle& a, const std::string& e) {
             return r.inverse_dynamics(vec(q, "q"), vec(v, "v"), vec(a, "a"), engine_named(e));
           },
           "q"_a, "v"_a, "a"_a, "engine"_a = "kernel", "tau = M(q) a + b(q, v) (Pinocchio's rnea).")
      .def("frame_placement",
           [](RobotModel& r, const py::handle& q, const std::string& frame, const std::string& e) {
             return r.frame_placement(vec(q, "q"), frame, engine_named(e));
           },
           "q"_a, "frame"_a, "engine"_a = "kernel", "The frame's pose in the world, a Placement.")
      .def("frame_jacobian",
           [](RobotModel& r, const py::handle& q, const std::string& frame, const py::handle& rf, const std::string& e) {
             return r.frame_jacobian(vec(q, "q"), frame, reference_frame_of(rf), engine_named(e));
           },
           "q"_a, "frame"_a, "reference_frame"_a = ReferenceFrame::LocalWorldAligned, "engine"_a = "kernel",
           "6 x nv, rows [linear; angular] in reference_frame (a ReferenceFrame or its name).")
      .def("com", [](RobotModel& r, const py::handle& q, const std::string& e) { return r.com(vec(q, "q"), engine_named(e)); },
           "q"_a, "engine"_a = "kernel", "The centre of mass in the world (m).")
      .def("com_jacobian", [](RobotModel& r, const py::handle& q, const std::string& e) { return r.com_jacobian(vec(q, "q"), engine_named(e)); },
           "q"_a, "engine"_a = "kernel", "3 x nv, world axes.")
      .def("__repr__", [](const RobotModel& r) {
        return "RobotModel('" + r.description().name + "', nq=" + std::to_string(r.layout().nq) + ", nv=" +
               std::to_string(r.layout().nv) + ", " + (r.floating() ? "floating" : "fixed") + " base)";
      });
  m.def("load_robot", &load, "name_or_urdf"_a, "base"_a = "fixed", "gravity"_a = 9.81, kLoadDoc);
}

}  // namespace

void bind_model(py::module_& m) {
  py::enum_<ReferenceFrame>(m, "ReferenceFrame", R"doc(
Where a frame Jacobian's velocity is taken and in which axes (Pinocchio's meanings):
LOCAL the frame's origin, the frame's axes; WORLD the body's point at the world origin,
world axes (the spatial velocity); LOCAL_WORLD_ALIGNED the frame's origin, world axes.)doc")
      .value("LOCAL", ReferenceFrame::Local)
      .value("WORLD", ReferenceFrame::World)
      .value("LOCAL_WORLD_ALIGNED", ReferenceFrame::LocalWorldAligned);
  bind_placement(m);
  bind_description(m);
  bind_robot_model(m);
}

}  // namespace dmbd::python
