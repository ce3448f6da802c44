#include "problems/cylinder/CylinderProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "core/BlockMeshBuilder.hpp"
#include "problems/components/BoundaryTraction.hpp"
#include "problems/components/Composition.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

CylinderMeshSpec CylinderMeshSpec::preset(const std::string& name) {
  // C<f>: refinement f of C1, uniform around the cylinder and across the channel. W<f>: the same
  // sizes with the wake resolved: the rear eighth of the cylinder and the channel behind it carry
  // twice as many elements (16 f), graded 4:1 towards the rear stagnation point around the arc and
  // 20:1 towards the axis across the channel, where the polymer stress has its boundary layer.
  static const char* names[] = {"C1", "C2", "C3", "C4", "W1", "W2", "W3", "W4"};
  for (int i = 0; i < 8; ++i) {
    if (name != names[i]) continue;
    const int f = i % 4 + 1;
    CylinderMeshSpec s;
    s.name = name;
    s.n_quarter = 8 * f;
    s.n_radial = 8 * f;
    s.nx_upstream = 12 * f;
    s.nx_downstream = 24 * f;
    if (i >= 4) {
      s.n_rear = 16 * f;
      s.rear_ratio = 4.0;
      s.wake_ratio = 20.0;
    }
    return s;
  }
  throw std::invalid_argument("unknown cylinder mesh '" + name + "' (C1..C4, W1..W4)");
}

void CylinderOptions::declare(SceneSchema& s) {
  s.section("geometry", "cylinder of radius 1 centred in a channel of half-width 2 (lengths in R)");
  s.real("geometry.upstream_length", 20.0, "distance from the inflow to the cylinder's centre", Range::above(2.0));
  s.real("geometry.downstream_length", 30.0, "distance from the cylinder's centre to the outflow", Range::above(2.0));
  s.section("mesh",
            "named meshes C1..C4 (refinement 1..4 of C1), W1..W4 (the same with the wake resolved) or explicit sizes");
  s.string("mesh.name", "C1", "mesh preset; 'custom' takes the sizes below",
           {"C1", "C2", "C3", "C4", "W1", "W2", "W3", "W4", "custom"});
  // at most 1000 elements along the cylinder and 2000 along a channel: under 10^8 unknowns, far
  // inside int (W4 has 32 and 96); a larger count is a scene error, not a failed allocation
  const Range count = Range::between(0, 1000), length_count = Range::between(0, 2000);
  s.integer("mesh.n_quarter", 0, "custom: elements along a quarter of the cylinder", count);
  s.integer("mesh.n_radial", 0, "custom: elements from the cylinder to the box around it", count);
  s.integer("mesh.nx_upstream", 0, "custom: elements along the upstream channel", length_count);
  s.integer("mesh.nx_downstream", 0, "custom: elements along the downstream channel", length_count);
  s.integer("mesh.n_rear", 0,
            "custom: elements around the rear eighth of the cylinder and across the channel behind it (0: n_quarter)",
            count);
  s.real("mesh.radial_ratio", 4.0, "largest / smallest radial element (fine at the cylinder)", Range::at_least(1));
  s.real("mesh.upstream_ratio", 10.0, "largest / smallest upstream element (fine near the cylinder)",
         Range::at_least(1));
  s.real("mesh.downstream_ratio", 20.0, "largest / smallest downstream element (fine in the near wake)",
         Range::at_least(1));
  s.real("mesh.wake_ratio", 1.0,
         "largest / smallest element across the channel behind the cylinder, fine on the axis (W presets: 20)",
         Range::at_least(1));
  s.real("mesh.rear_ratio", 1.0,
         "largest / smallest element around the rear eighth, fine at the rear stagnation point (W presets: 4)",
         Range::at_least(1));
  FluidOptions::declare(s, 0.59, 0.1);
}

