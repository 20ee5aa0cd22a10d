#pragma once
// Internal to model/: a collision mesh's contact points, the vertices of its convex hull
// (Debian's qhull, reentrant libqhull_r: a hull is a library's job), at most a given
// number of them, chosen by farthest-point sampling when the hull has more. Eigen only.
#include "dmbd/model/robot_description.hpp"

#include <Eigen/Core>

#include <cstddef>
#include <vector>

namespace dmbd::model::detail {

// The vertices of the convex hull of `points` (any order of input; output in qhull's
// vertex order, as doubles). Fewer than 4 points, or all on a plane or a line: qhull
// cannot build a 3-d hull, and the points are joggled (qhull's QJ: a random shift of
// about 1e-11 of their extent) so that it can; every extreme point is then a vertex.
// Empty input gives an empty result.
std::vector<Eigen::Vector3d> convex_hull_vertices(const std::vector<Eigen::Vector3f>& points);

// At most this many contact points per collision mesh.
constexpr std::size_t kMaxHullPoints = 64;

// `count` of the points by farthest-point sampling: the first is the point farthest from
// their centroid, each next one the point farthest from those chosen (ties: the first in
// order). All of them (unchanged) when there are no more than `count`.
std::vector<Eigen::Vector3d> farthest_points(const std::vector<Eigen::Vector3d>& points, std::size_t count);

// The contact points of a collision mesh: its convex hull's vertices, at most `max`
// (farthest-point sampled). `hull_size` (optional) gets the hull's vertex count.
std::vector<Eigen::Vector3d> mesh_contact_points(const TriangleMesh& mesh, std::size_t max, std::size_t* hull_size = nullptr);

}  // namespace dmbd::model::detail
