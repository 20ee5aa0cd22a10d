// A renderable scene from a robot description: one body per link, its visuals as
// meshes (URDF primitives tessellated by viz, mesh files as loaded), or its collision
// shapes where its visual meshes are missing.
#include "dmbd/report/robot_scene.hpp"

#include <algorithm>
#include <optional>
#include <stdexcept>
#include <string>

#include "dmbd/viz/primitives.hpp"

namespace dmbd::report {

using viz::Scene;
using viz::SceneBody;
using viz::SceneMesh;

namespace {

using Kind = model::Geometry::Kind;

bool mesh_missing(const model::Shape& s) { return s.geometry.kind == Kind::Mesh && !s.geometry.mesh; }

// A collision shape with a surface to draw: a loaded mesh, or a primitive whose sizes
// are all positive (the URDF allows zero sizes; such a shape has no surface).
bool drawable_collision(const model::Shape& s) {
  const model::Geometry& g = s.geometry;
  switch (g.kind) {
    case Kind::Box:
      return (g.box_size_m.array() > 0).all();
    case Kind::Cylinder:
      return g.radius_m > 0 && g.length_m > 0;
    case Kind::Sphere:
      return g.radius_m > 0;
    case Kind::Mesh:
      return g.mesh && !g.mesh->triangles.empty();
  }
  return false;
}

// The shape's triangles in its geometry frame, or nothing for a mesh that did not load.
// Throws viz's std::invalid_argument for a non-positive size.
std::optional<SceneMesh> geometry_mesh(const model::Geometry& g, const RobotSceneOptions& options) {
  switch (g.kind) {
    case Kind::Box:
      return viz::box_mesh(g.box_size_m);
    case Kind::Cylinder:
      return viz::cylinder_mesh(g.radius_m, g.length_m, options.cylinder_segments);
    case Kind::Sphere:
      return viz::sphere_mesh(g.radius_m, options.sphere_segments);
    case Kind::Mesh:
      break;
  }
  if (!g.mesh) return std::nullopt;
  SceneMesh m;
  m.vertices = g.mesh->vertices;
  if (g.mesh->normals.size() == g.mesh->vertices.size()) m.normals = g.mesh->normals;
  m.triangles = g.mesh->triangles;
  return m;
}

// The shape in the link frame, coloured; the error names the link and the shape.
std::optional<SceneMesh> shape_mesh(const model::Link& link, const model::Shape& shape, const Eigen::Vector4f& rgba,
                                    const char* role, const RobotSceneOptions& options) {
  std::optional<SceneMesh> m;
  try {
    m = geometry_mesh(shape.geometry, options);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string(e.what()) + " (link '" + link.name + "', " + role + " '" + shape.name + "')");
  }
  if (!m) return m;
  m = viz::transformed(std::move(*m), shape.X_LG);
  m->rgba = rgba;
  return m;
}

}  // namespace

bool drawn_from_collisions(const model::Link& link) {
  const bool visual_missing = link.visuals.empty() || std::any_of(link.visuals.begin(), link.visuals.end(), mesh_missing);
  return visual_missing && std::any_of(link.collisions.begin(), link.collisions.end(), drawable_collision);
}

std::vector<std::string> links_drawn_from_collisions(const model::RobotDescription& robot) {
  std::vector<std::string> names;
  for (const model::Link& link : robot.links)
    if (drawn_from_collisions(link)) names.push_back(link.name);
  return names;
}

Scene scene_from_robot(const model::RobotDescription& robot, const RobotSceneOptions& options) {
  Scene scene;
  scene.bodies.reserve(robot.links.size());
  for (const model::Link& link : robot.links) {
    SceneBody body;
    body.name = link.name;
    if (drawn_from_collisions(link)) {
      for (const model::Shape& shape : link.collisions)
        if (drawable_collision(shape))
          if (auto m = shape_mesh(link, shape, options.collision_rgba, "collision", options)) body.meshes.push_back(std::move(*m));
    } else {
      for (const model::Shape& shape : link.visuals)
        if (auto m = shape_mesh(link, shape, shape.rgba.cast<float>(), "visual", options)) body.meshes.push_back(std::move(*m));
    }
    scene.bodies.push_back(std::move(body));
  }
  return scene;
}

}  // namespace dmbd::report
