#include "core/ImportedMesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>
#include <unordered_set>

#include "core/MeshFileError.hpp"
#include "core/ReferenceElement.hpp"

namespace keller {

namespace {

using Point = Mesh::Point;

// Keller's node a = i + 3 j of the element mirrored about s = t (s and t swapped): the same element
// traversed the other way round, det J of the opposite sign.
constexpr std::array<int, 9> kSwapST = {0, 3, 6, 1, 4, 7, 2, 5, 8};

// A node n lying within this fraction of an edge's length of the edge's curve, without being one of
// its nodes, makes the mesh non-conforming. Generous on purpose: two surfaces meshed apart along
// one curved curve put their nodes on the curve, not on each other's quadratic edges.
constexpr double kOnEdgeTolerance = 1e-3;

std::string at(const Point& p) { return fmt::format("({:.9g}, {:.9g})", p[0], p[1]); }

std::string geo_fix_remesh() {
  return "check the surface's curve loop and its mesh settings (a transfinite surface's corners, "
         "`Mesh.HighOrderOptimize = 2;` for curved order-2 elements) in the .geo and mesh it again";
}

// +1: det J > 0 at every Gauss point; -1: det J < 0 at every Gauss point; 0: neither.
int orientation(const ImportedMesh& raw, const std::array<int, 9>& nodes) {
  const ref::Tables& tb = ref::tables();
  double xy[9][2];
  for (int a = 0; a < 9; ++a) {
    xy[a][0] = raw.nodes[nodes[a]][0];
    xy[a][1] = raw.nodes[nodes[a]][1];
  }
  int positive = 0, negative = 0;
  for (int q = 0; q < ref::kQp; ++q) {
    double Jinv[2][2], det;
    detail::inverse_jacobian(tb.dN2[q], xy, Jinv, det);
    if (det > 0.0) ++positive;
    if (det < 0.0) ++negative;
  }
  return positive == ref::kQp ? 1 : negative == ref::kQp ? -1 : 0;
}

// The elements counter-clockwise: a surface whose elements are all clockwise is mirrored.
std::vector<std::array<int, 9>> oriented_elements(const ImportedMesh& raw) {
  std::vector<int> sign(raw.quads.size());
  std::map<int, std::pair<int, int>> counts;  // surface -> (counter-clockwise, clockwise) elements
  for (std::size_t e = 0; e < raw.quads.size(); ++e) {
    const ImportedQuad& quad = raw.quads[e];
    sign[e] = orientation(raw, quad.nodes);
    if (sign[e] == 0) {
      throw MeshFileError(
          fmt::format("{}: element {} (Gmsh surface {}, corners {} {} {} {}) is degenerate or folded: det J is not of "
                      "one sign over it; {}",
                      raw.file, quad.tag, quad.surface, at(raw.nodes[quad.nodes[0]]), at(raw.nodes[quad.nodes[2]]),
                      at(raw.nodes[quad.nodes[8]]), at(raw.nodes[quad.nodes[6]]), geo_fix_remesh()));
    }
    auto& [ccw, cw] = counts[quad.surface];
    (sign[e] > 0 ? ccw : cw) += 1;
  }
  std::vector<std::array<int, 9>> elements(raw.quads.size());
  for (std::size_t e = 0; e < raw.quads.size(); ++e) {
    const ImportedQuad& quad = raw.quads[e];
    const auto& [ccw, cw] = counts[quad.surface];
    if (sign[e] < 0 && ccw > 0) {
      throw MeshFileError(fmt::format(
          "{}: element {} (Gmsh surface {}, corners {} {} {} {}) is inverted: it is clockwise while {} other "
          "elements of surface {} are counter-clockwise; {}",
          raw.file, quad.tag, quad.surface, at(raw.nodes[quad.nodes[0]]), at(raw.nodes[quad.nodes[2]]),
          at(raw.nodes[quad.nodes[8]]), at(raw.nodes[quad.nodes[6]]), ccw, quad.surface, geo_fix_remesh()));
    }
    for (int a = 0; a < 9; ++a) elements[e][a] = sign[e] > 0 ? quad.nodes[a] : quad.nodes[kSwapST[a]];
  }
  return elements;
}

struct EdgeUse {
  int element;
  int edge;
};

class EdgeTable {
 public:
  explicit EdgeTable(std::size_t num_nodes) : num_nodes_(num_nodes) {}
  std::uint64_t key(int a, int b) const {
    return static_cast<std::uint64_t>(std::min(a, b)) * num_nodes_ + static_cast<std::uint64_t>(std::max(a, b));
  }
  void add(int a, int b, EdgeUse use) { uses_[key(a, b)].push_back(use); }
  const std::vector<EdgeUse>* find(int a, int b) const {
    auto it = uses_.find(key(a, b));
    return it == uses_.end() ? nullptr : &it->second;
  }
  const std::unordered_map<std::uint64_t, std::vector<EdgeUse>>& uses() const { return uses_; }

