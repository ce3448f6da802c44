// A finite-element problem of your own: the Brusselator reaction-diffusion system on the square
// (0, L)^2 with no-flux walls,
//   du/dt = Du Laplace(u) + a - (b + 1) u + u^2 v,   dv/dt = Dv Laplace(v) + b u - u^2 v,
// with Q2 elements on an n x n mesh (weak form, an exact Jacobian by automatic differentiation)
// from keller's finite-element pieces: BlockMeshBuilder, DofMap, a kernel term and
// AssembledProblem, which assembles F, J, dF/dp and the mass matrix from it. The homogeneous state
// (a, b / a) loses stability to Turing patterns cos(m pi x / L) cos(n pi y / L) where
//   b = (1 + Du k^2) (a^2 + Dv k^2) / (Dv k^2),  k^2 = the Laplacian's eigenvalue of the mode
// (pi^2 (m^2 + n^2) / L^2 in the continuum; on the mesh the generalised eigenvalue of the Q2
// stiffness and mass matrices, a sum of two 1D ones).
//
// The program registers the problem type "brusselator2d" and hands over to keller's command line.
#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <vector>

#include <fmt/format.h>

#include "core/AssembledProblem.hpp"
#include "core/BlockMeshBuilder.hpp"
#include "core/DofMap.hpp"
#include "core/ElementGeometry.hpp"
#include "core/KernelTerm.hpp"
#include "core/ReferenceElement.hpp"
#include "core/Scene.hpp"
#include "core/SolutionFields.hpp"
#include "problems/ProblemRegistry.hpp"
#include "runs/CommandLine.hpp"

namespace {

using Geometry = std::vector<std::array<keller::QpGeometry<double>, keller::ref::kQp>>;

// One element's residual: u at its 9 nodes, then v (the field's components, component-major).
// Parameters by index: b 0, a 1; the diffusivities are constants.
class BrusselatorKernel {
 public:
  static constexpr int kSize = 18;
  BrusselatorKernel(const keller::DofMap& dofs, const Geometry* geometry, double Du, double Dv)
      : geometry_(geometry), Du_(Du), Dv_(Dv) {
    dofs_.resize(geometry->size() * kSize);
    for (size_t e = 0; e < geometry->size(); ++e) dofs.element_dofs(0, static_cast<int>(e), &dofs_[e * kSize]);
  }
  std::string name() const { return "brusselator"; }
  int num_items() const { return static_cast<int>(geometry_->size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  // F: int D grad phi . grad c - phi R(c), so that M dc/dt = -F
  template <class T, class P>
  keller::Status evaluate(int item, const T* c, const P* params, T* r) const {
    const keller::ref::Tables& tb = keller::ref::tables();
    const P b = params[0], a = params[1];
    std::fill(r, r + kSize, T(0.0));
    for (int q = 0; q < keller::ref::kQp; ++q) {
      const keller::QpGeometry<double>& g = (*geometry_)[item][q];
      T u = 0.0, v = 0.0, ux = 0.0, uy = 0.0, vx = 0.0, vy = 0.0;
      for (int k = 0; k < 9; ++k) {
        u += tb.N2[q][k] * c[k];
        v += tb.N2[q][k] * c[9 + k];
        ux += g.dN2dx[k][0] * c[k];
        uy += g.dN2dx[k][1] * c[k];
        vx += g.dN2dx[k][0] * c[9 + k];
        vy += g.dN2dx[k][1] * c[9 + k];
      }
      const T Ru = a - (b + 1.0) * u + u * u * v, Rv = b * u - u * u * v;
      for (int k = 0; k < 9; ++k) {
        const double N = tb.N2[q][k], dx = g.dN2dx[k][0], dy = g.dN2dx[k][1];
        r[k] += g.wdetJ * (Du_ * (dx * ux + dy * uy) - N * Ru);
        r[9 + k] += g.wdetJ * (Dv_ * (dx * vx + dy * vy) - N * Rv);
      }
    }
    return {};
  }

  // B of B dc/dt = -F: the Q2 mass matrix of each component
  keller::Status mass(int item, const double*, const double*, double* B) const {
    const keller::ref::Tables& tb = keller::ref::tables();
    std::fill(B, B + kSize * kSize, 0.0);
    for (int q = 0; q < keller::ref::kQp; ++q)
      for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) {
          const double m = (*geometry_)[item][q].wdetJ * tb.N2[q][i] * tb.N2[q][j];
          B[i * kSize + j] += m;
          B[(9 + i) * kSize + 9 + j] += m;
        }
    return {};
  }

 private:
  const Geometry* geometry_;
  std::vector<int> dofs_;
  double Du_, Dv_;
};

class Brusselator2D final : public keller::AssembledProblem {
 public:
  Brusselator2D(int n, double L, double Du, double Dv, double b, double a, double perturbation)
      : n_(n), L_(L), perturbation_(perturbation) {
    keller::BlockMeshBuilder builder;
    builder.add_block({"square",
                       "domain",
                       n,
                       n,
                       keller::Grading::uniform(),
                       keller::Grading::uniform(),
                       [L](double s, double t) {
                         return keller::Mesh::Point{L * s, L * t};
                       },
                       {"wall", "wall", "wall", "wall"}});
    mesh_ = builder.build();
    params_.add("b", b, "Brusselator b (Turing patterns above the homogeneous state's first b_k)");
    params_.add("a", a, "Brusselator a (the homogeneous state is u = a, v = b / a)");
    dofs_ = std::make_unique<keller::DofMap>(mesh_,
                                             std::vector<keller::FieldSpec>{{"c", keller::Basis::Q2, {"u", "v"}, {}}});
    geometry_.resize(mesh_.num_elements());
    for (int e = 0; e < mesh_.num_elements(); ++e) {
      double xy[9][2];
      mesh_.element_nodes(e, xy);
      keller::map_element(xy, geometry_[e]);
    }
    // no-flux walls are the weak form's natural condition: no boundary term, no Dirichlet rows
    assemble(dofs_->size(), {std::make_shared<keller::KernelTerm<BrusselatorKernel>>(
                                BrusselatorKernel(*dofs_, &geometry_, Du, Dv), params_)});
  }