CylinderOptions CylinderOptions::from_scene(const Scene& sc) {
  CylinderOptions o;
  o.upstream_length = sc.real("geometry.upstream_length");
  o.downstream_length = sc.real("geometry.downstream_length");
  const std::string name = sc.string("mesh.name");
  const char* sizes[] = {"mesh.n_quarter", "mesh.n_radial", "mesh.nx_upstream", "mesh.nx_downstream"};
  if (name == "custom") {
    for (const char* k : sizes)
      if (sc.integer(k) < 1) throw sc.error(k, "a custom mesh needs every size >= 1");
    o.mesh.name = "custom";
    o.mesh.n_quarter = static_cast<int>(sc.integer("mesh.n_quarter"));
    o.mesh.n_radial = static_cast<int>(sc.integer("mesh.n_radial"));
    o.mesh.nx_upstream = static_cast<int>(sc.integer("mesh.nx_upstream"));
    o.mesh.nx_downstream = static_cast<int>(sc.integer("mesh.nx_downstream"));
    o.mesh.n_rear = static_cast<int>(sc.integer("mesh.n_rear"));
  } else {
    for (const char* k : {"mesh.n_quarter", "mesh.n_radial", "mesh.nx_upstream", "mesh.nx_downstream", "mesh.n_rear"})
      if (sc.differs_from_default(k))
        throw sc.error(k, "explicit sizes need mesh.name = \"custom\" (got \"" + name + "\")");
    o.mesh = CylinderMeshSpec::preset(name);
  }
  // a ratio the scene sets replaces the preset's
  auto ratio = [&](const char* key, double& value) {
    if (name == "custom" || sc.differs_from_default(key)) value = sc.real(key);
  };
  ratio("mesh.radial_ratio", o.mesh.radial_ratio);
  ratio("mesh.upstream_ratio", o.mesh.upstream_ratio);
  ratio("mesh.downstream_ratio", o.mesh.downstream_ratio);
  ratio("mesh.wake_ratio", o.mesh.wake_ratio);
  ratio("mesh.rear_ratio", o.mesh.rear_ratio);
  o.fluid = FluidOptions::from_scene(sc);
  return o;
}

Mesh build_cylinder_mesh(const CylinderOptions& o) {
  const CylinderMeshSpec& s = o.mesh;
  const double Lu = o.upstream_length, Ld = o.downstream_length;
  auto arc = [](double theta) { return Mesh::Point{std::cos(theta), std::sin(theta)}; };
  // transfinite blend between the arc (t = 0) and a straight side of the box (t = 1)
  auto blend = [](const Mesh::Point& a, const Mesh::Point& b, double t) {
    return Mesh::Point{(1 - t) * a[0] + t * b[0], (1 - t) * a[1] + t * b[1]};
  };
  const Grading radial = Grading::start(s.radial_ratio), around = Grading::uniform();
  // Across the channel behind the cylinder the vertices are graded towards the axis (the wake),
  // on x = 2 and downstream; on the cylinder the east block's vertices stay uniform in angle, the
  // arc being parametrised by the inverse of the grading's continuous form
  // s(xi) = (q^(n xi) - 1) / (q^n - 1), q = ratio^(1 / (n - 1)), which has s(i / n) at its vertices.
  const Grading wake = Grading::start(s.wake_ratio);
  const int nw = s.n_rear > 0 ? s.n_rear : s.n_quarter;
  const double qn = nw > 1 ? std::pow(s.wake_ratio, static_cast<double>(nw) / (nw - 1)) : 1.0;
  const double qr = nw > 1 ? std::pow(s.rear_ratio, static_cast<double>(nw) / (nw - 1)) : 1.0;
  auto uniform_in = [=](double v) {
    const double xi = qn > 1.0 ? std::log1p(v * (qn - 1.0)) / std::log(qn) : v;
    return qr > 1.0 ? std::expm1(xi * std::log(qr)) / (qr - 1.0) : xi;
  };
  BlockMeshBuilder b;
  const int up = b.add_block({"upstream",
                              "fluid",
                              s.nx_upstream,
                              s.n_quarter,
                              Grading::end(s.upstream_ratio),
                              around,
                              [=](double u, double v) {
                                return Mesh::Point{-Lu + (Lu - 2.0) * u, 2.0 * v};
                              },
                              {"symmetry", "", "wall", "inflow"}});
  const int west = b.add_block({"west",
                                "fluid",
                                s.n_quarter,
                                s.n_radial,
                                around,
                                radial,
                                [=](double u, double t) {
                                  return blend(arc(M_PI - 0.25 * M_PI * u), {-2.0, 2.0 * u}, t);
                                },
                                {"cylinder", "", "", "symmetry"}});
  const int north = b.add_block({"north",
                                 "fluid",
                                 2 * s.n_quarter,
                                 s.n_radial,
                                 around,
                                 radial,
                                 [=](double u, double t) {
                                   return blend(arc(0.75 * M_PI - 0.5 * M_PI * u), {-2.0 + 4.0 * u, 2.0}, t);
                                 },
                                 {"cylinder", "", "wall", ""}});
  // east runs radially in s and around in t (so that it is positively oriented and its outer
  // side x = 2 runs upwards like the downstream block's inflow side)
  const int east = b.add_block({"east",
                                "fluid",
                                s.n_radial,
                                nw,
                                radial,
                                wake,
                                [=](double r, double v) {
                                  return blend(arc(0.25 * M_PI * uniform_in(v)), {2.0, 2.0 * v}, r);
                                },
                                {"symmetry", "", "", "cylinder"}});
  const int down = b.add_block({"downstream",
                                "fluid",
                                s.nx_downstream,
                                nw,
                                Grading::start(s.downstream_ratio),
                                wake,
                                [=](double u, double v) {
                                  return Mesh::Point{2.0 + (Ld - 2.0) * u, 2.0 * v};
                                },
                                {"symmetry", "outflow", "wall", ""}});
  b.connect(up, Side::Right, west, Side::Top);
  b.connect(west, Side::Right, north, Side::Left);
  b.connect(north, Side::Right, east, Side::Top);
  b.connect(east, Side::Right, down, Side::Left);
  return b.build();
}

