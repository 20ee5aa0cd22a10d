#pragma once
// Internal to model/: finding the file behind a URDF mesh URI and reading it with
// assimp into a TriangleMesh. Used by urdf_loader.cpp; no assimp type leaks out.

#include "dmbd/model/robot_description.hpp"

#include <Eigen/Core>

#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace dmbd::model::detail {

// The file a URDF mesh URI names, or nullopt when no candidate exists. Every
// candidate path that was tried is appended to `tried` (for the warning).
//   package://NAME/REST  <dir>/NAME/REST then <dir>/REST for each dir of
//                        `package_paths`, then the same two for `base_dir` and each
//                        of its parents up to the file-system root
//   file:///abs/path     /abs/path;  file://rel/path (non-standard) as rel/path
//   abs/or/rel/path      as is, relative paths against `base_dir`
// Any other scheme (http://, model://...) is not supported: nullopt, and `tried`
// gets one entry naming the scheme.
std::optional<std::string> resolve_mesh_uri(const std::string& uri, const std::string& base_dir,
                                            const std::vector<std::string>& package_paths,
                                            std::vector<std::string>* tried = nullptr);

// Reads a mesh file (STL binary/ASCII, OBJ, COLLADA and whatever else assimp reads)
// into one triangle mesh in the geometry frame:
//  - assimp post-processing: Triangulate | JoinIdenticalVertices | GenSmoothNormals
//    (normals from the file are kept; smooth ones are generated where missing);
//    point and line primitives are dropped.
//  - every node's transform is applied (the product along the node path, root
//    included), so a multi-part file is assembled as its author placed the parts.
//  - COLLADA: <unit meter="..."> is applied (assimp folds it into the root node),
//    <up_axis> is ignored (AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION): vertices
//    are taken as link-frame coordinates, as RViz and Gazebo display ROS meshes.
//    STL and OBJ carry no unit: their numbers are taken as metres.
//  - then `scale` (the URDF <mesh scale>) per axis; normals are transformed by the
//    inverse transpose and renormalised, and triangles are re-wound when the total
//    transform mirrors (negative determinant) so they keep facing outwards.
// Returns null and sets `error` (one line, no file name) when the file cannot be
// read or holds no triangle.
std::shared_ptr<TriangleMesh> load_mesh_file(const std::string& path, const Eigen::Vector3d& scale,
                                             std::string* error);

}  // namespace dmbd::model::detail
