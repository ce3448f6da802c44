// Finds the element(s) of a mesh that contain a physical point and the point's reference
// coordinates there, by a bucket grid of element bounding boxes and Newton inversion of the
// isoparametric map. Used to sample fields along lines (profiles, cross-sections) and to
// compare solutions on different meshes. Built from the node positions at construction: rebuild
// after the mesh moves.
#pragma once

#include <optional>
#include <vector>

#include "core/Mesh.hpp"

namespace keller {

struct MeshPoint {
  int element = -1;
  double s = 0, t = 0;  // reference coordinates in [-1, 1]
};

class PointLocator {
 public:
  // Elements of one group (or all, group = -1).
  explicit PointLocator(const Mesh& mesh, int group = -1);
  // Every element containing (x, y) within a relative tolerance (two or more on shared edges).
  std::vector<MeshPoint> locate_all(double x, double y, double tol = 1e-9) const;
  // One element containing (x, y), or nothing if the point is outside the mesh.
  std::optional<MeshPoint> locate(double x, double y, double tol = 1e-9) const;

 private:
  bool invert(int e, double x, double y, MeshPoint& out, double tol) const;
  const Mesh* mesh_;
  double x0_ = 0, y0_ = 0, dx_ = 1, dy_ = 1;
  int nbx_ = 1, nby_ = 1;
  std::vector<std::vector<int>> buckets_;
};

}  // namespace keller