CylinderProblem::CylinderProblem(const CylinderOptions& options)
    : options_(options), mesh_(build_cylinder_mesh(options)) {
  FlowBoundaries bc;
  bc.inflows = {{"inflow"}};  // across y in [0, 2], mirrored about the symmetry line: the channel [-2, 2]
  bc.outflows = {{"outflow"}};
  bc.walls = {"wall", "cylinder"};
  bc.symmetry = {"symmetry"};
  flow_ = std::make_unique<FlowEquations>(mesh_, "fluid", options_.fluid, bc, params_, -1);
  ComposedSystem system = Composition().add(*flow_).build(mesh_, params_);
  dofs_ = std::move(system.dofs);
  dirichlet_ = system.dirichlet;
  assemble(dofs_->size(), system.terms());
  const int fv = dofs_->field_index("velocity");
  on_cylinder_.assign(static_cast<size_t>(mesh_.num_nodes()), 0);
  for (int n : mesh_.boundary_nodes("cylinder")) {
    cylinder_vx_.push_back(dofs_->node_dof(fv, n, 0));
    on_cylinder_[static_cast<size_t>(n)] = 1;
  }
  for (int e = 0; e < mesh_.num_elements(); ++e)
    for (int n : mesh_.element(e))
      if (on_cylinder_[static_cast<size_t>(n)]) {
        cylinder_elements_.push_back(e);
        break;
      }
}

Vector CylinderProblem::initial_guess() {
  // The Stokes flow past the cylinder (one linear solve of the smaller Stokes system) with the
  // relaxed conformation, as FlowProblem starts: from the inflow profile continued past the
  // cylinder, whose velocity there is wrong by O(1), Newton needed a second factorisation on
  // W3 (its chord steps from the profile's Jacobian stalled at |F| ~ 1e-5); from the Stokes flow
  // one factorisation converges (W3 at Wi = 1e-4: first state 6.5 s -> 4.0 s, docs/cylinder.md).
  Vector u = Vector::Zero(size());
  if (!flow_->stokes_state(u).is_ok()) {
    u.setZero();
    flow_->initial_guess(u);
  }
  for (int k = 0; k < dirichlet_->num_items(); ++k) u[dirichlet_->dofs()[k]] = dirichlet_->value(k);
  return u;
}

double CylinderProblem::drag(const Vector& u) const {
  Vector R;
  const Status st = assembler().weak_residual(u, R);
  if (!st.is_ok()) return NAN;
  // sum of the weak residual over the cylinder's nodes = int T n_out ds (n_out into the
  // cylinder) = minus the force on it; both halves
  double f = 0;
  for (int d : cylinder_vx_) f -= R[d];
  return 2.0 * f;
}

