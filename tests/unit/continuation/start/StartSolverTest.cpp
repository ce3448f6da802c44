// The first steady state found by itself (StartSolver): where Newton from the initial guess fails,
// by continuation in a declared homotopy parameter from its easy value, or along the residual
// homotopy F(u) - (1 - s) F(guess) = 0; the state reached is the one Newton finds where it can.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <iostream>

#include "continuation/start/ResidualHomotopy.hpp"
#include "continuation/start/StartSolver.hpp"
#include "problems/analytic/Bratu2DProblem.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

// u^3 - 3u = lambda from u = -1.05, next to the local maximum of the cubic at u = -1 (lambda = 2):
// at lambda = 3 Newton's line search creeps into that local minimum of |F| and gives up, while the
// branch from lambda = -5 (one root, u = -2.28) reaches lambda = 3 past both folds.
class DeclaredCubic final : public Problem {
 public:
  DeclaredCubic() : inner_(3.0) {}
  std::string name() const override { return "declared-cubic"; }
  int size() const override { return 1; }
  ParameterSet& parameters() override { return inner_.parameters(); }
  const ParameterSet& parameters() const override { return inner_.parameters(); }
  const SparseMatrix& jacobian_pattern() const override { return inner_.jacobian_pattern(); }
  Status residual(const Vector& u, Vector& F) override { return inner_.residual(u, F); }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override { return inner_.jacobian(u, F, J); }
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override {
    return inner_.parameter_derivative(p, u, dF);
  }
  Vector initial_guess() override { return Vector::Constant(1, -1.05); }
  std::vector<Homotopy> homotopies() const override { return {{"lambda", -5.0}}; }
  SolutionFields fields(const Vector&) const override { return {}; }

 private:
  test::CubicProblem inner_;
};

// atan(u - lambda) = 0 (the root u = lambda) with a guess that depends on the parameter, u0 =
// lambda^2 / 2: Newton (5 iterations allowed, no chord) converges from within about 1 of the root
// and not from tens away (atan's Newton steps overshoot beyond 1.39 and the line search creeps).
// At lambda = 10 the guess 50 fails; at the easy value lambda = 1 that same guess still fails,
// while the guess made there (0.5) converges.
class GuessOfItsParameter final : public Problem {
 public:
  GuessOfItsParameter() {
    params_.add("lambda", 10.0, "the root");
    pattern_.resize(1, 1);
    pattern_.insert(0, 0) = 1.0;
    pattern_.makeCompressed();
  }
  std::string name() const override { return "guess-of-its-parameter"; }
  int size() const override { return 1; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override {
    F = Vector::Constant(1, std::atan(u[0] - params_.get("lambda")));
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    const double d = u[0] - params_.get("lambda");
    J.coeffRef(0, 0) = 1.0 / (1.0 + d * d);
    return {};
  }
  Vector initial_guess() override {
    const double lambda = params_.get("lambda");
    return Vector::Constant(1, 0.5 * lambda * lambda);
  }
  std::vector<Homotopy> homotopies() const override { return {{"lambda", 1.0}}; }
  SolutionFields fields(const Vector&) const override { return {}; }

 private:
  ParameterSet params_;
  SparseMatrix pattern_;
};

}  // namespace

TEST(StartSolver, AStageAlsoTriesTheGuessMadeAtItsEasyValues) {
  GuessOfItsParameter p;
  NewtonOptions few;
  few.max_iterations = 5;
  few.chord_rate = 0.0;  // Newton proper: its reach from each guess is what the case is built on
  const Vector scene_guess = p.initial_guess();
  Vector u = scene_guess;
  EXPECT_FALSE(NewtonSolver(p, few).solve(u).converged());  // at lambda = 10
  p.parameters().set("lambda", 1.0);
  u = scene_guess;
  EXPECT_FALSE(NewtonSolver(p, few).solve(u).converged());  // the scene's guess at the easy value
  p.parameters().set("lambda", 10.0);

  StartOptions by_parameters;
  by_parameters.path = StartOptions::Path::Parameters;
  StartSolver start(p, few, {}, by_parameters);
  u = scene_guess;
  const StartResult r = start.solve(u);
  ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
  EXPECT_NE(r.path.find("lambda from 1 to 10 (from the initial guess made at the easy values)"), std::string::npos)
      << r.path;
  // |F| = |atan(u - 10)| <= the tolerance 1e-10 and atan' = 1 at the root
  EXPECT_NEAR(u[0], 10.0, 1e-10);
  EXPECT_DOUBLE_EQ(p.parameters().get("lambda"), 10.0);
}

