// An unstructured-by-storage, structured-by-construction mesh of 9-node quadrilaterals:
// node positions, element connectivity (ReferenceElement.hpp ordering), element groups
// ("fluid", "solid", ...), named boundaries as lists of element edges, and the logical block
// layout each element came from (used for column-wise diagnostics such as flow rates).
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include "core/ElementGeometry.hpp"

namespace keller {

struct BoundaryEdge {
  int element;
  int edge;  // 0 bottom, 1 right, 2 top, 3 left (reference element)
};

struct MeshBlock {
  std::string name;
  int group = 0;
  int nx = 0, ny = 0;          // elements along s and t
  std::vector<int> node_grid;  // (2 nx + 1) x (2 ny + 1) node ids, index i + (2 nx + 1) j
  std::vector<int> elements;   // element ids, index i + nx j
  int node(int i, int j) const { return node_grid[i + (2 * nx + 1) * j]; }
  int element(int i, int j) const { return elements[i + nx * j]; }
};

class Mesh {
 public:
  using Point = std::array<double, 2>;

  Mesh() = default;
  Mesh(std::vector<Point> nodes, std::vector<std::array<int, 9>> elements, std::vector<int> element_group,
       std::vector<std::string> group_names, std::map<std::string, std::vector<BoundaryEdge>> boundaries,
       std::vector<MeshBlock> blocks);

  int num_nodes() const { return static_cast<int>(nodes_.size()); }
  int num_elements() const { return static_cast<int>(elements_.size()); }
  const Point& node(int n) const { return nodes_[n]; }
  const std::vector<Point>& nodes() const { return nodes_; }
  void set_node(int n, const Point& p) { nodes_[n] = p; }
  const std::array<int, 9>& element(int e) const { return elements_[e]; }
  void element_nodes(int e, double (&xy)[9][2]) const;

  int element_group(int e) const { return element_group_[e]; }
  const std::vector<std::string>& group_names() const { return group_names_; }
  int group_index(const std::string& name) const;  // throws if unknown
  bool has_group(const std::string& name) const;
  std::vector<int> elements_in_group(int group) const;

  bool has_boundary(const std::string& name) const { return boundaries_.count(name) > 0; }
  const std::vector<BoundaryEdge>& boundary(const std::string& name) const;  // throws if unknown
  std::vector<std::string> boundary_names() const;
  // Sorted, unique node ids on a boundary (all three nodes of every edge).
  std::vector<int> boundary_nodes(const std::string& name) const;

  bool is_vertex(int n) const { return is_vertex_[n] != 0; }
  const std::vector<MeshBlock>& blocks() const { return blocks_; }
  const MeshBlock& block(const std::string& name) const;  // throws if unknown

  // Smallest and largest det J over all Gauss points (negative min = inverted element).
  std::pair<double, double> jacobian_range() const;

 private:
  std::vector<Point> nodes_;
  std::vector<std::array<int, 9>> elements_;
  std::vector<int> element_group_;
  std::vector<std::string> group_names_;
  std::map<std::string, std::vector<BoundaryEdge>> boundaries_;
  std::vector<MeshBlock> blocks_;
  std::vector<char> is_vertex_;
};

}  // namespace keller
