#include "problems/components/FlowBoundaries.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>
#include <utility>

#include "core/ReferenceElement.hpp"

namespace keller {

namespace {

// Nodes within this fraction of a boundary's length of its line count as on it (rounding in
// mesh files and mapped blocks is far smaller; a curved boundary far larger).
constexpr double kStraight = 1e-8;

std::vector<std::pair<std::string, std::string>> named_conditions(const FlowBoundaries& b) {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& c : b.inflows) out.emplace_back(c.boundary, "inflow");
  for (const auto& c : b.outflows) out.emplace_back(c.boundary, "outflow");
  for (const auto& w : b.walls) out.emplace_back(w, "wall");
  for (const auto& w : b.moving_walls) out.emplace_back(w, "moving wall");
  for (const auto& s : b.symmetry) out.emplace_back(s, "symmetry");
  for (const auto& d : b.driven_walls) out.emplace_back(d.boundary, "driven wall");
  for (const auto& t : b.tractions) out.emplace_back(t.boundary, "traction");
  return out;
}

bool finite(const std::array<double, 2>& v) { return std::isfinite(v[0]) && std::isfinite(v[1]); }

std::array<int, 3> edge_node_ids(const Mesh& mesh, const BoundaryEdge& be) {
  const auto& el = mesh.element(be.element);
  const auto& en = ref::edge_nodes[static_cast<size_t>(be.edge)];
  return {el[static_cast<size_t>(en[0])], el[static_cast<size_t>(en[1])], el[static_cast<size_t>(en[2])]};
}

}  // namespace

std::vector<std::string> FlowBoundaries::names() const {
  std::vector<std::string> out;
  for (const auto& [name, kind] : named_conditions(*this)) out.push_back(name);
  return out;
}

void FlowBoundaries::validate(const Mesh& mesh) const {
  std::map<std::string, std::string> seen;
  for (const auto& [name, kind] : named_conditions(*this)) {
    if (!mesh.has_boundary(name)) {
      std::string known;
      for (const std::string& n : mesh.boundary_names()) known += (known.empty() ? "" : ", ") + n;
      throw std::invalid_argument(
          fmt::format("the mesh has no boundary '{}' (given a {} condition); its boundaries: {}", name, kind, known));
    }
    if (!seen.emplace(name, kind).second)
      throw std::invalid_argument(
          fmt::format("boundary '{}' has two conditions ({} and {}); give each boundary one", name, seen[name], kind));
  }
  for (const auto& c : inflows) {
    if (c.fully_developed && !(std::isfinite(c.mean_velocity) && c.mean_velocity != 0.0))
      throw std::invalid_argument(
          fmt::format("inflow '{}': the mean velocity of a fully developed inflow must be finite and non-zero (got {})",
                      c.boundary, c.mean_velocity));
    if (!c.fully_developed && !finite(c.velocity))
      throw std::invalid_argument(fmt::format("inflow '{}': the given velocity must be finite", c.boundary));
  }
  for (const auto& d : driven_walls)
    if (!finite(d.velocity))
      throw std::invalid_argument(fmt::format("driven wall '{}': the velocity must be finite", d.boundary));
  for (const auto& t : tractions)
    if (!finite(t.traction))
      throw std::invalid_argument(fmt::format("traction boundary '{}': the traction must be finite", t.boundary));
}

std::array<double, 4> InflowFrame::rotate(const std::array<double, 4>& m) const {
  if (identity()) return m;
  const double c = normal[0], s = normal[1];
  return {c * c * m[0] - 2 * c * s * m[1] + s * s * m[2], c * s * (m[0] - m[2]) + (c * c - s * s) * m[1],
          s * s * m[0] + 2 * c * s * m[1] + c * c * m[2], m[3]};
}

std::array<double, 4> InflowFrame::shear_gradient(double g) const {
  if (identity()) return {0.0, g, 0.0, 0.0};
  const double c = normal[0], s = normal[1];  // L = g e1 e2^T
  return {-g * c * s, g * c * c, -g * s * s, g * s * c};
}