TEST(StartSolver, NewtonFromTheGuessFailsAndTheDeclaredHomotopyReachesTheState) {
  DeclaredCubic p;
  Vector u = p.initial_guess();
  NewtonSolver plain(p);
  EXPECT_FALSE(plain.solve(u).converged());  // the case this is about

  std::vector<std::string> said;
  StartSolver start(p, {}, {}, {}, [&](const std::string& line) { said.push_back(line); });
  u = p.initial_guess();
  const StartResult r = start.solve(u);
  for (const std::string& line : said) std::cout << line << "\n";
  ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
  EXPECT_TRUE(r.by_continuation);
  EXPECT_NE(r.path.find("lambda from -5 to 3"), std::string::npos) << r.path;
  ASSERT_EQ(said.size(), 2u);  // why Newton from the guess was not enough, and the path taken
  EXPECT_NE(said.back().find("continuation in lambda"), std::string::npos) << said.back();
  // the cubic's one root above 2 at lambda = 3, to Newton's tolerance over |J| = 3u^2 - 3
  EXPECT_NEAR(u[0], 2.1038034027355365, 1e-10);
  EXPECT_DOUBLE_EQ(p.parameters().get("lambda"), 3.0);  // the scene's value again
}

// The residual homotopy on its own: Bratu 2D near its fold from u = 0, with Newton limited to
// three iterations (it needs more from there); its steps start near the solution, so the state is
// reached, and it is the one an unlimited Newton finds.
TEST(StartSolver, TheResidualHomotopyReachesTheStateNewtonFinds) {
  Bratu2DProblem p(8, 6.5);
  NewtonOptions few;
  few.max_iterations = 3;
  Vector u = p.initial_guess();
  EXPECT_FALSE(NewtonSolver(p, few).solve(u).converged());
  Vector reference = p.initial_guess();
  ASSERT_TRUE(NewtonSolver(p).solve(reference).converged());

  StartOptions residual;
  residual.path = StartOptions::Path::Auto;  // Bratu declares no homotopy parameter
  StartSolver start(p, few, {}, residual);
  u = p.initial_guess();
  const StartResult r = start.solve(u);
  ASSERT_TRUE(r.status.is_ok()) << r.status.describe();
  EXPECT_NE(r.path.find("residual homotopy"), std::string::npos) << r.path;
  std::cout << r.path << ": " << r.steps << " points, " << r.factorisations << " factorisations\n";
  // both states solve F to the tolerance: they differ by at most the sum of their residuals over
  // J's smallest singular value (small this close to the fold)
  Vector F1, F2;
  SparseMatrix J;
  ASSERT_TRUE(p.residual(u, F1).is_ok());
  ASSERT_TRUE(p.jacobian(reference, F2, J).is_ok());
  const double sigma_min = Eigen::JacobiSVD<Eigen::MatrixXd>(Eigen::MatrixXd(J)).singularValues().minCoeff();
  const double bound = (F1.norm() + F2.norm()) / sigma_min;
  std::cout << "states differ by " << (u - reference).norm() << ", bound " << bound << "\n";
  EXPECT_LE((u - reference).norm(), bound);
}

// The residual homotopy's equations: H(u0, 0) = 0 at the guess, H = F at s = 1, dH/ds = F(u0).
TEST(ResidualHomotopy, StartsAtTheGuessAndEndsAtTheProblem) {
  Bratu2DProblem p(4, 3.0);
  const Vector u0 = Vector::Constant(p.size(), 0.3);
  ResidualHomotopy h(p, u0);
  ASSERT_TRUE(h.status().is_ok());
  Vector H, F, dH;
  ASSERT_TRUE(h.residual(u0, H).is_ok());
  EXPECT_LT(H.lpNorm<Eigen::Infinity>(), 1e-15);
  const Vector u1 = Vector::Constant(p.size(), 0.7);
  h.parameters().set("homotopy", 1.0);
  ASSERT_TRUE(h.residual(u1, H).is_ok());
  ASSERT_TRUE(p.residual(u1, F).is_ok());
  EXPECT_LT((H - F).lpNorm<Eigen::Infinity>(), 1e-15);
  Vector F0;
  ASSERT_TRUE(p.residual(u0, F0).is_ok());
  ASSERT_TRUE(h.parameter_derivative(0, u1, dH).is_ok());
  EXPECT_LT((dH - F0).lpNorm<Eigen::Infinity>(), 1e-15);
  // (the continuation engine's finite-difference check of dF/dp is the problem's default: exact here)
  h.parameters().set("homotopy", 0.4);
  Vector Hp, Hm;
  h.parameters().set("homotopy", 0.4 + 1e-6);
  h.residual(u1, Hp);
  h.parameters().set("homotopy", 0.4 - 1e-6);
  h.residual(u1, Hm);
  EXPECT_LT(((Hp - Hm) / 2e-6 - dH).lpNorm<Eigen::Infinity>(), 1e-8);
}
