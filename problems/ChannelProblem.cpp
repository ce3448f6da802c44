#include "problems/ChannelProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <stdexcept>

#include "core/KernelTerm.hpp"
#include "problems/NewtonianFlowKernel.hpp"

namespace keller {

void ChannelOptions::declare(SceneSchema& s) {
  declare_channel_mesh_keys(s);
  s.section("fluid", "the fluid and which physics is on");
  s.string("fluid.model", "newtonian", "constitutive law of the fluid", {"newtonian"});
  s.section("inflow", "inflow boundary condition at x = 0");
  s.string("inflow.profile", "parabolic", "fully developed inflow profile v_x(y) of mean Gamma", {"parabolic"});
  s.section("parameters", "initial values of the named continuation parameters");
  s.real("parameters.Re", 0.0, "Reynolds number rho W U0 / eta0 (0: Stokes, the convective term is not assembled)",
         Range::non_negative());
  s.real("parameters.Gamma", 4.95e-4, "Gamma = eta0 U0 / (G W): the mean inflow velocity in these units",
         Range::positive());
}

ChannelOptions ChannelOptions::from_scene(const Scene& scene) {
  ChannelOptions o;
  o.geometry = channel_geometry_from(scene);
  o.mesh = channel_mesh_spec_from(scene);
  o.fluid_model = scene.string("fluid.model");
  o.inflow_profile = scene.string("inflow.profile");
  o.Re = scene.real("parameters.Re");
  o.Gamma = scene.real("parameters.Gamma");
  o.inertia = o.Re > 0.0;
  return o;
}

ChannelProblem::ChannelProblem(const ChannelOptions& options)
    : ChannelProblem(options, build_channel_mesh(options.geometry, options.mesh, false)) {}

ChannelProblem::ChannelProblem(const ChannelOptions& options, Mesh mesh) : options_(options), mesh_(std::move(mesh)) {
  setup();
}

void ChannelProblem::setup() {
  if (options_.fluid_model != "newtonian")
    throw std::invalid_argument("channel: fluid model '" + options_.fluid_model + "' is not available");
  if (options_.Re > 0.0 && !options_.inertia)
    throw std::invalid_argument("channel: Re > 0 needs the convective term (inertia = true)");
  iRe_ = params_.add("Re", options_.Re, "Reynolds number", 0.0);
  iGamma_ = params_.add("Gamma", options_.Gamma, "mean inflow velocity (solid elasticity parameter)",
                        std::numeric_limits<double>::min());

  dofs_ = std::make_unique<DofMap>(mesh_, std::vector<FieldSpec>{
                                              {"velocity", Basis::Q2, {"vx", "vy"}, {"fluid"}},
                                              {"pressure", Basis::P1Disc, {"p"}, {"fluid"}},
                                          });
  fluid_elements_ = mesh_.elements_in_group(mesh_.group_index("fluid"));
  geometry_.resize(fluid_elements_.size());
  for (size_t k = 0; k < fluid_elements_.size(); ++k) {
    double xy[9][2];
    mesh_.element_nodes(fluid_elements_[k], xy);
    if (!map_element(xy, geometry_[k]))
      throw std::invalid_argument(fmt::format("channel: element {} is inverted or degenerate", fluid_elements_[k]));
  }

  // Dirichlet conditions; walls win at corners (both give zero there).
  const int fv = dofs_->field_index("velocity");
  std::map<int, DirichletTerm::ValueFunction> fixed;
  std::map<int, double> zero;
  for (int n : mesh_.boundary_nodes("inflow")) {
    const double y = mesh_.node(n)[1];
    fixed[dofs_->node_dof(fv, n, 0)] = [iG = iGamma_, y](const ParameterSet& p) {
      return 6.0 * p.value(iG) * y * (1.0 - y);
    };
    zero[dofs_->node_dof(fv, n, 1)] = 0.0;
  }
  for (int n : mesh_.boundary_nodes("outflow")) zero[dofs_->node_dof(fv, n, 1)] = 0.0;
  for (const char* wall : {"bottom_wall", "top_wall", "interface"}) {
    for (int n : mesh_.boundary_nodes(wall)) {
      for (int c = 0; c < 2; ++c) {
        fixed.erase(dofs_->node_dof(fv, n, c));
        zero[dofs_->node_dof(fv, n, c)] = 0.0;
      }
    }
  }
  dirichlet_ = std::make_shared<DirichletTerm>("velocity-dirichlet", params_);
  for (auto& [dof, g] : fixed) dirichlet_->add(dof, g);
  for (auto& [dof, v] : zero) dirichlet_->add(dof, v);

  NewtonianFlowParameters np{iRe_, iGamma_, -1};
  auto flow = std::make_shared<KernelTerm<NewtonianFlowKernel>>(
      NewtonianFlowKernel(mesh_, *dofs_, fluid_elements_, &geometry_, np, options_.inertia), params_);
  assembler_ = std::make_unique<Assembler>(dofs_->size(), std::vector<std::shared_ptr<const Term>>{flow, dirichlet_});
  locator_ = std::make_unique<PointLocator>(mesh_, mesh_.group_index("fluid"));
}

double ChannelProblem::inflow_velocity(double y) const {
  const double Gamma = params_.value(iGamma_);
  return 6.0 * Gamma * y * (1.0 - y);
}

Status ChannelProblem::residual(const Vector& u, Vector& F) { return assembler_->residual(u, F); }

Status ChannelProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) { return assembler_->jacobian(u, F, J); }

Status ChannelProblem::parameter_derivative(int p, const Vector& u, Vector& dF) {
  return assembler_->parameter_derivative(p, u, dF);
}

double ChannelProblem::residual_scale() const { return params_.value(iGamma_); }

Vector ChannelProblem::initial_guess() {
  // fully developed velocity everywhere, zero pressure
  Vector u = Vector::Zero(size());
  const int fv = dofs_->field_index("velocity");
  for (int n = 0; n < mesh_.num_nodes(); ++n) {
    const int d = dofs_->node_dof(fv, n, 0);
    if (d >= 0) u[d] = inflow_velocity(mesh_.node(n)[1]);
  }
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

std::vector<std::string> ChannelProblem::observable_names() const { return {"dP", "Q_in", "Q_out", "vx_max"}; }

Status ChannelProblem::observables(const Vector& u, std::vector<double>& values) {
  const int fv = dofs_->field_index("velocity");
  double vmax = -INFINITY;
  for (int n = 0; n < mesh_.num_nodes(); ++n) {
    const int d = dofs_->node_dof(fv, n, 0);
    if (d >= 0) vmax = std::max(vmax, u[d]);
  }
  const double Lu = options_.geometry.upstream_length, L = options_.geometry.deformable_length;
  const std::vector<double> q = column_flow_rates(u);
  values = {section_pressure(u, Lu) - section_pressure(u, Lu + L), q.front(), q.back(), vmax};
  return {};
}

SolutionFields ChannelProblem::fields(const Vector& u) const { return extract_fields(mesh_, *dofs_, u); }

std::string ChannelProblem::summary() const {
  return fmt::format("channel, {} fluid, rigid walls, {}; mesh {}: {} elements, {} nodes; Q2-P1disc, {} unknowns",
                     options_.fluid_model, options_.inertia ? "Navier-Stokes" : "Stokes", options_.mesh.name,
                     mesh_.num_elements(), mesh_.num_nodes(), size());
}

}  // namespace keller
