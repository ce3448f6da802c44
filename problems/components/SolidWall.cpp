#include "problems/components/SolidWall.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include "core/ElementGeometry.hpp"
#include "core/KernelTerm.hpp"
#include "core/RateConstraintTerm.hpp"
#include "problems/kernels/FollowerPressureKernel.hpp"
#include "problems/kernels/NeoHookeanSolidKernel.hpp"
#include "problems/kernels/SolidInertiaTerm.hpp"

namespace keller {

SolidWall::SolidWall(const Mesh& mesh, WallGeometry geometry, double t0, double Pe, ParameterSet& params)
    : mesh_(&mesh), geometry_(geometry), params_(&params) {
  if (!(t0 > 0.0)) throw std::invalid_argument(fmt::format("wall thickness t must be > 0 (got {})", t0));
  it_ = params.add("t", t0, "wall thickness (units of the channel width)", min_thickness, max_thickness);
  iPe_ = params.add("Pe", Pe, "external pressure on the top of the wall (units of G)");
  elements_ = mesh.elements_in_group(mesh.group_index("solid"));
  // X = (X, 1) + t (0, eta): the mesh was built with thickness t0 and straight vertical lines
  reference_.parameter = it_;
  reference_.base.assign(mesh.num_nodes(), {0.0, 0.0});
  reference_.slope.assign(mesh.num_nodes(), {0.0, 0.0});
  std::set<int> solid_nodes;
  for (int e : elements_)
    for (int n : mesh.element(e)) solid_nodes.insert(n);
  for (int n : solid_nodes) {
    const auto& p = mesh.node(n);
    reference_.base[n] = {p[0], geometry.y_bottom};
    reference_.slope[n] = {0.0, (p[1] - geometry.y_bottom) / t0};
  }
  interface_nodes_ = mesh.boundary_nodes("interface");
  std::sort(interface_nodes_.begin(), interface_nodes_.end(),
            [&](int a, int b) { return mesh.node(a)[0] < mesh.node(b)[0]; });
}

std::vector<FieldSpec> SolidWall::fields() const {
  std::vector<FieldSpec> f = {{"solid_pressure", Basis::P1Disc, {"pi"}, {"solid"}}};
  if (density_) f.push_back({"wall_velocity", Basis::Q2, {"wx", "wy"}, {"solid"}});
  return f;
}

std::vector<int> SolidWall::position_nodes() const {
  std::set<int> nodes;
  for (int e : elements_)
    for (int n : mesh_->element(e)) nodes.insert(n);
  return {nodes.begin(), nodes.end()};
}

void SolidWall::build(const ComponentBuild& b) {
  const DofMap& dofs = b.dofs;
  DirichletTerm& dirichlet = b.dirichlet;
  dofs_ = &dofs;
  const ParameterSet& params = *params_;
  terms_.push_back(std::make_shared<KernelTerm<NeoHookeanSolidKernel>>(
      NeoHookeanSolidKernel(*mesh_, dofs, elements_, &reference_), params));
  terms_.push_back(std::make_shared<KernelTerm<FollowerPressureKernel>>(
      FollowerPressureKernel(*mesh_, dofs, mesh_->boundary("wall_top"), iPe_), params));
  const int fx = dofs.field_index("position");
  if (density_) {
    terms_.push_back(std::make_shared<SolidInertiaTerm>(*mesh_, dofs, elements_, &reference_, params, density_));
    // w = dx/dt at every node of the solid (w = 0 where the sides are clamped)
    auto kinematics = std::make_shared<RateConstraintTerm>("wall kinematics");
    const int fw = dofs.field_index("wall_velocity");
    for (int n : position_nodes())
      for (int c = 0; c < 2; ++c) kinematics->add(dofs.node_dof(fw, n, c), dofs.node_dof(fx, n, c));
    terms_.push_back(kinematics);
  }
  std::set<int> clamped;
  for (const char* side : {"wall_left", "wall_right"})
    for (int n : mesh_->boundary_nodes(side)) clamped.insert(n);
  for (int n : clamped) {
    const auto base = reference_.base[n], slope = reference_.slope[n];
    const int it = it_;
    dirichlet.add(dofs.node_dof(fx, n, 0), base[0]);
    dirichlet.add(dofs.node_dof(fx, n, 1),
                  [base, slope, it](const ParameterSet& p) { return base[1] + p.value(it) * slope[1]; });
  }
}

void SolidWall::reference_state(Vector& u) const {
  const int fx = dofs_->field_index("position");
  for (int e : elements_)
    for (int n : mesh_->element(e)) {
      const auto X = reference_.at(n, params_->values());
      u[dofs_->node_dof(fx, n, 0)] = X[0];
      u[dofs_->node_dof(fx, n, 1)] = X[1];
    }
}

namespace {

// Deformed node positions of element e from the position field.
void deformed_nodes(const Mesh& mesh, const DofMap& dofs, int e, const Vector& u, double (&xy)[9][2]) {
  const int fx = dofs.field_index("position");
  const auto& el = mesh.element(e);
  for (int a = 0; a < 9; ++a)
    for (int i = 0; i < 2; ++i) xy[a][i] = u[dofs.node_dof(fx, el[a], i)];
}

}  // namespace

double SolidWall::area(const Vector& u) const {
  // int J dA0 = the deformed area; the Gauss rule is exact for det of a Q2 map
  double sum = 0;
  for (int e : elements_) {
    double xy[9][2];
    deformed_nodes(*mesh_, *dofs_, e, u, xy);
    const ref::Tables& tb = ref::tables();
    for (int q = 0; q < ref::kQp; ++q) {
      double J[2][2] = {{0, 0}, {0, 0}};
      for (int a = 0; a < 9; ++a)
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j) J[i][j] += xy[a][i] * tb.dN2[q][a][j];
      sum += tb.w[q] * (J[0][0] * J[1][1] - J[0][1] * J[1][0]);
    }
  }
  return sum;
}

