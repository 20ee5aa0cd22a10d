#pragma once
// A robot as read from a URDF: links, joints, geometry and meshes. Plain data
// (Eigen, std), no Simbody and no urdfdom types: model/src/plant.cpp builds the
// Simbody system from it, viz/ renders its meshes, apps/ summarises it.
//
// Conventions: SI units; every pose is X_PC (child frame C expressed in parent
// frame P) as an Eigen::Isometry3d; inertia is about the link's centre of mass,
// expressed in the inertial frame's orientation rotated into the link frame.

#include <Eigen/Geometry>

#include <array>
#include <cstddef>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace dmbd::model {

// A triangle mesh in its file's units times the URDF scale, in the geometry frame.
struct TriangleMesh {
  std::string path;                            // resolved file that was read
  std::vector<Eigen::Vector3f> vertices;       // m
  std::vector<Eigen::Vector3f> normals;        // per vertex, unit (may be empty)
  std::vector<std::array<int, 3>> triangles;   // indices into vertices
};

struct Geometry {
  enum class Kind { Box, Cylinder, Sphere, Mesh };
  Kind kind = Kind::Box;
  Eigen::Vector3d box_size_m = Eigen::Vector3d::Zero();   // Box: full edge lengths
  double radius_m = 0;                                    // Cylinder, Sphere
  double length_m = 0;                                    // Cylinder (along its z)
  std::string mesh_uri;                                   // Mesh: as written in the URDF
  Eigen::Vector3d mesh_scale = Eigen::Vector3d::Ones();   // Mesh
  // Mesh: the loaded triangles (scale applied), or null when the file could not
  // be found or read (then its URI is listed in RobotDescription::meshes_missing).
  std::shared_ptr<const TriangleMesh> mesh;
  // Mesh of a <collision>: its contact points, the vertices of the mesh's convex hull in
  // the geometry frame (m), at most 64 (farthest-point sampled, with a warning, when the
  // hull has more). Filled by the loader; empty when the mesh did not load (the plant
  // computes it if a description built in code has a mesh but no hull).
  std::vector<Eigen::Vector3d> hull_m;
};

struct Shape {
  std::string name;                                        // may be empty
  Eigen::Isometry3d X_LG = Eigen::Isometry3d::Identity();  // geometry frame in link frame
  Geometry geometry;
  Eigen::Vector4d rgba{0.7, 0.7, 0.7, 1.0};                // visuals only
};

struct Link {
  std::string name;
  double mass_kg = 0;                                      // 0: massless (no <inertial>)
  Eigen::Vector3d com_m = Eigen::Vector3d::Zero();         // in link frame
  Eigen::Matrix3d inertia_kgm2 = Eigen::Matrix3d::Zero();  // about com, link-frame axes
  std::vector<Shape> visuals;
  std::vector<Shape> collisions;
};

enum class JointType { Fixed, Revolute, Continuous, Prismatic, Floating, Planar };

struct Joint {
  std::string name;
  JointType type = JointType::Fixed;
  std::string parent, child;                                // link names
  Eigen::Isometry3d X_PJ = Eigen::Isometry3d::Identity();  // joint (= child) frame in parent link frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();          // unit, in joint frame
  bool has_limits = false;                                  // revolute, prismatic
  double lower = 0, upper = 0;                              // rad or m
  double effort = 0, velocity = 0;                          // N m or N; rad/s or m/s (0: none given)
  double damping = 0, friction = 0;                         // N m s/rad (N s/m); N m (N)
  // A geared rotor's inertia reflected onto the joint, J_rotor N² (MuJoCo's armature),
  // kg m² (kg): it adds to the joint's diagonal of the mass matrix. 0 from a URDF (it
  // has no such field); a scenario's robot.armature sets it for joints without an
  // actuator model (an actuator carries its own rotor).
  double armature = 0;
};

// A physically invalid value of the file that the loader repaired (UrdfOptions::strict
// refuses it instead). docs/model.md states the rules.
struct Repair {
  std::string link;
  // "balanceinertia": the principal moments broke the triangle inequality; before and
  //   after are the three principal moments, ascending (kg m^2).
  // "massless_moving_link": a moving joint's child and every link below it have no
  //   mass; before and after are the link's mass (kg), kept at 0 (the plant welds the
  //   joint, which moves nothing).
  std::string kind;
  std::vector<double> before, after;
  std::string what;  // what was wrong, one line
};

struct RobotDescription {
  std::string name;
  std::string source;                 // the URDF file read ("" for a string)
  std::vector<Link> links;            // links[0] is the root
  std::vector<Joint> joints;          // parent before child (topological order)
  std::vector<std::string> meshes_missing;  // URIs that could not be found or read
  std::size_t meshes_loaded = 0;
  std::vector<std::string> warnings;  // one line each: unknown tags, missing meshes, repairs...
  std::vector<Repair> repairs;        // each has its line in warnings too

