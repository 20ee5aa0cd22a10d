// A renderable scene from a robot description: one body per link, its visuals as
// meshes (URDF primitives tessellated by viz, mesh files as loaded).
#include "dmbd/report/robot_scene.hpp"

#include <stdexcept>
#include <string>

#include "dmbd/viz/primitives.hpp"

namespace dmbd::report {

using viz::Scene;
using viz::SceneBody;
using viz::SceneMesh;

Scene scene_from_robot(const model::RobotDescription& robot, const RobotSceneOptions& options) {
  using Kind = model::Geometry::Kind;
  Scene scene;
  scene.bodies.reserve(robot.links.size());
  for (const model::Link& link : robot.links) {
    SceneBody body;
    body.name = link.name;
    for (const model::Shape& shape : link.visuals) {
      const model::Geometry& g = shape.geometry;
      SceneMesh m;
      try {
        switch (g.kind) {
          case Kind::Box:
            m = viz::box_mesh(g.box_size_m);
            break;
          case Kind::Cylinder:
            m = viz::cylinder_mesh(g.radius_m, g.length_m, options.cylinder_segments);
            break;
          case Kind::Sphere:
            m = viz::sphere_mesh(g.radius_m, options.sphere_segments);
            break;
          case Kind::Mesh:
            if (!g.mesh) continue;
            m.vertices = g.mesh->vertices;
            if (g.mesh->normals.size() == g.mesh->vertices.size()) m.normals = g.mesh->normals;
            m.triangles = g.mesh->triangles;
            break;
        }
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(std::string(e.what()) + " (link '" + link.name + "', visual '" + shape.name + "')");
      }
      m = viz::transformed(std::move(m), shape.X_LG);
      m.rgba = shape.rgba.cast<float>();
      body.meshes.push_back(std::move(m));
    }
    scene.bodies.push_back(std::move(body));
  }
  return scene;
}

}  // namespace dmbd::report