 private:
  std::uint64_t num_nodes_;
  std::unordered_map<std::uint64_t, std::vector<EdgeUse>> uses_;
};

std::array<int, 3> edge_of(const std::vector<std::array<int, 9>>& elements, EdgeUse use) {
  const auto& local = ref::edge_nodes[use.edge];
  return {elements[use.element][local[0]], elements[use.element][local[1]], elements[use.element][local[2]]};
}

// The distance from x to the quadratic curve through p, m, q (at parameters -1, 0, 1).
double distance_to_edge(const Point& p, const Point& m, const Point& q, const Point& x) {
  auto position = [&](double s, int i) {
    return p[i] * 0.5 * s * (s - 1.0) + m[i] * (1.0 - s * s) + q[i] * 0.5 * s * (s + 1.0);
  };
  auto tangent = [&](double s, int i) { return p[i] * (s - 0.5) - m[i] * 2.0 * s + q[i] * (s + 0.5); };
  auto distance = [&](double s) { return std::hypot(position(s, 0) - x[0], position(s, 1) - x[1]); };
  double best = -1.0;
  for (int k = 0; k <= 8; ++k) {
    const double s = -1.0 + 0.25 * k;
    if (best < -0.5 || distance(s) < distance(best)) best = s;
  }
  for (int it = 0; it < 8; ++it) {  // Newton on (x(s) - x) . x'(s) = 0
    double g = 0.0, dg = 0.0;
    for (int i = 0; i < 2; ++i) {
      const double r = position(best, i) - x[i], t = tangent(best, i);
      g += r * t;
      dg += t * t + r * (p[i] - 2.0 * m[i] + q[i]);
    }
    if (!(dg > 0.0)) break;
    best = std::clamp(best - g / dg, -1.0, 1.0);
  }
  return distance(best);
}

// Refuses edges of one element that touch other such edges anywhere but at their shared nodes:
// a hanging node, or two surfaces meshed without sharing the curve between them.
void check_no_inner_boundary(const ImportedMesh& raw, const std::vector<std::array<int, 9>>& elements,
                             const std::vector<EdgeUse>& single) {
  if (single.empty()) return;
  double cell = 0.0;
  for (const EdgeUse& use : single) {
    const auto nodes = edge_of(elements, use);
    for (int i = 0; i < 2; ++i) cell = std::max(cell, std::abs(raw.nodes[nodes[0]][i] - raw.nodes[nodes[2]][i]));
  }
  cell = std::max(cell, 1e-300);
  auto cell_of = [&](double v) { return static_cast<std::int64_t>(std::floor(v / cell)); };
  std::map<std::pair<std::int64_t, std::int64_t>, std::vector<int>> grid;
  std::unordered_set<int> boundary_nodes;
  for (const EdgeUse& use : single)
    for (int n : edge_of(elements, use)) boundary_nodes.insert(n);
  for (int n : boundary_nodes) grid[{cell_of(raw.nodes[n][0]), cell_of(raw.nodes[n][1])}].push_back(n);

  for (const EdgeUse& use : single) {
    const auto nodes = edge_of(elements, use);
    const Point& p = raw.nodes[nodes[0]];
    const Point& m = raw.nodes[nodes[1]];
    const Point& q = raw.nodes[nodes[2]];
    const double length = std::hypot(m[0] - p[0], m[1] - p[1]) + std::hypot(q[0] - m[0], q[1] - m[1]);
    const double tol = kOnEdgeTolerance * length;
    double lo[2], hi[2];
    for (int i = 0; i < 2; ++i) {  // the curve lies in the hull of p, q and its Bezier point 2m - (p+q)/2
      const double c = 2.0 * m[i] - 0.5 * (p[i] + q[i]);
      lo[i] = std::min({p[i], q[i], c}) - tol;
      hi[i] = std::max({p[i], q[i], c}) + tol;
    }
    for (std::int64_t cx = cell_of(lo[0]); cx <= cell_of(hi[0]); ++cx) {
      for (std::int64_t cy = cell_of(lo[1]); cy <= cell_of(hi[1]); ++cy) {
        auto it = grid.find({cx, cy});
        if (it == grid.end()) continue;
        for (int n : it->second) {
          if (n == nodes[0] || n == nodes[1] || n == nodes[2]) continue;
          if (distance_to_edge(p, m, q, raw.nodes[n]) > tol) continue;
          throw MeshFileError(fmt::format(
              "{}: the mesh is not conforming: node {} at {} lies on the edge of element {} from {} to {} without "
              "being one of its nodes (a hanging node, or two surfaces meshed without sharing the curve "
              "between them); in the .geo, let neighbouring surfaces share their curves (the same Curve in "
              "both Curve Loops, `Coherence;`, or BooleanFragments with OpenCASCADE) and mesh it again",
              raw.file, raw.node_tags[n], at(raw.nodes[n]), raw.quads[use.element].tag, at(p), at(q)));
        }
      }
    }
  }
}

}  // namespace

Mesh build_imported_mesh(const ImportedMesh& raw) {
  std::vector<std::array<int, 9>> elements = oriented_elements(raw);

  EdgeTable table(raw.nodes.size());
  for (int e = 0; e < static_cast<int>(elements.size()); ++e)
    for (int k = 0; k < 4; ++k) {
      const auto nodes = edge_of(elements, {e, k});
      table.add(nodes[0], nodes[2], {e, k});
    }
  std::vector<EdgeUse> single;
  for (const auto& [key, uses] : table.uses()) {
    const auto first = edge_of(elements, uses[0]);
    if (uses.size() > 2) {
      throw MeshFileError(
          fmt::format("{}: the edge from {} to {} belongs to {} elements ({}, {}, {}...); an edge may join at most two "
                      "elements: check the .geo for overlapping or duplicated surfaces",
                      raw.file, at(raw.nodes[first[0]]), at(raw.nodes[first[2]]), uses.size(),
                      raw.quads[uses[0].element].tag, raw.quads[uses[1].element].tag, raw.quads[uses[2].element].tag));
    }
    if (uses.size() == 2 && edge_of(elements, uses[1])[1] != first[1]) {
      throw MeshFileError(fmt::format(
          "{}: the mesh is not conforming: elements {} and {} share the ends {} and {} of an edge but not its "
          "middle node; in the .geo, let neighbouring surfaces share their curves and mesh it again",
          raw.file, raw.quads[uses[0].element].tag, raw.quads[uses[1].element].tag, at(raw.nodes[first[0]]),
          at(raw.nodes[first[2]])));
    }
    if (uses.size() == 1) single.push_back(uses[0]);
  }
  std::sort(single.begin(), single.end(), [](const EdgeUse& a, const EdgeUse& b) {
    return std::pair(a.element, a.edge) < std::pair(b.element, b.edge);
  });
  check_no_inner_boundary(raw, elements, single);

  std::map<std::string, std::vector<BoundaryEdge>> boundaries;
  std::unordered_set<std::uint64_t> named;
  for (const auto& [name, lines] : raw.boundaries) {
    std::vector<BoundaryEdge>& edges = boundaries[name];
    for (const ImportedLine& line : lines) {
      const std::vector<EdgeUse>* uses = table.find(line.nodes[0], line.nodes[1]);
      if (!uses || edge_of(elements, (*uses)[0])[1] != line.nodes[2]) {
        throw MeshFileError(fmt::format(
            "{}: line element {} of physical curve '{}' (from {} to {}) is not an edge of the 2D elements of the "
            "physical surfaces; in the .geo, put in physical curves only curves that bound a physical surface "
            "and mesh the curves and surfaces together",
            raw.file, line.tag, name, at(raw.nodes[line.nodes[0]]), at(raw.nodes[line.nodes[1]])));
      }
      EdgeUse use = (*uses)[0];
      for (const EdgeUse& u : *uses)
        if (elements[u.element][ccw_edge_line[u.edge][0]] == line.nodes[0]) use = u;
      edges.push_back({use.element, use.edge});
      named.insert(table.key(line.nodes[0], line.nodes[1]));
    }
  }
  for (const EdgeUse& use : single) {
    const auto nodes = edge_of(elements, use);
    if (named.count(table.key(nodes[0], nodes[2]))) continue;
    throw MeshFileError(fmt::format(
        "{}: the edge of element {} from {} to {} is on the boundary of the domain but in no 1D physical group; "
        "every boundary needs a name to be given a condition: in the .geo, add its curve to a "
        "`Physical Curve(\"name\") = {{...}};`",
        raw.file, raw.quads[use.element].tag, at(raw.nodes[nodes[0]]), at(raw.nodes[nodes[2]])));
  }

  std::vector<int> groups(raw.quads.size());
  for (std::size_t e = 0; e < raw.quads.size(); ++e) groups[e] = raw.quads[e].group;
  return Mesh(raw.nodes, std::move(elements), std::move(groups), raw.group_names, std::move(boundaries), {});
}

}  // namespace keller
