#include "core/Mesh.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace keller {

Mesh::Mesh(std::vector<Point> nodes, std::vector<std::array<int, 9>> elements, std::vector<int> element_group,
           std::vector<std::string> group_names, std::map<std::string, std::vector<BoundaryEdge>> boundaries,
           std::vector<MeshBlock> blocks)
    : nodes_(std::move(nodes)),
      elements_(std::move(elements)),
      element_group_(std::move(element_group)),
      group_names_(std::move(group_names)),
      boundaries_(std::move(boundaries)),
      blocks_(std::move(blocks)),
      is_vertex_(nodes_.size(), 0) {
  if (element_group_.size() != elements_.size())
    throw std::invalid_argument("Mesh: one group index per element required");
  for (const auto& el : elements_) {
    for (int v : ref::q1_node) {
      if (el[v] < 0 || el[v] >= num_nodes()) throw std::invalid_argument("Mesh: node index out of range");
      is_vertex_[el[v]] = 1;
    }
  }
}

void Mesh::element_nodes(int e, double (&xy)[9][2]) const {
  const auto& el = elements_[e];
  for (int a = 0; a < 9; ++a) {
    xy[a][0] = nodes_[el[a]][0];
    xy[a][1] = nodes_[el[a]][1];
  }
}

int Mesh::group_index(const std::string& name) const {
  auto it = std::find(group_names_.begin(), group_names_.end(), name);
  if (it == group_names_.end()) throw std::invalid_argument("Mesh: no element group named '" + name + "'");
  return static_cast<int>(it - group_names_.begin());
}

bool Mesh::has_group(const std::string& name) const {
  return std::find(group_names_.begin(), group_names_.end(), name) != group_names_.end();
}

std::vector<int> Mesh::elements_in_group(int group) const {
  std::vector<int> out;
  for (int e = 0; e < num_elements(); ++e)
    if (element_group_[e] == group) out.push_back(e);
  return out;
}

const std::vector<BoundaryEdge>& Mesh::boundary(const std::string& name) const {
  auto it = boundaries_.find(name);
  if (it == boundaries_.end()) throw std::invalid_argument("Mesh: no boundary named '" + name + "'");
  return it->second;
}

std::vector<std::string> Mesh::boundary_names() const {
  std::vector<std::string> out;
  for (const auto& [name, edges] : boundaries_) out.push_back(name);
  return out;
}

std::vector<int> Mesh::boundary_nodes(const std::string& name) const {
  std::vector<int> out;
  for (const BoundaryEdge& be : boundary(name))
    for (int a : ref::edge_nodes[be.edge]) out.push_back(elements_[be.element][a]);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

const MeshBlock& Mesh::block(const std::string& name) const {
  for (const auto& b : blocks_)
    if (b.name == name) return b;
  throw std::invalid_argument("Mesh: no block named '" + name + "'");
}

std::pair<double, double> Mesh::jacobian_range() const {
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  const ref::Tables& tb = ref::tables();
  for (int e = 0; e < num_elements(); ++e) {
    double xy[9][2];
    element_nodes(e, xy);
    for (int q = 0; q < ref::kQp; ++q) {
      double Jinv[2][2], det;
      detail::inverse_jacobian(tb.dN2[q], xy, Jinv, det);
      lo = std::min(lo, det);
      hi = std::max(hi, det);
    }
  }
  return {lo, hi};
}

}  // namespace keller