InflowFrame InflowFrame::of(const Mesh& mesh, const std::string& boundary, const std::vector<std::string>& symmetry) {
  const std::vector<BoundaryEdge>& edges = mesh.boundary(boundary);
  const std::string what = fmt::format("fully developed inflow '{}'", boundary);
  // its edges must chain into one segment: two ends of degree 1, the rest of degree 2, connected
  std::map<int, std::vector<size_t>> at;  // vertex -> edges
  for (size_t k = 0; k < edges.size(); ++k) {
    const auto n = edge_node_ids(mesh, edges[k]);
    at[n[0]].push_back(k);
    at[n[2]].push_back(k);
  }
  std::vector<int> ends;
  for (const auto& [v, list] : at) {
    if (list.size() > 2)
      throw std::invalid_argument(
          fmt::format("{}: the boundary branches at node {}; it must be one straight segment", what, v));
    if (list.size() == 1) ends.push_back(v);
  }
  std::vector<char> used(edges.size(), 0);
  size_t visited = 0;
  if (ends.size() == 2)
    for (int v = ends[0];;) {
      size_t next = edges.size();
      for (size_t k : at[v])
        if (!used[k]) next = k;
      if (next == edges.size()) break;
      used[next] = 1;
      ++visited;
      const auto n = edge_node_ids(mesh, edges[next]);
      v = n[0] == v ? n[2] : n[0];
    }
  if (ends.size() != 2 || visited != edges.size())
    throw std::invalid_argument(fmt::format(
        "{}: the boundary is not a single segment (it has {} loose ends); give each inlet its own physical group", what,
        ends.size()));
  const Mesh::Point A = mesh.node(ends[0]), B = mesh.node(ends[1]);
  const double dx = B[0] - A[0], dy = B[1] - A[1], L = std::hypot(dx, dy);
  for (int n : mesh.boundary_nodes(boundary)) {
    const Mesh::Point& P = mesh.node(n);
    const double off = std::abs(dx * (P[1] - A[1]) - dy * (P[0] - A[0])) / L;
    if (off > kStraight * L)
      throw std::invalid_argument(fmt::format(
          "{}: the boundary is not straight (node {} at ({:g}, {:g}) lies {:.3g} off the line through its ends); a "
          "fully developed profile needs a straight inlet: straighten it, or give a velocity instead",
          what, n, P[0], P[1], off));
  }
  std::array<double, 2> t = {dx / L, dy / L};
  if (std::abs(t[0]) <= 1e-12) t = {0.0, t[1] > 0 ? 1.0 : -1.0};
  if (std::abs(t[1]) <= 1e-12) t = {t[0] > 0 ? 1.0 : -1.0, 0.0};
  InflowFrame f;
  f.normal = {-t[1] + 0.0, t[0] + 0.0};
  // inward: towards the centre node of the element owning the first edge
  const Mesh::Point& C = mesh.node(mesh.element(edges[0].element)[4]);
  if (f.normal[0] * (C[0] - A[0]) + f.normal[1] * (C[1] - A[1]) < 0)
    f.normal = {-f.normal[0] + 0.0, -f.normal[1] + 0.0};
  std::set<int> sym;
  for (const std::string& s : symmetry)
    for (int n : mesh.boundary_nodes(s)) sym.insert(n);
  double a = f.across(A), b = f.across(B);
  bool a_sym = sym.count(ends[0]) > 0, b_sym = sym.count(ends[1]) > 0;
  if (a > b) {
    std::swap(a, b);
    std::swap(a_sym, b_sym);
  }
  if (a_sym && b_sym)
    throw std::invalid_argument(
        fmt::format("{}: both its ends lie on symmetry lines, so the channel of its profile is undefined; make one "
                    "of them a wall",
                    what));
  f.lo = a_sym ? 2 * a - b : a;
  f.hi = b_sym ? 2 * b - a : b;
  return f;
}

std::map<int, std::vector<int>> axis_normal_components(const Mesh& mesh, const std::string& boundary,
                                                       const std::string& what) {
  std::map<int, std::vector<int>> out;
  for (const BoundaryEdge& be : mesh.boundary(boundary)) {
    const auto n = edge_node_ids(mesh, be);
    double hx = 0, hy = 0;
    for (int k : {1, 2}) {
      hx = std::max(hx, std::abs(mesh.node(n[static_cast<size_t>(k)])[0] - mesh.node(n[0])[0]));
      hy = std::max(hy, std::abs(mesh.node(n[static_cast<size_t>(k)])[1] - mesh.node(n[0])[1]));
    }
    const double h = std::max(hx, hy);
    int c = -1;
    if (hx <= kStraight * h)
      c = 0;  // along y: v_x is the normal component
    else if (hy <= kStraight * h)
      c = 1;
    if (c < 0) {
      const Mesh::Point &p = mesh.node(n[0]), &q = mesh.node(n[2]);
      throw std::invalid_argument(fmt::format(
          "{} '{}': its edge from ({:g}, {:g}) to ({:g}, {:g}) runs along neither x nor y; keller's velocity "
          "unknowns are v_x and v_y (no rotated unknowns), so a {} must be a line x = const or y = const",
          what, boundary, p[0], p[1], q[0], q[1], what));
    }
    for (int node : n) {
      auto& list = out[node];
      if (std::find(list.begin(), list.end(), c) == list.end()) list.push_back(c);
    }
  }
  return out;
}

}  // namespace keller
