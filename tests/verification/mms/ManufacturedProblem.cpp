#include "ManufacturedProblem.hpp"

#include <cmath>
#include <stdexcept>

#include "core/BlockMeshBuilder.hpp"
#include "core/KernelTerm.hpp"
#include "problems/kernels/NewtonianFlowKernel.hpp"
#include "problems/laws/LawKeys.hpp"

namespace keller::mms {

namespace {

void apply(SquareMap map, double s, double t, double& x, double& y) {
  if (map == SquareMap::Distorted)
    distorted_square(s, t, x, y);
  else
    collapsed_square(s, t, x, y);
}

Mesh square_mesh(int n, SquareMap map, bool moving) {
  BlockMeshBuilder builder;
  BlockSpec b;
  b.name = "square";
  b.group = "fluid";
  b.nx = b.ny = n;
  // the moving forms take the unit square as their reference and the motion maps it
  b.map = [map, moving](double s, double t) {
    Mesh::Point p{s, t};
    if (!moving) apply(map, s, t, p[0], p[1]);
    return p;
  };
  b.side_names = {"bottom", "right", "top", "left"};
  builder.add_block(b);
  return builder.build();
}

// 5-point Gauss-Legendre rule on [-1, 1] (exact to degree 9).
constexpr double kGaussPoint[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831,
                                   0.9061798459386640};
constexpr double kGaussWeight[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                                    0.2369268850561891};

template <int NC, bool Moving>
std::shared_ptr<const Term> viscoelastic_term(const Mesh& mesh, const DofMap& dofs, const std::vector<int>& elements,
                                              const std::vector<std::array<QpGeometry<double>, ref::kQp>>& geometry,
                                              FlowParameterIndices p, const ViscoelasticKernelOptions& o,
                                              const ParameterSet& params) {
  return std::make_shared<KernelTerm<ViscoelasticFlowKernel<NC, Moving>>>(
      ViscoelasticFlowKernel<NC, Moving>(mesh, dofs, elements, &geometry, p, o), params);
}

}  // namespace

ManufacturedProblem::ManufacturedProblem(const ManufacturedOptions& options)
    : options_(options),
      strong_(options.fluid, ManufacturedFields{}),
      mesh_(square_mesh(options.n, options.map, options.moving)) {
  const FluidSpec& fl = options_.fluid;
  if (fl.dynamic_zz && fl.model != FluidModel::FeneP) throw std::invalid_argument("dynamic M_zz is for FENE-P only");
  const std::string group = "fluid";
  std::vector<FieldSpec> fields = {{"velocity", Basis::Q2, {"vx", "vy"}, {group}},
                                   {"pressure", Basis::P1Disc, {"p"}, {group}}};
  const int nc = fl.conformation_components();
  if (fl.viscoelastic()) {
    fields.push_back({"gradient", Basis::Q1, {"Lxx", "Lxy", "Lyx", "Lyy"}, {group}});
    std::vector<std::string> comps = {"c_xx", "c_xy", "c_yy"};
    if (nc == 4) comps.push_back("c_zz");
    fields.push_back({"conformation", Basis::Q1, comps, {group}});
  }
  if (options_.moving) fields.push_back({"position", Basis::Q2, {"x", "y"}, {group}});
  dofs_ = std::make_unique<DofMap>(mesh_, fields);

  elements_ = mesh_.elements_in_group(mesh_.group_index(group));
  geometry_.resize(elements_.size());
  double area = 0;
  for (size_t k = 0; k < elements_.size(); ++k) {
    double xy[9][2];
    mesh_.element_nodes(elements_[k], xy);
    if (!map_element(xy, geometry_[k])) throw std::logic_error("manufactured mesh: inverted element");
    for (const auto& g : geometry_[k]) area += g.wdetJ;
  }

  FlowParameterIndices idx;
  idx.Gamma = params_.add("Gamma", fl.Gamma, "velocity scale");
  if (fl.Re > 0) idx.Re = params_.add("Re", fl.Re, "Reynolds number");
  if (fl.viscoelastic()) {
    idx.Wi = params_.add("Wi", fl.Wi, "Weissenberg number");
    idx.beta = params_.add("beta", fl.beta, "viscosity ratio");
    idx.law = add_law_parameters(params_, fl.model, fl.log_form, {fl.b, fl.alpha, fl.epsilon, fl.xi});
  }

  auto source = std::make_shared<FlowSource>();
  const StrongForm<ManufacturedFields>* sf = &strong_;
  source->momentum = [sf](const double(&x)[2], double(&f)[2]) { sf->momentum_source(x, f); };
  if (fl.viscoelastic())
    source->constitutive = [sf](const double(&x)[2], double(&s)[4]) { sf->constitutive_source(x, s); };

  std::vector<std::shared_ptr<const Term>> terms;
  if (!fl.viscoelastic()) {
    if (options_.moving)
      terms.push_back(std::make_shared<KernelTerm<NewtonianFlowKernel<true>>>(
          NewtonianFlowKernel<true>(mesh_, *dofs_, elements_, &geometry_, idx, fl.Re > 0, source), params_));
    else
      terms.push_back(std::make_shared<KernelTerm<NewtonianFlowKernel<false>>>(
          NewtonianFlowKernel<false>(mesh_, *dofs_, elements_, &geometry_, idx, fl.Re > 0, source), params_));
  } else {
    ViscoelasticKernelOptions ko = options_.kernel;
    ko.model = fl.model;
    ko.log_conformation = fl.log_form;
    ko.inertia = fl.Re > 0;
    ko.owens = fl.owens;
    ko.supg.global_size = std::sqrt(area / static_cast<double>(elements_.size()));
    ko.source = source;
    const Mesh& m = mesh_;
    const DofMap& d = *dofs_;
    if (nc == 3)
      terms.push_back(options_.moving ? viscoelastic_term<3, true>(m, d, elements_, geometry_, idx, ko, params_)
                                      : viscoelastic_term<3, false>(m, d, elements_, geometry_, idx, ko, params_));
    else
      terms.push_back(options_.moving ? viscoelastic_term<4, true>(m, d, elements_, geometry_, idx, ko, params_)
                                      : viscoelastic_term<4, false>(m, d, elements_, geometry_, idx, ko, params_));
  }

  // boundary data from the exact solution
  dirichlet_ = std::make_shared<DirichletTerm>("exact", params_);
  const int fv = dofs_->field_index("velocity");
  std::vector<char> velocity_done(mesh_.num_nodes(), 0), conformation_done(mesh_.num_nodes(), 0);
  for (const std::string& side : mesh_.boundary_names()) {
    for (const BoundaryEdge& be : mesh_.boundary(side)) {
      const auto& el = mesh_.element(be.element);
      double xy[9][2];
      for (int a = 0; a < 9; ++a) {
        const Mesh::Point p = position(el[a]);
        xy[a][0] = p[0];
        xy[a][1] = p[1];
      }
      for (int a : ref::edge_nodes[be.edge]) {
        const int node = el[a];
        if (velocity_done[node]) continue;
        velocity_done[node] = 1;
        double v[2], P, L[4], c[4];
        const Mesh::Point p = position(node);
        exact({p[0], p[1]}, v, P, L, c);
        for (int i = 0; i < 2; ++i) dirichlet_->add(dofs_->node_dof(fv, node, i), v[i]);
      }
      if (!fl.viscoelastic()) continue;
      // inflow edge: v . n < 0 at the middle edge Gauss point (the midpoint)
      std::array<EdgeQpGeometry<double>, ref::kEdgeQp> eg;
      map_edge(xy, be.edge, eg);
      double v[2], P, L[4], c[4];
      exact({eg[1].x[0], eg[1].x[1]}, v, P, L, c);
      if (v[0] * eg[1].normal[0] + v[1] * eg[1].normal[1] >= 0.0) continue;
      const int fm = dofs_->field_index("conformation");
      for (int a : {ref::edge_nodes[be.edge][0], ref::edge_nodes[be.edge][2]}) {
        const int node = el[a];
        if (conformation_done[node]) continue;
        conformation_done[node] = 1;
        const Mesh::Point p = position(node);
        exact({p[0], p[1]}, v, P, L, c);
        for (int k = 0; k < nc; ++k) dirichlet_->add(dofs_->node_dof(fm, node, k), c[k]);
      }
    }
  }
  {
    const int fp = dofs_->field_index("pressure");
    const Mesh::Point p = position(mesh_.element(elements_[0])[4]);
    double v[2], P, L[4], c[4];
    exact({p[0], p[1]}, v, P, L, c);
    dirichlet_->add(dofs_->element_dof(fp, elements_[0], 0, 0), P);
  }
  if (options_.moving) {
    const int fx = dofs_->field_index("position");
    for (int n = 0; n < mesh_.num_nodes(); ++n) {
      const Mesh::Point p = position(n);
      for (int i = 0; i < 2; ++i) dirichlet_->add(dofs_->node_dof(fx, n, i), p[i]);
    }
  }
  terms.push_back(dirichlet_);
  assemble(dofs_->size(), terms);
}

Mesh::Point ManufacturedProblem::position(int n) const {
  Mesh::Point p = mesh_.node(n);
  if (options_.moving) apply(options_.map, mesh_.node(n)[0], mesh_.node(n)[1], p[0], p[1]);
  return p;
}

void ManufacturedProblem::exact(const double (&x)[2], double (&v)[2], double& P, double (&L)[4], double (&c)[4]) const {
  double K[2][2];
  strong_.velocity_gradient(x, v, K);
  P = strong_.fields().pressure(x);
  // L = K - (div v / 2) I = K: the velocity is solenoidal
  L[0] = K[0][0];
  L[1] = K[0][1];
  L[2] = K[1][0];
  L[3] = K[1][1];
  if (options_.fluid.log_form)
    strong_.fields().log_conformation(x, c);
  else
    strong_.fields().conformation(x, c);
}

Vector ManufacturedProblem::initial_guess() {
  Vector u = Vector::Zero(size());
  const DofMap& d = *dofs_;
  const bool ve = options_.fluid.viscoelastic();
  const int fv = d.field_index("velocity"), fp = d.field_index("pressure");
  const int fl = ve ? d.field_index("gradient") : -1, fm = ve ? d.field_index("conformation") : -1;
  const int fx = options_.moving ? d.field_index("position") : -1;
  const int nc = options_.fluid.conformation_components();
  for (int n = 0; n < mesh_.num_nodes(); ++n) {
    const Mesh::Point p = position(n);
    double v[2], P, L[4], c[4];
    exact({p[0], p[1]}, v, P, L, c);
    for (int i = 0; i < 2; ++i) u[d.node_dof(fv, n, i)] = v[i];
    if (fx >= 0)
      for (int i = 0; i < 2; ++i) u[d.node_dof(fx, n, i)] = p[i];
    if (!ve || d.node_dof(fm, n, 0) < 0) continue;
    for (int k = 0; k < 4; ++k) u[d.node_dof(fl, n, k)] = L[k];
    for (int k = 0; k < nc; ++k) u[d.node_dof(fm, n, k)] = c[k];
  }
  for (int e : elements_) {
    const Mesh::Point p = position(mesh_.element(e)[4]);
    using D = Grad<double>;
    const D xd[2] = {D(p[0], 2, 0), D(p[1], 2, 1)};
    const D P = strong_.fields().pressure(xd);
    u[d.element_dof(fp, e, 0, 0)] = P.value();
    u[d.element_dof(fp, e, 1, 0)] = P.derivatives()(0);
    u[d.element_dof(fp, e, 2, 0)] = P.derivatives()(1);
  }
  return u;
}

Errors ManufacturedProblem::errors(const Vector& u) const {
  const DofMap& d = *dofs_;
  const bool ve = options_.fluid.viscoelastic();
  const int fv = d.field_index("velocity"), fp = d.field_index("pressure");
  const int fl = ve ? d.field_index("gradient") : -1, fm = ve ? d.field_index("conformation") : -1;
  const int nc = options_.fluid.conformation_components();
  // per field: integral of |e|^2 and |u|^2, max |e| and |u|
  double e2[4] = {0, 0, 0, 0}, u2[4] = {0, 0, 0, 0}, emax[4] = {0, 0, 0, 0}, umax[4] = {0, 0, 0, 0};
  for (int e : elements_) {
    const auto& el = mesh_.element(e);
    double xy[9][2];
    for (int a = 0; a < 9; ++a) {
      const Mesh::Point p = position(el[a]);
      xy[a][0] = p[0];
      xy[a][1] = p[1];
    }
    int vd[18], ld[16], md[16];
    d.element_dofs(fv, e, vd);
    if (ve) {
      d.element_dofs(fl, e, ld);
      d.element_dofs(fm, e, md);
    }
    const double pc[3] = {u[d.element_dof(fp, e, 0, 0)], u[d.element_dof(fp, e, 1, 0)], u[d.element_dof(fp, e, 2, 0)]};
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j) {
        double N2[9], dN2[9][2], N1[4], dN1[4][2];
        ref::q2_shape(kGaussPoint[i], kGaussPoint[j], N2, dN2);
        ref::q1_shape(kGaussPoint[i], kGaussPoint[j], N1, dN1);
        double x[2] = {0, 0}, J[2][2] = {{0, 0}, {0, 0}};
        for (int a = 0; a < 9; ++a)
          for (int r = 0; r < 2; ++r) {
            x[r] += N2[a] * xy[a][r];
            for (int s = 0; s < 2; ++s) J[r][s] += dN2[a][s] * xy[a][r];
          }
        const double w = kGaussWeight[i] * kGaussWeight[j] * (J[0][0] * J[1][1] - J[0][1] * J[1][0]);
        double v[2], P, L[4], c[4];
        exact(x, v, P, L, c);
        double vh[2] = {0, 0}, Lh[4] = {0, 0, 0, 0}, ch[4] = {0, 0, 0, 0};
        for (int a = 0; a < 9; ++a)
          for (int r = 0; r < 2; ++r) vh[r] += N2[a] * u[vd[9 * r + a]];
        if (ve)
          for (int k = 0; k < 4; ++k) {
            for (int r = 0; r < 4; ++r) Lh[r] += N1[k] * u[ld[4 * r + k]];
            for (int r = 0; r < nc; ++r) ch[r] += N1[k] * u[md[4 * r + k]];
          }
        const double Ph = pc[0] + pc[1] * (x[0] - xy[4][0]) + pc[2] * (x[1] - xy[4][1]);
        double ce = 0, cu = 0;
        for (int r = 0; r < nc; ++r) {
          // the off-diagonal component stands for two entries of the tensor
          const double weight = r == 1 ? 2.0 : 1.0;
          ce += weight * std::pow(ch[r] - c[r], 2);
          cu += weight * c[r] * c[r];
        }
        double le = 0, lu = 0;
        for (int r = 0; r < 4; ++r) {
          le += std::pow(Lh[r] - L[r], 2);
          lu += L[r] * L[r];
        }
        const double err[4] = {std::hypot(vh[0] - v[0], vh[1] - v[1]), std::abs(Ph - P), std::sqrt(le), std::sqrt(ce)};
        const double val[4] = {std::hypot(v[0], v[1]), std::abs(P), std::sqrt(lu), std::sqrt(cu)};
        for (int f = 0; f < 4; ++f) {
          e2[f] += w * err[f] * err[f];
          u2[f] += w * val[f] * val[f];
          emax[f] = std::max(emax[f], err[f]);
          umax[f] = std::max(umax[f], val[f]);
        }
      }
  }
  FieldError out[4];
  for (int f = 0; f < 4; ++f) {
    out[f].l2 = u2[f] > 0 ? std::sqrt(e2[f] / u2[f]) : 0.0;
    out[f].max = umax[f] > 0 ? emax[f] / umax[f] : 0.0;
  }
  return {out[0], out[1], out[2], out[3]};
}

}  // namespace keller::mms
