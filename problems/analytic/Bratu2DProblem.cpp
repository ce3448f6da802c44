#include "problems/analytic/Bratu2DProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>

#include "core/BlockMeshBuilder.hpp"
#include "core/KernelTerm.hpp"

namespace keller {

namespace {

// Residual of one element: r_a = int grad phi_a . grad u - lambda phi_a e^u.
class BratuKernel {
 public:
  static constexpr int kSize = 9;
  BratuKernel(const DofMap& dofs, const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry)
      : geometry_(geometry) {
    const int f = dofs.field_index("u");
    const int ne = dofs.mesh().num_elements();
    dofs_.resize(static_cast<size_t>(ne) * kSize);
    for (int e = 0; e < ne; ++e) dofs.element_dofs(f, e, &dofs_[static_cast<size_t>(e) * kSize]);
  }
  std::string name() const { return "bratu"; }
  int num_items() const { return static_cast<int>(geometry_->size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  // u_t = Laplace(u) + lambda e^u: B is the Q2 mass matrix
  Status mass(int item, const double*, const double*, double* B) const {
    const ref::Tables& tb = ref::tables();
    std::fill(B, B + kSize * kSize, 0.0);
    for (int q = 0; q < ref::kQp; ++q)
      for (int a = 0; a < 9; ++a)
        for (int b = 0; b < 9; ++b) B[a * kSize + b] += (*geometry_)[item][q].wdetJ * tb.N2[q][a] * tb.N2[q][b];
    return {};
  }

  template <class T, class P>
  Status evaluate(int item, const T* u, const P* params, T* r) const {
    using std::exp;
    const ref::Tables& tb = ref::tables();
    const P lambda = params[0];
    for (int a = 0; a < kSize; ++a) r[a] = 0.0;
    for (int q = 0; q < ref::kQp; ++q) {
      const QpGeometry<double>& g = (*geometry_)[item][q];
      T val = 0.0, gx = 0.0, gy = 0.0;
      for (int a = 0; a < 9; ++a) {
        val += tb.N2[q][a] * u[a];
        gx += g.dN2dx[a][0] * u[a];
        gy += g.dN2dx[a][1] * u[a];
      }
      const T source = lambda * exp(val);
      for (int a = 0; a < 9; ++a) r[a] += g.wdetJ * (g.dN2dx[a][0] * gx + g.dN2dx[a][1] * gy - tb.N2[q][a] * source);
    }
    return {};
  }

 private:
  const std::vector<std::array<QpGeometry<double>, ref::kQp>>* geometry_;
  std::vector<int> dofs_;
};

}  // namespace

Bratu2DProblem::Bratu2DProblem(int n, double lambda) : n_(n) {
  if (n < 1) throw std::invalid_argument("bratu2d: need at least one element per side");
  BlockMeshBuilder b;
  b.add_block({"square",
               "domain",
               n,
               n,
               Grading::uniform(),
               Grading::uniform(),
               [](double s, double t) {
                 return Mesh::Point{s, t};
               },
               {"boundary", "boundary", "boundary", "boundary"}});
  mesh_ = b.build();
  params_.add("lambda", lambda, "Bratu parameter");
  dofs_ = std::make_unique<DofMap>(mesh_, std::vector<FieldSpec>{{"u", Basis::Q2, {"u"}, {}}});
  geometry_.resize(mesh_.num_elements());
  for (int e = 0; e < mesh_.num_elements(); ++e) {
    double xy[9][2];
    mesh_.element_nodes(e, xy);
    map_element(xy, geometry_[e]);
  }
  dirichlet_ = std::make_shared<DirichletTerm>("boundary", params_);
  for (int node : mesh_.boundary_nodes("boundary")) dirichlet_->add(dofs_->node_dof(0, node, 0), 0.0);
  auto kernel = std::make_shared<KernelTerm<BratuKernel>>(BratuKernel(*dofs_, &geometry_), params_);
  assemble(dofs_->size(), {kernel, dirichlet_});
}

double Bratu2DProblem::evaluate(const Vector& u, double x, double y) const {
  // uniform mesh: locate the element directly, then the reference point by linear inversion
  const int i = std::min(static_cast<int>(x * n_), n_ - 1), j = std::min(static_cast<int>(y * n_), n_ - 1);
  const int e = mesh_.blocks()[0].element(i, j);
  const double s = 2.0 * (x * n_ - i) - 1.0, t = 2.0 * (y * n_ - j) - 1.0;
  double N[9], dN[9][2];
  ref::q2_shape(s, t, N, dN);
  int d[9];
  dofs_->element_dofs(0, e, d);
  double v = 0.0;
  for (int a = 0; a < 9; ++a) v += N[a] * u[d[a]];
  return v;
}

Status Bratu2DProblem::observables(const Vector& u, std::vector<double>& values) {
  values = {u.maxCoeff(), evaluate(u, 0.5, 0.5)};
  return {};
}

std::string Bratu2DProblem::summary() const {
  return fmt::format("2D Bratu, Q2 elements on a uniform {}x{} mesh, {} unknowns", n_, n_, size());
}

std::unique_ptr<Problem> Bratu2DProblem::from_scene(const Scene& scene) {
  // (2n + 1)^2 unknowns and about 25 Jacobian entries each must stay far inside int
  if (scene.integer("bratu.intervals") > max_elements_per_side)
    throw scene.error("bratu.intervals",
                      fmt::format("bratu2d takes at most {} elements per side", max_elements_per_side));
  return std::make_unique<Bratu2DProblem>(static_cast<int>(scene.integer("bratu.intervals")),
                                          scene.real("bratu.lambda"));
}

}  // namespace keller
