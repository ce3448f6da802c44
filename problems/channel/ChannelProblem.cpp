#include "problems/channel/ChannelProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <stdexcept>

#include "core/KernelTerm.hpp"
#include "problems/components/Composition.hpp"

namespace keller {

void ChannelOptions::declare(SceneSchema& s) {
  declare_channel_mesh_keys(s);
  // blood (model.md): beta = eta_s / (eta_s + eta_p0) = 0.001 / 0.198
  FluidOptions::declare(s, OwensParameters().beta(), 0.1);
  s.real("parameters.Gamma", 4.95e-4, "Gamma = eta0 U0 / (G W): the mean inflow velocity in these units",
         Range::positive());
}

ChannelOptions ChannelOptions::from_scene(const Scene& scene) {
  ChannelOptions o;
  o.geometry = channel_geometry_from(scene);
  o.mesh = channel_mesh_spec_from(scene);
  o.fluid = FluidOptions::from_scene(scene);
  o.Gamma = scene.real("parameters.Gamma");
  return o;
}

ChannelProblem::ChannelProblem(const ChannelOptions& options)
    : ChannelProblem(options, build_channel_mesh(options.geometry, options.mesh, false)) {}

ChannelProblem::ChannelProblem(const ChannelOptions& options, Mesh mesh) : options_(options), mesh_(std::move(mesh)) {
  setup();
}

void ChannelProblem::setup() {
  iGamma_ =
      params_.add("Gamma", options_.Gamma, "mean inflow velocity (solid elasticity parameter)", Range::positive());
  FlowBoundaries bc;
  bc.inflows = {{"inflow"}};
  bc.outflows = {{"outflow"}};
  bc.walls = {"bottom_wall", "top_wall", "interface"};
  flow_ = std::make_unique<FlowEquations>(mesh_, "fluid", options_.fluid, bc, params_, iGamma_);
  ComposedSystem system = Composition().add(*flow_).build(mesh_, params_);
  dofs_ = std::move(system.dofs);
  dirichlet_ = system.dirichlet;
  assemble(dofs_->size(), system.terms());
  locator_ = std::make_unique<PointLocator>(mesh_, mesh_.group_index("fluid"));
  declare_quantities();
}

double ChannelProblem::residual_scale() const { return params_.value(iGamma_); }

Vector ChannelProblem::initial_guess() {
  // the fully developed inflow state everywhere, zero pressure
  Vector u = Vector::Zero(size());
  flow_->initial_guess(u);
  for (int k = 0; k < dirichlet_->num_items(); ++k) u[dirichlet_->dofs()[k]] = dirichlet_->value(k);
  return u;
}

double ChannelProblem::pressure_at(const Vector& u, const MeshPoint& p) const {
  const int fp = dofs_->field_index("pressure");
  const auto& el = mesh_.element(p.element);
  double N[9], dN[9][2];
  ref::q2_shape(p.s, p.t, N, dN);
  double x = 0, y = 0;
  for (int a = 0; a < 9; ++a) {
    x += N[a] * mesh_.node(el[a])[0];
    y += N[a] * mesh_.node(el[a])[1];
  }
  const auto& c = mesh_.node(el[4]);
  return u[dofs_->element_dof(fp, p.element, 0, 0)] + u[dofs_->element_dof(fp, p.element, 1, 0)] * (x - c[0]) +
         u[dofs_->element_dof(fp, p.element, 2, 0)] * (y - c[1]);
}

double ChannelProblem::section_pressure(const Vector& u, double x0) const {
  // 3-point Gauss on each of 4 ny uniform sub-intervals of [0, 1]
  const int m = 4 * options_.mesh.ny_fluid;
  const double g = std::sqrt(0.6), gp[3] = {-g, 0.0, g}, gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  double sum = 0;
  for (int k = 0; k < m; ++k) {
    for (int q = 0; q < 3; ++q) {
      const double y = (k + 0.5 * (1 + gp[q])) / m;
      const auto found = locator_->locate_all(x0, y);
      if (found.empty()) throw std::logic_error(fmt::format("channel: point ({}, {}) outside the fluid", x0, y));
      double p = 0;
      for (const MeshPoint& mp : found) p += pressure_at(u, mp);
      sum += 0.5 * gw[q] / m * p / static_cast<double>(found.size());
    }
  }
  return sum;
}

std::vector<double> ChannelProblem::column_flow_rates(const Vector& u) const {
  const int fv = dofs_->field_index("velocity");
  std::vector<double> out;
  auto line_flow = [&](const MeshBlock& b, int i) {
    double q = 0;
    for (int j = 0; j < b.ny; ++j) {
      const bool right = i == b.nx;
      const int e = b.element(right ? b.nx - 1 : i, j), edge = right ? 1 : 3;
      double xy[9][2];
      mesh_.element_nodes(e, xy);
      std::array<EdgeQpGeometry<double>, ref::kEdgeQp> eg;
      map_edge(xy, edge, eg);
      int vd[18];
      dofs_->element_dofs(fv, e, vd);
      for (int k = 0; k < ref::kEdgeQp; ++k) {
        double vx = 0, vy = 0;
        for (int a = 0; a < 9; ++a) {
          vx += ref::tables().edge_N2[edge][k][a] * u[vd[a]];
          vy += ref::tables().edge_N2[edge][k][a] * u[vd[9 + a]];
        }
        // outward normal of a right edge points downstream, of a left edge upstream
        q += (right ? 1.0 : -1.0) * (vx * eg[k].normal[0] + vy * eg[k].normal[1]) * eg[k].wds;
      }
    }
    return q;
  };
  const char* blocks[] = {"upstream", "deformable", "downstream"};
  for (int bi = 0; bi < 3; ++bi) {
    const MeshBlock& b = mesh_.block(blocks[bi]);
    for (int i = bi == 0 ? 0 : 1; i <= b.nx; ++i) out.push_back(line_flow(b, i));
  }
  return out;
}

void ChannelProblem::declare_quantities() {
  Quantities& o = observables_;
  o.add("dP", [this](const Vector& u) {
    const double Lu = options_.geometry.upstream_length, L = options_.geometry.deformable_length;
    return section_pressure(u, Lu) - section_pressure(u, Lu + L);
  });
  o.add("Q_in", [this](const Vector& u) { return column_flow_rates(u).front(); });
  o.add("Q_out", [this](const Vector& u) { return column_flow_rates(u).back(); });
  o.add("vx_max", [this](const Vector& u) {
    const int fv = dofs_->field_index("velocity");
    double vmax = -INFINITY;
    for (int n = 0; n < mesh_.num_nodes(); ++n) {
      const int d = dofs_->node_dof(fv, n, 0);
      if (d >= 0) vmax = std::max(vmax, u[d]);
    }
    return vmax;
  });
  if (!options_.fluid.viscoelastic()) return;
  const auto min_m1 = [this](const Vector& u) { return flow_->conformation_extremes(u).min_m1; };
  o.add("min_m1", min_m1);
  o.add("max_m3", [this](const Vector& u) { return flow_->conformation_extremes(u).max_m3; });
  monitors_.add("min_m1", min_m1);
}

Status ChannelProblem::observables(const Vector& u, std::vector<double>& values) {
  observables_.evaluate(u, values);
  return {};
}

Status ChannelProblem::monitors(const Vector& u, std::vector<double>& values) {
  monitors_.evaluate(u, values);
  return {};
}

SolutionFields ChannelProblem::fields(const Vector& u) const {
  SolutionFields f = extract_fields(mesh_, *dofs_, u);
  flow_->add_fields(u, f);
  return f;
}

std::string ChannelProblem::summary() const {
  const FluidOptions& f = options_.fluid;
  return fmt::format("channel, {}, rigid walls, {}; mesh {}: {} elements, {} nodes; {}, {} unknowns", f.describe(),
                     f.inertia ? "Navier-Stokes" : "Stokes", options_.mesh.name, mesh_.num_elements(),
                     mesh_.num_nodes(), f.viscoelastic() ? "Q2-P1disc-Q1-Q1 DEVSS-TG/SUPG" : "Q2-P1disc", size());
}

}  // namespace keller
