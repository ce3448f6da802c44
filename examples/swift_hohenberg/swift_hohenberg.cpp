// A fourth-order PDE of your own with keller's finite elements: the Swift-Hohenberg equation
//   du/dt = r u - (1 + Laplace)^2 u + nu u^2 - u^3
// on the rectangle (0, Lx) x (0, Ly) with du/dn = d(Laplace u)/dn = 0 on its walls, as a mixed
// system of second order for u and w = u + Laplace(u) (Q2 elements, both fields natural at the
// walls):
//   int phi du/dt = -int (phi w - grad phi . grad w) + int phi (r u + nu u^2 - u^3),
//   0 = int psi (w - u) + int grad psi . grad u.
// The trivial state u = 0 loses stability to the pattern cos(m pi x / Lx) cos(n pi y / Ly) at
//   r = (1 - k^2)^2,  k^2 = (m pi / Lx)^2 + (n pi / Ly)^2
// (on the mesh: k^2 the generalised eigenvalue of the Q2 stiffness and mass matrices, a sum of two
// 1D ones): stripes (4, 0) at r = 0 and spots (2, 2) at r = 0.0121 for Lx = 4 pi, Ly = 2.5 pi.
//
// The program registers the problem type "swift-hohenberg" and hands over to keller's command line.
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

// One element's residual: u at its 9 nodes, then w. Parameters by index: r 0, nu 1.
class SwiftHohenbergKernel {
 public:
  static constexpr int kSize = 18;
  SwiftHohenbergKernel(const keller::DofMap& dofs, const Geometry* geometry) : geometry_(geometry) {
    dofs_.resize(geometry->size() * kSize);
    for (size_t e = 0; e < geometry->size(); ++e) dofs.element_dofs(0, static_cast<int>(e), &dofs_[e * kSize]);
  }
  std::string name() const { return "swift-hohenberg"; }
  int num_items() const { return static_cast<int>(geometry_->size()); }
  void item_dofs(int item, int* out) const { std::copy_n(&dofs_[static_cast<size_t>(item) * kSize], kSize, out); }

  // F of B dc/dt = -F; T: double or an AD number (the Jacobian), P: double or a parameter's AD number
  template <class T, class P>
  keller::Status evaluate(int item, const T* c, const P* params, T* res) const {
    const keller::ref::Tables& tb = keller::ref::tables();
    const P r = params[0], nu = params[1];
    std::fill(res, res + kSize, T(0.0));
    for (int q = 0; q < keller::ref::kQp; ++q) {
      const keller::QpGeometry<double>& g = (*geometry_)[item][q];
      T u = 0.0, w = 0.0, ux = 0.0, uy = 0.0, wx = 0.0, wy = 0.0;
      for (int k = 0; k < 9; ++k) {
        u += tb.N2[q][k] * c[k];
        w += tb.N2[q][k] * c[9 + k];
        ux += g.dN2dx[k][0] * c[k];
        uy += g.dN2dx[k][1] * c[k];
        wx += g.dN2dx[k][0] * c[9 + k];
        wy += g.dN2dx[k][1] * c[9 + k];
      }
      const T source = r * u + nu * u * u - u * u * u;
      for (int k = 0; k < 9; ++k) {
        const double N = tb.N2[q][k], dx = g.dN2dx[k][0], dy = g.dN2dx[k][1];
        res[k] += g.wdetJ * (N * w - (dx * wx + dy * wy) - N * source);
        res[9 + k] += g.wdetJ * (N * (w - u) + dx * ux + dy * uy);
      }
    }
    return {};
  }

  // B of B dc/dt = -F: the Q2 mass matrix in u's rows; w has no time derivative
  keller::Status mass(int item, const double*, const double*, double* B) const {
    const keller::ref::Tables& tb = keller::ref::tables();
    std::fill(B, B + kSize * kSize, 0.0);
    for (int q = 0; q < keller::ref::kQp; ++q)
      for (int i = 0; i < 9; ++i)
        for (int j = 0; j < 9; ++j) B[i * kSize + j] += (*geometry_)[item][q].wdetJ * tb.N2[q][i] * tb.N2[q][j];
    return {};
  }

 private:
  const Geometry* geometry_;
  std::vector<int> dofs_;
};