double SolidWall::reference_area() const { return (geometry_.x_right - geometry_.x_left) * params_->value(it_); }

std::vector<std::array<double, 2>> SolidWall::interface_shape(const Vector& u) const {
  const int fx = dofs_->field_index("position");
  std::vector<std::array<double, 2>> out;
  for (int n : interface_nodes_) out.push_back({u[dofs_->node_dof(fx, n, 0)], u[dofs_->node_dof(fx, n, 1)]});
  return out;
}

std::array<double, 2> SolidWall::max_deflection(const Vector& u) const {
  const auto shape = interface_shape(u);
  const double y0 = geometry_.y_bottom, xc = 0.5 * (geometry_.x_left + geometry_.x_right);
  size_t k = 0;
  for (size_t i = 1; i < shape.size(); ++i)
    if (std::abs(shape[i][1] - y0) > std::abs(shape[k][1] - y0)) k = i;
  if (std::abs(shape[k][1] - y0) < 1e-12) return {0.0, 0.0};  // flat: no deflection to locate
  double x = shape[k][0], y = shape[k][1];
  if (k > 0 && k + 1 < shape.size()) {
    // extremum of the parabola through the node and its neighbours, parametrised by node index
    const double ya = shape[k - 1][1], yb = shape[k][1], yc = shape[k + 1][1];
    const double c = ya - 2 * yb + yc;
    if (std::abs(c) > 0) {
      const double s = std::clamp(0.5 * (ya - yc) / c, -0.5, 0.5);
      auto lag = [&](int j) { return ref::lagrange2(j, s); };
      x = lag(0) * shape[k - 1][0] + lag(1) * shape[k][0] + lag(2) * shape[k + 1][0];
      y = lag(0) * ya + lag(1) * yb + lag(2) * yc;
    }
  }
  return {x - xc, y - y0};
}

double SolidWall::min_jacobian(const Vector& u) const {
  double m = INFINITY;
  for (int e : elements_) {
    double xy[9][2], X[9][2];
    deformed_nodes(*mesh_, *dofs_, e, u, xy);
    reference_.element(*mesh_, e, params_->values(), X);
    std::array<QpGeometry<double>, ref::kQp> gx, gX;
    const bool ok_ref = map_element(X, gX);
    if (!ok_ref || !map_element(xy, gx)) return ok_ref ? -1.0 : NAN;
    for (int q = 0; q < ref::kQp; ++q) m = std::min(m, gx[q].detJ / gX[q].detJ);
  }
  return m;
}

}  // namespace keller