  // Index of a link/joint by name, or -1.
  int link_index(const std::string& name) const;
  int joint_index(const std::string& name) const;
  // The joint whose child is the link, or -1 for the root.
  int parent_joint_of_link(int link) const;
  double total_mass_kg() const;       // sum of link masses
};

struct UrdfOptions {
  // Folders searched for package://NAME/rest: <dir>/NAME/rest, then <dir>/rest.
  // The URDF's own folder and its parents are always tried after these.
  std::vector<std::string> package_paths;
  // A mesh that cannot be found/read is an error, and so is what would be repaired
  // (an inertia breaking the triangle inequality, a moving joint that moves no mass).
  bool strict = false;
  bool load_meshes = true;            // false: record URIs only (fast)
};

// Reads a URDF file. Throws dmbd::model::ModelError with a one-line message naming
// the file, the line and the element ("draco.urdf:42: link 'thigh': inertia is not
// positive definite") for malformed XML, a missing file, a loop or a second parent
// in the tree, a NaN/inf number, a negative mass or a non-positive-definite inertia; with
// options.strict also for what is otherwise repaired with a warning (see Repair).
RobotDescription load_urdf(const std::string& path, const UrdfOptions& options = {});
// Same from text; `base_dir` resolves relative mesh paths, `label` names it in errors.
RobotDescription parse_urdf(const std::string& xml, const std::string& base_dir,
                            const std::string& label, const UrdfOptions& options = {});

// Forward kinematics, the project's one routine for a description: X_WL for every link,
// the root link at X_W_root and joint j at q[j] (robot.joints order): rotation about the
// joint axis for revolute and continuous joints (rad), translation along it for
// prismatic ones (m); fixed, floating and planar joints contribute X_PJ only (move a
// floating base through X_W_root). Throws ModelError if q.size() != robot.joints.size().
std::vector<Eigen::Isometry3d> link_frames(const RobotDescription& robot, const std::vector<double>& q,
                                           const Eigen::Isometry3d& X_W_root = Eigen::Isometry3d::Identity());
// Default-pose forward kinematics (every joint at 0, root at identity).
std::vector<Eigen::Isometry3d> default_pose_link_frames(const RobotDescription& robot);
// The centre of mass in world of the links at X_WL (zero if the robot has no mass).
Eigen::Vector3d center_of_mass(const RobotDescription& robot, const std::vector<Eigen::Isometry3d>& X_WL);

// Inertia about joint `joint`'s axis (kg m^2) of the links it moves (its child and
// every link below), in the description's zero pose: rotation about the axis does not
// change it; joints below are taken at zero (welded joints where they were welded).
double subtree_axis_inertia(const RobotDescription& robot, int joint);

// Mass of each link plus every link below it (kg), indexed as robot.links.
std::vector<double> subtree_masses(const RobotDescription& robot);

// The same robot with a rigid mass bolted to `link`: mass_kg at com_L (link frame) with
// principal moments inertia_kgm2 about axes parallel to the link frame's; the link's
// mass, centre of mass and inertia become those of the union. Throws ModelError for an
// unknown link or a non-positive mass.
void add_payload(RobotDescription& robot, const std::string& link, double mass_kg, const Eigen::Vector3d& com_L,
                 const Eigen::Vector3d& inertia_kgm2);

// The same robot with some 1-dof joints welded at given positions (rad or m): each
// becomes a Fixed joint whose origin includes the rotation (translation) by q about
// (along) its axis, so the welded links sit where the moving joint would put them.
// A test bench clamps the joints it does not study this way; the plant then has no
// coordinates (and no constraint equations) for them. Throws ModelError naming a joint
// that does not exist or has no single degree of freedom, or a position outside the
// joint's limits.
RobotDescription freeze_joints(const RobotDescription& robot,
                               const std::vector<std::pair<std::string, double>>& positions);

// Whether a collision shape touches the ground in the plant (docs/model.md, "Contact"):
// a sphere and a box always, a cylinder of positive radius, a mesh whose file loaded
// (its convex hull's points). The plant numbers its contacts over these shapes (links in
// order, each link's in URDF order): the log's contact.K.
bool can_collide(const Geometry& geometry);

// The type as URDF writes it: "fixed", "revolute", "continuous", "prismatic", "floating", "planar".
const char* joint_type_name(JointType type);

// Summary used by `dmbd model info`.
struct ModelSummary {
  std::string name;
  std::size_t links = 0;
  std::size_t dof = 0;                // actuated joints: revolute + continuous + prismatic
  std::size_t fixed = 0, revolute = 0, continuous = 0, prismatic = 0, floating = 0, planar = 0;
  double total_mass_kg = 0;
  double height_m = 0;                // vertical extent of the visual geometry, default pose
  std::size_t meshes_loaded = 0;
  std::vector<std::string> meshes_missing;
};
ModelSummary summarize(const RobotDescription& robot);

}  // namespace dmbd::model
