#include "problems/flow/FlowObservables.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <stdexcept>

#include "problems/flow/StreamFunction.hpp"
#include "problems/laws/InflowProfile.hpp"

namespace keller {

const char* to_string(FlowObservableSpec::Kind k) {
  using K = FlowObservableSpec::Kind;
  switch (k) {
    case K::Force: return "force";
    case K::FlowRate: return "flow-rate";
    case K::MeanPressure: return "mean-pressure";
    case K::PressureDrop: return "pressure-drop";
    case K::CouetteCorrection: return "couette-correction";
    case K::Reattachment: return "reattachment";
    case K::StreamFunctionExtremum: return "stream-function-extremum";
    case K::MinM1: return "min-m1";
  }
  return "?";
}

FlowObservableSpec::Kind flow_observable_kind(const std::string& name) {
  using K = FlowObservableSpec::Kind;
  std::string known;
  for (K k : {K::Force, K::FlowRate, K::MeanPressure, K::PressureDrop, K::CouetteCorrection, K::Reattachment,
              K::StreamFunctionExtremum, K::MinM1}) {
    if (name == to_string(k)) return k;
    known += (known.empty() ? "" : ", ") + std::string(to_string(k));
  }
  throw std::invalid_argument("unknown observable kind '" + name + "' (" + known + ")");
}

// The wall's Gauss points in the order of their arclength s from origin.
struct FlowObservables::Chain {
  struct Point {
    double s;
    int edge;  // index into edges
    int q;     // Gauss point of that edge
  };
  std::vector<BoundaryEdge> edges;
  std::vector<Point> points;
};

namespace {

using Kind = FlowObservableSpec::Kind;

std::invalid_argument spec_error(const FlowObservableSpec& s, const std::string& what) {
  return std::invalid_argument("observable '" + s.name + "' (" + to_string(s.kind) + "): " + what);
}

std::string joined(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::string point(const Mesh::Point& p) { return "(" + std::to_string(p[0]) + ", " + std::to_string(p[1]) + ")"; }

// Length of a quadratic edge through X[0], X[1], X[2] (at r = -1, 0, 1) from r = -1 to r = r1:
// 5-point Gauss-Legendre on |dX/dr|, a smooth integrand (the edge is not degenerate).
double edge_arclength(const double (&X)[3][2], double r1) {
  static const double gx[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  static const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                               0.2369268850561891};
  double sum = 0;
  for (int k = 0; k < 5; ++k) {
    const double r = -1.0 + 0.5 * (r1 + 1.0) * (gx[k] + 1.0);
    double d[2] = {0, 0};
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < 2; ++i) d[i] += X[a][i] * ref::lagrange2_d(a, r);
    sum += gw[k] * std::hypot(d[0], d[1]);
  }
  return 0.5 * (r1 + 1.0) * sum;
}

}  // namespace

FlowObservables::FlowObservables(const Mesh& mesh, const DofMap& dofs, const FlowEquations& flow,
                                 const ParameterSet& params, const FlowConstraints& constraints,
                                 std::vector<FlowObservableSpec> specs)
    : mesh_(&mesh),
      dofs_(&dofs),
      flow_(&flow),
      params_(&params),
      specs_(std::move(specs)),
      symmetry_(constraints.symmetry),
      traction_(mesh, dofs, flow) {
  given_.assign(static_cast<size_t>(dofs.size()), 0);
  for (int d : constraints.given)
    if (d >= 0 && d < dofs.size()) given_[static_cast<size_t>(d)] = 1;
  const std::string known = joined(mesh.boundary_names());
  for (const std::string& b : symmetry_)
    if (!mesh.has_boundary(b))
      throw std::invalid_argument("flow observables: the symmetry line '" + b +
                                  "' is not a boundary of the mesh (its boundaries: " + known + ")");
  chains_.resize(specs_.size());
  region_nodes_.resize(specs_.size());
  std::set<std::string> seen;
  std::vector<char> fluid(static_cast<size_t>(mesh.num_nodes()), 0);
  for (int e : flow.elements())
    for (int a : mesh.element(e)) fluid[static_cast<size_t>(a)] = 1;
  for (size_t i = 0; i < specs_.size(); ++i) {
    const FlowObservableSpec& s = specs_[i];
    if (s.name.empty()) throw spec_error(s, "has no name");
    if (!seen.insert(s.name).second) throw spec_error(s, "the name is used by another observable: give each its own");
    if (!std::isfinite(s.scale)) throw spec_error(s, "scale must be a finite number");
    auto need = [&](const std::string& b, const char* role) {
      if (b.empty()) throw spec_error(s, std::string("needs a boundary (") + role + ")");
      if (!mesh.has_boundary(b))
        throw spec_error(s,
                         "the boundary '" + b + "' (" + role + ") is not in the mesh (its boundaries: " + known + ")");
    };
    switch (s.kind) {
      case Kind::Force:
        need(s.boundary, "the boundary the force is on");
        if (s.component != 0 && s.component != 1) throw spec_error(s, "component must be 0 (x) or 1 (y)");
        break;
      case Kind::FlowRate: need(s.boundary, "the boundary the flow crosses"); break;
      case Kind::MeanPressure: need(s.boundary, "the boundary the pressure is averaged on"); break;
      case Kind::PressureDrop:
      case Kind::CouetteCorrection:
        need(s.boundary, s.kind == Kind::PressureDrop ? "from" : "the inflow");
        need(s.other, s.kind == Kind::PressureDrop ? "to" : "the outflow");
        if (s.other == s.boundary) throw spec_error(s, "the two boundaries are the same ('" + s.boundary + "')");
        break;
      case Kind::Reattachment:
        need(s.boundary, "the wall");
        chains_[i] = build_chain(s);
        break;
      case Kind::StreamFunctionExtremum: {
        need(s.boundary, "where psi = 0");
        if (!s.other.empty()) need(s.other, "the flow rate psi is divided by");
        const auto& r = s.region;
        if (!(r[0] < r[1]) || !(r[2] < r[3]))
          throw spec_error(s, "the region must be xmin < xmax, ymin < ymax (got " + std::to_string(r[0]) + " " +
                                  std::to_string(r[1]) + " " + std::to_string(r[2]) + " " + std::to_string(r[3]) + ")");
        for (int n = 0; n < mesh.num_nodes(); ++n) {
          const Mesh::Point& x = mesh.node(n);
          if (fluid[static_cast<size_t>(n)] && x[0] >= r[0] && x[0] <= r[1] && x[1] >= r[2] && x[1] <= r[3])
            region_nodes_[i].push_back(n);
        }
        if (region_nodes_[i].empty()) throw spec_error(s, "the region holds no node of the fluid's mesh: enlarge it");
        if (!stream_) stream_ = std::make_unique<StreamFunction>(mesh, dofs, flow.elements(), flow.geometry());
        break;
      }
      case Kind::MinM1:
        if (!flow.options().viscoelastic()) throw spec_error(s, "the fluid is Newtonian: it has no conformation");
        if (s.component < 0 || s.component > 2)
          throw spec_error(s, "component must be 0 (the value), 1 (its x) or 2 (its y)");
        if (s.component > 0 && s.monitor)
          throw spec_error(s,
                           "the place of min m1 jumps from node to node: it cannot be a monitor (min m1 itself can)");
        break;
    }
  }
}

FlowObservables::~FlowObservables() = default;

std::vector<std::string> FlowObservables::names() const {
  std::vector<std::string> out;
  for (const FlowObservableSpec& s : specs_) out.push_back(s.name);
  return out;
}

bool FlowObservables::component_given(const std::string& boundary, int c) const {
  const int fv = dofs_->field_index("velocity");
  for (int n : mesh_->boundary_nodes(boundary))
    if (!given(dofs_->node_dof(fv, n, c))) return false;
  return true;
}

bool FlowObservables::touches_symmetry(const std::string& boundary) const {
  const std::vector<int> nodes = mesh_->boundary_nodes(boundary);
  for (const std::string& sym : symmetry_)
    for (int n : mesh_->boundary_nodes(sym))
      if (std::binary_search(nodes.begin(), nodes.end(), n)) return true;
  return false;
}

bool FlowObservables::uses_reaction(const FlowObservableSpec& s) const {
  return s.kind == Kind::Force && !s.surface_integral && component_given(s.boundary, s.component);
}

bool FlowObservables::needs_reaction() const {
  return std::any_of(specs_.begin(), specs_.end(), [&](const FlowObservableSpec& s) { return uses_reaction(s); });
}

Status FlowObservables::edge_failure(const BoundaryEdge& be) const {
  return {StatusCode::InvalidState,
          "flow observables: element " + std::to_string(be.element) + " on the boundary is inverted or degenerate"};
}

Status FlowObservables::integrals(const std::string& boundary, const Vector& u, EdgeIntegrals& out) const {
  out = {};
  std::array<TractionPoint, ref::kEdgeQp> tp;
  for (const BoundaryEdge& be : mesh_->boundary(boundary)) {
    if (!traction_.evaluate(u, *params_, be, tp)) return edge_failure(be);
    for (const TractionPoint& t : tp) {
      out.length += t.wds;
      out.flow_rate += t.wds * (t.velocity[0] * t.normal[0] + t.velocity[1] * t.normal[1]);
      out.pressure += t.wds * t.pressure;
      out.x += t.wds * t.x[0];
    }
  }
  return {};
}

Status FlowObservables::force(const FlowObservableSpec& s, const Vector& u, const Vector* R, double& value) const {
  const int c = s.component;
  std::array<TractionPoint, ref::kEdgeQp> tp;
  double f = 0;
  if (!uses_reaction(s)) {
    for (const BoundaryEdge& be : mesh_->boundary(s.boundary)) {
      if (!traction_.evaluate(u, *params_, be, tp)) return edge_failure(be);
      for (const TractionPoint& t : tp) f -= t.wds * t.traction[c];
    }
    value = s.scale * f;
    return {};
  }
  if (R == nullptr || R->size() != dofs_->size())
    throw std::logic_error("observable '" + s.name + "': the force by the reaction needs the weak residual");
  const int fv = dofs_->field_index("velocity");
  const std::vector<int> nodes = mesh_->boundary_nodes(s.boundary);
  auto on = [&](int n) { return std::binary_search(nodes.begin(), nodes.end(), n); };
  for (int n : nodes) f -= (*R)[dofs_->node_dof(fv, n, c)];
  // a node shared with a neighbour whose velocity is given too: its residual holds the
  // neighbour's traction weighted by the node's test function there; take it out
  const ref::Tables& tb = ref::tables();
  for (const std::string& b : mesh_->boundary_names()) {
    if (b == s.boundary) continue;
    for (const BoundaryEdge& be : mesh_->boundary(b)) {
      const std::array<int, 9>& en = mesh_->element(be.element);
      bool shared = false, all_given = true;
      for (int a : ref::edge_nodes[static_cast<size_t>(be.edge)]) {
        const int n = en[static_cast<size_t>(a)];
        shared = shared || on(n);
        all_given = all_given && given(dofs_->node_dof(fv, n, c));
      }
      if (!shared || !all_given) continue;
      if (!traction_.evaluate(u, *params_, be, tp)) return edge_failure(be);
      for (int q = 0; q < ref::kEdgeQp; ++q) {
        double phi = 0;
        for (int a : ref::edge_nodes[static_cast<size_t>(be.edge)])
          if (on(en[static_cast<size_t>(a)])) phi += tb.edge_N2[be.edge][q][a];
        f += phi * tp[static_cast<size_t>(q)].wds * tp[static_cast<size_t>(q)].traction[c];
      }
    }
  }
  value = s.scale * f;
  return {};
}

Status FlowObservables::couette(const FlowObservableSpec& s, const Vector& u, double& value) const {
  EdgeIntegrals in, out;
  if (Status st = integrals(s.boundary, u, in); !st.is_ok()) return st;
  if (Status st = integrals(s.other, u, out); !st.is_ok()) return st;
  const std::function<double(double)> eta = flow_->viscosity(*params_);
  // a channel's fully developed pressure gradient, from its end boundary; and its half-width
  auto channel = [&](const std::string& name, const EdgeIntegrals& e, double& H) {
    H = touches_symmetry(name) ? e.length : 0.5 * e.length;
    const double U = std::abs(e.flow_rate) / e.length;
    return U > 0 ? FullyDevelopedProfile(eta, H, U).pressure_gradient() : 0.0;
  };
  double Hu = 0, Hd = 0;
  const double Gu = channel(s.boundary, in, Hu), Gd = channel(s.other, out, Hd);
  if (!(Gd > 0))
    return {StatusCode::InvalidState, "observable '" + s.name + "': no flow through '" + s.other +
                                          "' (the Couette correction divides by its wall shear stress)"};
  const double Lu = std::abs(in.x / in.length - s.origin[0]), Ld = std::abs(out.x / out.length - s.origin[0]);
  const double dp = in.pressure / in.length - out.pressure / out.length;
  value = s.scale * (dp - Gu * Lu - Gd * Ld) / (2.0 * Gd * Hd);
  return {};
}

Status FlowObservables::evaluate(const Vector& u, const Vector* R, std::vector<double>& values) const {
  values.assign(specs_.size(), NAN);
  Vector psi;
  if (stream_) psi = stream_->solve(u);
  for (size_t i = 0; i < specs_.size(); ++i) {
    const FlowObservableSpec& s = specs_[i];
    double& v = values[i];
    EdgeIntegrals a, b;
    Status st;
    switch (s.kind) {
      case Kind::Force: st = force(s, u, R, v); break;
      case Kind::FlowRate:
        st = integrals(s.boundary, u, a);
        v = s.scale * a.flow_rate;
        break;
      case Kind::MeanPressure:
        st = integrals(s.boundary, u, a);
        v = s.scale * a.pressure / a.length;
        break;
      case Kind::PressureDrop:
        st = integrals(s.boundary, u, a);
        if (st.is_ok()) st = integrals(s.other, u, b);
        v = s.scale * (a.pressure / a.length - b.pressure / b.length);
        break;
      case Kind::CouetteCorrection: st = couette(s, u, v); break;
      case Kind::Reattachment: st = reattachment(s, *chains_[i], u, v); break;
      case Kind::StreamFunctionExtremum: st = stream_extremum(s, region_nodes_[i], psi, u, v); break;
      case Kind::MinM1: v = min_m1(s, u); break;
    }
    if (!st.is_ok()) return st;
  }
  return {};
}

Status FlowObservables::stream_extremum(const FlowObservableSpec& s, const std::vector<int>& region, const Vector& psi,
                                        const Vector& u, double& value) const {
  const std::vector<int> wall = mesh_->boundary_nodes(s.boundary);
  double ref = 0;
  for (int n : wall) ref += psi[n];
  ref /= static_cast<double>(wall.size());
  double x = s.maximum ? -INFINITY : INFINITY;
  for (int n : region) x = s.maximum ? std::max(x, psi[n] - ref) : std::min(x, psi[n] - ref);
  value = s.scale * x;
  if (s.other.empty()) return {};
  EdgeIntegrals e;
  if (Status st = integrals(s.other, u, e); !st.is_ok()) return st;
  if (!(std::abs(e.flow_rate) > 0))
    return {StatusCode::InvalidState,
            "observable '" + s.name + "': no flow through '" + s.other + "' to divide the stream function by"};
  value /= std::abs(e.flow_rate);
  return {};
}

double FlowObservables::min_m1(const FlowObservableSpec& s, const Vector& u) const {
  const FlowEquations::ConformationExtremes x = flow_->conformation_extremes(u);
  if (s.component == 0) return s.scale * x.min_m1;
  if (x.min_m1_node < 0) return NAN;
  return s.scale * mesh_->node(x.min_m1_node)[static_cast<size_t>(s.component - 1)];
}

std::unique_ptr<FlowObservables::Chain> FlowObservables::build_chain(const FlowObservableSpec& s) const {
  const std::vector<BoundaryEdge>& edges = mesh_->boundary(s.boundary);
  // the edges' end vertices, and the edges at each vertex
  std::map<int, std::vector<int>> at;
  auto ends = [&](const BoundaryEdge& be) {
    const std::array<int, 9>& en = mesh_->element(be.element);
    const auto& loc = ref::edge_nodes[static_cast<size_t>(be.edge)];
    return std::array<int, 2>{en[static_cast<size_t>(loc[0])], en[static_cast<size_t>(loc[2])]};
  };
  for (size_t k = 0; k < edges.size(); ++k)
    for (int n : ends(edges[k])) at[n].push_back(static_cast<int>(k));
  std::vector<int> tips;
  for (const auto& [n, list] : at) {
    if (list.size() > 2) throw spec_error(s, "the wall '" + s.boundary + "' branches at " + point(mesh_->node(n)));
    if (list.size() == 1) tips.push_back(n);
  }
  if (tips.size() != 2)
    throw spec_error(s, "the wall '" + s.boundary + "' must be one open curve (it is closed or in pieces)");
  auto dist = [&](int n) { return std::hypot(mesh_->node(n)[0] - s.origin[0], mesh_->node(n)[1] - s.origin[1]); };
  const int start = dist(tips[0]) <= dist(tips[1]) ? tips[0] : tips[1];
  auto chain = std::make_unique<Chain>();
  const ref::Tables& tb = ref::tables();
  int node = start, prev = -1;
  double s0 = 0;
  for (size_t step = 0; step < edges.size(); ++step) {
    const std::vector<int>& list = at[node];
    const int k = list[0] != prev ? list[0] : (list.size() > 1 ? list[1] : -1);
    if (k < 0) break;
    const BoundaryEdge& be = edges[static_cast<size_t>(k)];
    const std::array<int, 2> e = ends(be);
    const bool reversed = e[0] != node;
    double X[3][2];
    const std::array<int, 9>& en = mesh_->element(be.element);
    for (int a = 0; a < 3; ++a)
      for (int i = 0; i < 2; ++i)
        X[a][i] = mesh_->node(en[static_cast<size_t>(ref::edge_nodes[static_cast<size_t>(be.edge)][a])])[i];
    const double length = edge_arclength(X, 1.0);
    const int index = static_cast<int>(chain->edges.size());
    chain->edges.push_back(be);
    for (int q = 0; q < ref::kEdgeQp; ++q) {
      const double r = (be.edge == 0 || be.edge == 2) ? tb.edge_s[be.edge][q] : tb.edge_t[be.edge][q];
      const double along = edge_arclength(X, r);
      chain->points.push_back({s0 + (reversed ? length - along : along), index, q});
    }
    s0 += length;
    prev = k;
    node = reversed ? e[0] : e[1];
  }
  if (chain->edges.size() != edges.size())
    throw spec_error(s, "the wall '" + s.boundary + "' must be one open curve (it is in pieces)");
  if (dist(start) > 1e-6 * s0)
    throw spec_error(s, "the origin " + point(s.origin) + " must be an end of the wall '" + s.boundary +
                            "' (its ends: " + point(mesh_->node(tips[0])) + ", " + point(mesh_->node(tips[1])) + ")");
  std::sort(chain->points.begin(), chain->points.end(),
            [](const Chain::Point& a, const Chain::Point& b) { return a.s < b.s; });
  return chain;
}

Status FlowObservables::reattachment(const FlowObservableSpec& s, const Chain& chain, const Vector& u,
                                     double& value) const {
  // the wall shear stress (tangential traction, tangent (-n_y, n_x)) at every Gauss point
  std::vector<std::array<TractionPoint, ref::kEdgeQp>> tp(chain.edges.size());
  for (size_t k = 0; k < chain.edges.size(); ++k)
    if (!traction_.evaluate(u, *params_, chain.edges[k], tp[k])) return edge_failure(chain.edges[k]);
  std::vector<double> tau(chain.points.size());
  for (size_t i = 0; i < chain.points.size(); ++i) {
    const TractionPoint& t = tp[static_cast<size_t>(chain.points[i].edge)][static_cast<size_t>(chain.points[i].q)];
    tau[i] = -t.normal[1] * t.traction[0] + t.normal[0] * t.traction[1];
  }
  // from the far end towards origin: the sign there, then the first point where it is lost
  value = 0;
  size_t i = tau.size();
  while (i > 0 && tau[i - 1] == 0) --i;
  if (i == 0) return {};
  const double sign = tau[i - 1] > 0 ? 1.0 : -1.0;
  for (size_t k = i - 1; k > 0; --k) {
    const double a = sign * tau[k], b = sign * tau[k - 1];  // a > 0
    if (b > 0) continue;
    const double sa = chain.points[k].s, sb = chain.points[k - 1].s;
    value = s.scale * (sa + (sb - sa) * a / (a - b));
    return {};
  }
  return {};
}

}  // namespace keller
