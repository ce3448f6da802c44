// The elliptic mesh equations alone, on the fluid part of the channel mesh with the interface
// prescribed: the generated mesh solves them exactly; a deep prescribed collapse of the interface
// moves the mesh without inverting an element; the Jacobian matches finite differences.
#include <gtest/gtest.h>

#include <limits>

#include <cmath>
#include <memory>
#include <random>

#include "core/AssembledProblem.hpp"
#include "core/KernelTerm.hpp"
#include "core/Newton.hpp"
#include "problems/channel/ChannelMesh.hpp"
#include "problems/components/FluidMeshMotion.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

// Fluid mesh with the interface pushed down to y = 1 - A sin^2(pi (x - Lu) / L) (nodes keep x).
class PrescribedInterfaceMesh final : public AssembledProblem {
 public:
  PrescribedInterfaceMesh(const ChannelMeshSpec& spec, bool sliding)
      : mesh_(build_channel_mesh(ChannelGeometry{}, spec, false)), motion_(mesh_, "fluid", MeshMotionOptions{sliding}) {
    iA_ = params_.add("A", 0.0, "interface depression");
    dofs_ = std::make_unique<DofMap>(mesh_, std::vector<FieldSpec>{{"position", Basis::Q2, {"x", "y"}, {"fluid"}}});
    dirichlet_ = std::make_shared<DirichletTerm>("boundary", params_);
    std::vector<int> interface = mesh_.boundary_nodes("interface");
    const int fx = dofs_->field_index("position"), iA = iA_;
    for (int n : interface) {
      const double x = mesh_.node(n)[0], s = std::sin(M_PI * (x - 7.0) / 5.0);
      dirichlet_->add(dofs_->node_dof(fx, n, 0), x);
      dirichlet_->add(dofs_->node_dof(fx, n, 1), [s, iA](const ParameterSet& p) { return 1.0 - p.value(iA) * s * s; });
    }
    motion_.build(ComponentBuild{*dofs_, *dirichlet_, params_, true, interface});
    std::vector<std::shared_ptr<const Term>> terms = motion_.terms();
    terms.push_back(dirichlet_);
    assemble(dofs_->size(), terms);
  }
  std::string name() const override { return "mesh"; }
  Vector initial_guess() override {
    Vector u = Vector::Zero(size());
    motion_.generated_state(*dofs_, u);
    return u;
  }
  SolutionFields fields(const Vector& u) const override { return extract_fields(mesh_, *dofs_, u); }

  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  const FluidMeshMotion& motion() const { return motion_; }
  double y(const Vector& u, int node) const { return u[dofs_->node_dof(0, node, 1)]; }
  double x(const Vector& u, int node) const { return u[dofs_->node_dof(0, node, 0)]; }

 private:
  Mesh mesh_;
  FluidMeshMotion motion_;
  int iA_ = -1;
  std::unique_ptr<DofMap> dofs_;
  std::shared_ptr<DirichletTerm> dirichlet_;
};

}  // namespace

// The generated mesh is an exact discrete solution: its residual is rounding, each row's below a
// small multiple of the unit roundoff times the size of the terms that cancel in it, (|J| |u|)_i
// (at most about 36 Gauss-point contributions of a few products each enter a row; 64 leaves
// room for the order in which an unoptimised build adds them).
TEST(MeshMotion, TheGeneratedMeshSolvesTheEllipticEquations) {
  for (const char* name : {"M1", "M3"}) {
    PrescribedInterfaceMesh p(ChannelMeshSpec::preset(name), true);
    const Vector u = p.initial_guess();
    Vector F;
    SparseMatrix J;
    ASSERT_TRUE(p.jacobian(u, F, J).is_ok());
    const Vector terms = J.cwiseAbs() * u.cwiseAbs();
    double worst = 0;
    for (int i = 0; i < F.size(); ++i)
      if (terms[i] > 0) worst = std::max(worst, std::abs(F[i]) / (std::numeric_limits<double>::epsilon() * terms[i]));
    std::printf("%s: ||F||_inf on the generated mesh = %.2e, at most %.1f eps (|J| |u|)_i\n", name,
                F.cwiseAbs().maxCoeff(), worst);
    EXPECT_LT(worst, 64.0);
  }
}

TEST(MeshMotion, DeepCollapseKeepsEveryElementUpright) {
  for (bool sliding : {true, false}) {
    PrescribedInterfaceMesh p(ChannelMeshSpec::preset("M1"), sliding);
    Vector u = p.initial_guess();
    NewtonSolver newton(p);
    // to a gap of 10% of the width in steps of 0.15
    for (double A : {0.15, 0.3, 0.45, 0.6, 0.75, 0.9}) {
      p.parameters().set("A", A);
      const NewtonResult r = newton.solve(u);
      ASSERT_TRUE(r.converged()) << "A = " << A << ": " << r.status.describe();
    }
    const double jmin = p.motion().min_relative_jacobian(p.dofs(), u);
    std::printf("%s walls, gap 0.1: min det J / det J_generated = %.4f\n", sliding ? "sliding" : "fixed", jmin);
    EXPECT_GT(jmin, 0.02);
    // the nodes under the narrowest point of the interface share the gap in the generated
    // proportions: the mesh line next to the bottom wall keeps its relative height
    const MeshBlock& b = p.mesh().block("deformable");
    const int mid = b.nx;  // node column at x = Lu + L/2
    const int top = b.node(mid, 2 * b.ny), bottom = b.node(mid, 0), first = b.node(mid, 2);
    const double gap = p.y(u, top) - p.y(u, bottom);
    EXPECT_NEAR(gap, 0.1, 1e-12);
    const double generated = p.mesh().node(first)[1];
    EXPECT_NEAR((p.y(u, first) - p.y(u, bottom)) / gap, generated, 0.02);
    if (sliding) continue;
    for (int n : p.mesh().boundary_nodes("bottom_wall")) EXPECT_EQ(p.x(u, n), p.mesh().node(n)[0]);
  }
}

TEST(MeshMotion, JacobianMatchesFiniteDifferences) {
  ChannelMeshSpec s = ChannelMeshSpec::preset("M1");
  s.nx_upstream = s.nx_downstream = 2;
  s.nx_deformable = 4;
  s.ny_fluid = 3;
  PrescribedInterfaceMesh p(s, true);
  p.parameters().set("A", 0.4);
  Vector u = p.initial_guess();
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> d(-0.02, 0.02);
  for (int i = 0; i < u.size(); ++i) u[i] += d(gen);
  const test::JacobianCheck c = test::check_problem_jacobian(p, u);
  std::printf("Jacobian: max relative error %.2e\n", c.max_relative_error);
  EXPECT_LT(c.max_relative_error, 1e-6);
  EXPECT_LT(test::check_parameter_derivative(p, 0, u), 1e-6);
}
