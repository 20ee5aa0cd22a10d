// Mesh URIs to files, files to triangles (assimp). See mesh_loader.hpp for the rules.
#include "mesh_loader.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Dense>

#include <array>
#include <cmath>
#include <filesystem>
#include <system_error>
#include <utility>

namespace dmbd::model::detail {

namespace fs = std::filesystem;

namespace {

bool is_file(const fs::path& p) {
  std::error_code ec;
  return fs::is_regular_file(p, ec);
}

// Tries `p`; records it.
std::optional<std::string> try_path(const fs::path& p, std::vector<std::string>* tried) {
  const std::string s = p.lexically_normal().string();
  if (tried) tried->push_back(s);
  if (is_file(p)) return s;
  return std::nullopt;
}

fs::path absolute_dir(const std::string& dir) {
  std::error_code ec;
  fs::path p = fs::absolute(dir.empty() ? fs::path(".") : fs::path(dir), ec);
  if (ec) p = dir.empty() ? fs::path(".") : fs::path(dir);
  return p.lexically_normal();
}

Eigen::Matrix4d to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4d e;
  for (unsigned r = 0; r < 4; ++r)
    for (unsigned c = 0; c < 4; ++c) e(r, c) = static_cast<double>(m[r][c]);
  return e;
}

// Appends every triangle under `node` (transform `X_parent` above it) to `out`.
void collect(const aiScene* scene, const aiNode* node, const Eigen::Matrix4d& X_parent, const Eigen::Vector3d& scale,
             TriangleMesh& out, bool& normals_ok) {
  const Eigen::Matrix4d X = X_parent * to_eigen(node->mTransformation);
  Eigen::Matrix4d S = Eigen::Matrix4d::Identity();
  S.topLeftCorner<3, 3>() = scale.asDiagonal();
  const Eigen::Matrix4d T = S * X;  // file coordinates -> geometry frame (m)
  const Eigen::Matrix3d A = T.topLeftCorner<3, 3>();
  const Eigen::Vector3d b = T.topRightCorner<3, 1>();
  const double det = A.determinant();
  // Normals: inverse transpose (a singular A, a zero scale, leaves normals undefined).
  const bool can_normal = std::abs(det) > 0;
  const Eigen::Matrix3d N = can_normal ? Eigen::Matrix3d(A.inverse().transpose()) : Eigen::Matrix3d::Zero();
  for (unsigned k = 0; k < node->mNumMeshes; ++k) {
    const aiMesh* m = scene->mMeshes[node->mMeshes[k]];
    const int base = static_cast<int>(out.vertices.size());
    const bool has_normals = m->HasNormals() && can_normal;
    if (!has_normals) normals_ok = false;
    for (unsigned v = 0; v < m->mNumVertices; ++v) {
      const aiVector3D& p = m->mVertices[v];
      const Eigen::Vector3d q = A * Eigen::Vector3d(p.x, p.y, p.z) + b;
      out.vertices.push_back(q.cast<float>());
      if (has_normals) {
        const aiVector3D& n = m->mNormals[v];
        Eigen::Vector3d nn = N * Eigen::Vector3d(n.x, n.y, n.z);
        const double len = nn.norm();
        // GenSmoothNormals leaves NaN on vertices of degenerate faces: store zero.
        nn = (len > 0 && std::isfinite(len)) ? Eigen::Vector3d(nn / len) : Eigen::Vector3d::Zero();
        out.normals.push_back(nn.cast<float>());
      }
    }
    for (unsigned f = 0; f < m->mNumFaces; ++f) {
      const aiFace& face = m->mFaces[f];
      if (face.mNumIndices != 3) continue;  // points and lines
      std::array<int, 3> t{base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
                           base + static_cast<int>(face.mIndices[2])};
      if (det < 0) std::swap(t[1], t[2]);  // a mirror would turn the faces inside out
      out.triangles.push_back(t);
    }
  }
  for (unsigned c = 0; c < node->mNumChildren; ++c) collect(scene, node->mChildren[c], X, scale, out, normals_ok);
}

}  // namespace

std::optional<std::string> resolve_mesh_uri(const std::string& uri, const std::string& base_dir,
                                            const std::vector<std::string>& package_paths,
                                            std::vector<std::string>* tried) {
  static const std::string kPackage = "package://", kFile = "file://";
  if (uri.compare(0, kPackage.size(), kPackage) == 0) {
    const std::string rest_all = uri.substr(kPackage.size());
    const auto slash = rest_all.find('/');
    const std::string name = slash == std::string::npos ? rest_all : rest_all.substr(0, slash);
    const std::string rest = slash == std::string::npos ? std::string() : rest_all.substr(slash + 1);
    if (name.empty() || rest.empty()) {
      if (tried) tried->push_back("(expected package://NAME/PATH)");
      return std::nullopt;
    }
    auto both = [&](const fs::path& dir) -> std::optional<std::string> {
      if (auto p = try_path(dir / name / rest, tried)) return p;
      return try_path(dir / rest, tried);
    };
    for (const std::string& d : package_paths)
      if (auto p = both(d)) return p;
    fs::path dir = absolute_dir(base_dir);
    while (true) {
      if (auto p = both(dir)) return p;
      if (!dir.has_parent_path() || dir.parent_path() == dir) break;
      dir = dir.parent_path();
    }
    return std::nullopt;
  }
  std::string path = uri;
  if (uri.compare(0, kFile.size(), kFile) == 0) {
    path = uri.substr(kFile.size());
  } else if (const auto colon = uri.find("://"); colon != std::string::npos) {
    if (tried) tried->push_back("(unsupported URI scheme '" + uri.substr(0, colon) + "://')");
    return std::nullopt;
  }
  if (path.empty()) return std::nullopt;
  const fs::path p(path);
  if (p.is_absolute()) return try_path(p, tried);
  return try_path(absolute_dir(base_dir) / p, tried);
}

std::shared_ptr<TriangleMesh> load_mesh_file(const std::string& path, const Eigen::Vector3d& scale,
                                             std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return std::shared_ptr<TriangleMesh>();
  };
  if (!scale.allFinite()) return fail("the scale is not finite");
  Assimp::Importer importer;
  importer.SetPropertyBool(AI_CONFIG_IMPORT_COLLADA_IGNORE_UP_DIRECTION, true);
  const aiScene* scene =
      importer.ReadFile(path, aiProcess_Triangulate | aiProcess_JoinIdenticalVertices | aiProcess_GenSmoothNormals);
  if (!scene) {
    std::string why = importer.GetErrorString();
    for (char& c : why)
      if (c == '\n' || c == '\r') c = ' ';
    return fail(why.empty() ? "assimp could not read it" : "assimp: " + why);
  }
  if ((scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) || !scene->mRootNode) return fail("assimp: the scene is incomplete");
  auto mesh = std::make_shared<TriangleMesh>();
  mesh->path = path;
  bool normals_ok = true;
  collect(scene, scene->mRootNode, Eigen::Matrix4d::Identity(), scale, *mesh, normals_ok);
  if (!normals_ok) mesh->normals.clear();  // all or nothing: one normal per vertex
  if (mesh->triangles.empty()) return fail("the file holds no triangle");
  for (const auto& v : mesh->vertices)
    if (!v.allFinite()) return fail("a vertex is not finite");
  return mesh;
}

}  // namespace dmbd::model::detail