CylinderProblem::DragTerms CylinderProblem::drag_terms(const Vector& u) const {
  DragTerms out;
  out.reaction = drag(u);
  const FluidOptions& fo = options_.fluid;
  const bool ve = fo.viscoelastic();
  const int fv = dofs_->field_index("velocity"), fl = ve ? dofs_->field_index("gradient") : -1;
  const double beta = ve ? params_.get("beta") : 1.0;
  const double beta_a = fo.kernel.devss >= 0 ? fo.kernel.devss : 1.0 - beta;
  const ref::Tables& tb = ref::tables();
  auto gather = [&](int f, int e, int n) {
    std::vector<int> d(static_cast<size_t>(n));
    dofs_->element_dofs(f, e, d.data());
    std::vector<double> v(static_cast<size_t>(n));
    for (int i = 0; i < n; ++i) v[static_cast<size_t>(i)] = u[d[static_cast<size_t>(i)]];
    return v;
  };
  const BoundaryTraction traction(mesh_, *dofs_, *flow_);
  std::array<TractionPoint, ref::kEdgeQp> tp;
  for (const BoundaryEdge& be : mesh_.boundary("cylinder")) {
    if (!traction.evaluate(u, params_, be, tp)) return {NAN, NAN, NAN};
    // the normal is the fluid's outward one (into the cylinder): the force on the cylinder
    // is minus the integral of T n_out; both halves
    for (const TractionPoint& t : tp) out.surface -= 2.0 * t.wds * t.traction[0];
  }
  if (ve) {
    for (int e : cylinder_elements_) {
      double xy[9][2];
      mesh_.element_nodes(e, xy);
      std::array<QpGeometry<double>, ref::kQp> geo;
      if (!map_element(xy, geo)) return {NAN, NAN, NAN};
      const std::vector<double> v = gather(fv, e, 18), lc = gather(fl, e, 16);
      const auto& nodes = mesh_.element(e);
      for (int q = 0; q < ref::kQp; ++q) {
        const QpGeometry<double>& g = geo[static_cast<size_t>(q)];
        double K[2][2] = {{0, 0}, {0, 0}}, L[2][2] = {{0, 0}, {0, 0}}, gphi[2] = {0, 0};
        for (int a = 0; a < 9; ++a) {
          for (int j = 0; j < 2; ++j) {
            K[0][j] += g.dN2dx[a][j] * v[static_cast<size_t>(a)];
            K[1][j] += g.dN2dx[a][j] * v[static_cast<size_t>(9 + a)];
          }
          if (on_cylinder_[static_cast<size_t>(nodes[static_cast<size_t>(a)])]) {
            gphi[0] += g.dN2dx[a][0];
            gphi[1] += g.dN2dx[a][1];
          }
        }
        for (int k = 0; k < 4; ++k)
          for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) L[i][j] += tb.N1[q][k] * lc[static_cast<size_t>(4 * (2 * i + j) + k)];
        const double dxx = 2.0 * beta_a * (K[0][0] - L[0][0]);
        const double dxy = beta_a * ((K[0][1] + K[1][0]) - (L[0][1] + L[1][0]));
        out.devss -= 2.0 * g.wdetJ * (gphi[0] * dxx + gphi[1] * dxy);
      }
    }
  }
  return out;
}

std::vector<std::string> CylinderProblem::observable_names() const {
  std::vector<std::string> names = {"K", "K_surface"};
  if (options_.fluid.viscoelastic()) names.push_back("K_devss");
  if (options_.fluid.viscoelastic()) names.insert(names.end(), {"min_m1", "max_m3"});
  return names;
}

Status CylinderProblem::observables(const Vector& u, std::vector<double>& values) {
  const DragTerms d = drag_terms(u);
  values = {d.reaction, d.surface};
  if (options_.fluid.viscoelastic()) {
    values.push_back(d.devss);
    const FlowEquations::ConformationExtremes x = flow_->conformation_extremes(u);
    values.push_back(x.min_m1);
    values.push_back(x.max_m3);
  }
  return {};
}

std::vector<std::string> CylinderProblem::monitor_names() const {
  if (options_.fluid.viscoelastic()) return {"min_m1"};
  return {};
}

Status CylinderProblem::monitors(const Vector& u, std::vector<double>& values) {
  values.clear();
  if (!options_.fluid.viscoelastic()) return {};
  values = {flow_->conformation_extremes(u).min_m1};  // on its own: not the drag's surface integrals
  return {};
}

SolutionFields CylinderProblem::fields(const Vector& u) const {
  SolutionFields f = extract_fields(mesh_, *dofs_, u);
  flow_->add_fields(u, f);
  return f;
}

std::string CylinderProblem::summary() const {
  const FluidOptions& f = options_.fluid;
  return fmt::format("confined cylinder (blockage 0.5), {}; mesh {}: {} elements, {} nodes; {} unknowns", f.describe(),
                     options_.mesh.name, mesh_.num_elements(), mesh_.num_nodes(), size());
}

}  // namespace keller