class SwiftHohenberg final : public keller::AssembledProblem {
 public:
  SwiftHohenberg(int nx, int ny, double lx, double ly, double r, double nu) : nx_(nx), ny_(ny), lx_(lx), ly_(ly) {
    keller::BlockMeshBuilder builder;
    builder.add_block({"rectangle",
                       "domain",
                       nx,
                       ny,
                       keller::Grading::uniform(),
                       keller::Grading::uniform(),
                       [lx, ly](double s, double t) {
                         return keller::Mesh::Point{lx * s, ly * t};
                       },
                       {"wall", "wall", "wall", "wall"}});
    mesh_ = builder.build();
    params_.add("r", r, "distance from onset: u = 0 loses stability where r = (1 - k^2)^2");
    params_.add("nu", nu, "coefficient of the quadratic term u^2");
    dofs_ = std::make_unique<keller::DofMap>(mesh_,
                                             std::vector<keller::FieldSpec>{{"c", keller::Basis::Q2, {"u", "w"}, {}}});
    geometry_.resize(mesh_.num_elements());
    for (int e = 0; e < mesh_.num_elements(); ++e) {
      double xy[9][2];
      mesh_.element_nodes(e, xy);
      keller::map_element(xy, geometry_[e]);
    }
    // the walls' conditions are natural: no boundary term, no Dirichlet rows
    assemble(dofs_->size(), {std::make_shared<keller::KernelTerm<SwiftHohenbergKernel>>(
                                SwiftHohenbergKernel(*dofs_, &geometry_), params_)});
    at_origin_ = node_at(0.0, 0.0);
    at_quarter_ = node_at(lx / 4, 0.0);
    at_top_ = node_at(0.0, ly);
  }

  std::string name() const override { return "swift-hohenberg"; }
  keller::Vector initial_guess() override { return keller::Vector::Zero(size()); }
  // the largest |u|, and u at (0, 0), (Lx / 4, 0) and (0, Ly): stripes cos(4 pi x / Lx) have
  // u(Lx / 4, 0) = -u(0, 0) and u(0, Ly) = u(0, 0); spots cos(2 pi x / Lx) cos(2 pi y / Ly) have
  // u(Lx / 4, 0) = 0
  std::vector<std::string> observable_names() const override { return {"u_max", "u_origin", "u_quarter", "u_top"}; }
  keller::Status observables(const keller::Vector& c, std::vector<double>& values) override {
    double m = 0.0;
    for (int node = 0; node < mesh_.num_nodes(); ++node) m = std::max(m, std::abs(c[dofs_->node_dof(0, node, 0)]));
    values = {m, u(c, at_origin_), u(c, at_quarter_), u(c, at_top_)};
    return {};
  }
  keller::SolutionFields fields(const keller::Vector& c) const override {
    return keller::extract_fields(mesh_, *dofs_, c);
  }
  std::string summary() const override {
    return fmt::format("Swift-Hohenberg, mixed Q2 elements on a {} x {} mesh of (0, {:.6g}) x (0, {:.6g}), {} unknowns",
                       nx_, ny_, lx_, ly_, size());
  }

 private:
  int node_at(double x, double y) const {
    for (int node = 0; node < mesh_.num_nodes(); ++node)
      if (std::abs(mesh_.node(node)[0] - x) < 1e-9 * lx_ && std::abs(mesh_.node(node)[1] - y) < 1e-9 * ly_) return node;
    return -1;
  }
  double u(const keller::Vector& c, int node) const { return node < 0 ? NAN : c[dofs_->node_dof(0, node, 0)]; }

  int nx_, ny_;
  double lx_, ly_;
  keller::Mesh mesh_;
  std::unique_ptr<keller::DofMap> dofs_;
  Geometry geometry_;
  int at_origin_ = -1, at_quarter_ = -1, at_top_ = -1;
};

}  // namespace

int main(int argc, char** argv) {
  keller::use_native_blas_kernels(argv);  // OpenBLAS on the CPU's own kernels (runs/CommandLine.hpp)
  keller::ProblemType type;
  type.name = "swift-hohenberg";
  type.doc = "the Swift-Hohenberg equation on a rectangle with no-flux walls, mixed Q2 elements (patterns)";
  type.declare = [](keller::SceneSchema& s) {
    s.section("swift_hohenberg", "the rectangle and its mesh");
    s.real("swift_hohenberg.lx", 4.0, "side Lx along x, in units of pi", keller::Range::positive());
    s.real("swift_hohenberg.ly", 2.5, "side Ly along y, in units of pi", keller::Range::positive());
    s.integer("swift_hohenberg.nx", 16, "elements along x (a multiple of 4: x = Lx / 4 is a node)",
              keller::Range::between(4, 4000));
    s.integer("swift_hohenberg.ny", 10, "elements along y", keller::Range::between(1, 4000));
    s.section("parameters", "initial values of the named continuation parameters");
    s.real("parameters.r", -0.02, "distance from onset");
    s.real("parameters.nu", 0.0, "coefficient of u^2 (0: the symmetry u -> -u)");
  };
  type.build = [](const keller::Scene& s) -> std::unique_ptr<keller::Problem> {
    const int nx = s.integer("swift_hohenberg.nx");
    if (nx % 4 != 0) throw s.error("swift_hohenberg.nx", "must be a multiple of 4 (u_quarter is a node value)");
    return std::make_unique<SwiftHohenberg>(nx, s.integer("swift_hohenberg.ny"), M_PI * s.real("swift_hohenberg.lx"),
                                            M_PI * s.real("swift_hohenberg.ly"), s.real("parameters.r"),
                                            s.real("parameters.nu"));
  };
  keller::register_problem_type(std::move(type));
  return keller::run_command_line(argc, argv);
}