  std::string name() const override { return "brusselator2d"; }
  // the homogeneous state, plus perturbation cos(2 pi x / L) cos(2 pi y / L) in u (a Newton start away
  // from it: toward a pattern where there is one)
  keller::Vector initial_guess() override {
    keller::Vector c(size());
    const double b = params_.value(0), a = params_.value(1);
    for (int node = 0; node < mesh_.num_nodes(); ++node) {
      const auto& x = mesh_.node(node);
      c[dofs_->node_dof(0, node, 0)] =
          a + perturbation_ * std::cos(2 * M_PI * x[0] / L_) * std::cos(2 * M_PI * x[1] / L_);
      c[dofs_->node_dof(0, node, 1)] = b / a;
    }
    return c;
  }
  // u - a at the corner (0, 0) and at the middle of the bottom wall (L / 2, 0): zero on the
  // homogeneous branch; a pattern cos(m pi x / L) ... has their ratio (-1)^m
  std::vector<std::string> observable_names() const override { return {"u_corner", "u_mid_wall", "u_range"}; }
  keller::Status observables(const keller::Vector& c, std::vector<double>& values) override {
    const double a = params_.value(1);
    double lo = INFINITY, hi = -INFINITY;
    for (int node = 0; node < mesh_.num_nodes(); ++node) {
      lo = std::min(lo, c[dofs_->node_dof(0, node, 0)]);
      hi = std::max(hi, c[dofs_->node_dof(0, node, 0)]);
    }
    values = {u_at(c, 0.0, 0.0) - a, u_at(c, L_ / 2, 0.0) - a, hi - lo};
    return {};
  }
  keller::SolutionFields fields(const keller::Vector& c) const override {
    return keller::extract_fields(mesh_, *dofs_, c);
  }
  std::string summary() const override {
    return fmt::format("2D Brusselator, Q2 elements on a {} x {} mesh of (0, {:g})^2, {} unknowns", n_, n_, L_, size());
  }

 private:
  // u at a mesh node at (x, y)
  double u_at(const keller::Vector& c, double x, double y) const {
    for (int node = 0; node < mesh_.num_nodes(); ++node)
      if (std::abs(mesh_.node(node)[0] - x) < 1e-9 * L_ && std::abs(mesh_.node(node)[1] - y) < 1e-9 * L_)
        return c[dofs_->node_dof(0, node, 0)];
    return NAN;
  }

  int n_;
  double L_, perturbation_;
  keller::Mesh mesh_;
  std::unique_ptr<keller::DofMap> dofs_;
  Geometry geometry_;
};

}  // namespace

int main(int argc, char** argv) {
  keller::use_native_blas_kernels(argv);  // OpenBLAS on the CPU's own kernels (runs/CommandLine.hpp)
  keller::ProblemType type;
  type.name = "brusselator2d";
  type.doc = "the Brusselator on a square with no-flux walls, Q2 elements (Turing patterns)";
  type.declare = [](keller::SceneSchema& s) {
    s.section("brusselator2d", "the domain, the mesh and the diffusivities");
    s.real("brusselator2d.length", 10.0, "side L of the square", keller::Range::positive());
    s.integer("brusselator2d.elements", 16, "elements per side (even: the wall's midpoint is a node)",
              keller::Range::between(2, 2000));
    s.real("brusselator2d.Du", 1.0, "diffusivity of u", keller::Range::positive());
    s.real("brusselator2d.Dv", 8.0, "diffusivity of v", keller::Range::positive());
    s.real("brusselator2d.perturbation", 0.0, "amplitude of the pattern (2, 2) added to u's initial guess");
    s.section("parameters", "initial values of the named continuation parameters");
    s.real("parameters.b", 2.8, "Brusselator b");
    s.real("parameters.a", 2.0, "Brusselator a", keller::Range::positive());
  };
  type.build = [](const keller::Scene& s) -> std::unique_ptr<keller::Problem> {
    const int n = s.integer("brusselator2d.elements");
    if (n % 2 != 0) throw s.error("brusselator2d.elements", "must be even (u_mid_wall is a node value)");
    return std::make_unique<Brusselator2D>(n, s.real("brusselator2d.length"), s.real("brusselator2d.Du"),
                                           s.real("brusselator2d.Dv"), s.real("parameters.b"), s.real("parameters.a"),
                                           s.real("brusselator2d.perturbation"));
  };
  keller::register_problem_type(std::move(type));
  return keller::run_command_line(argc, argv);
}
