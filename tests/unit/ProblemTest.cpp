// The problem contract (core/Problem.hpp) from a user's side: a 2D Bratu problem written the way
// a user would write one, with its equations and nothing else (the Jacobian, dF/dp and the fields
// are the contract's defaults), traced through Continuation to its fold, which must be the fold of
// problems/analytic/Bratu2DProblem on the same grid; and the defaults themselves.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <stdexcept>

#include "continuation/Continuation.hpp"
#include "core/Problem.hpp"
#include "problems/ProblemRegistry.hpp"
#include "problems/analytic/Bratu2DProblem.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

// Laplace(u) + lambda e^u = 0 on the unit square, u = 0 on its boundary: the weak form
// int grad u . grad phi - lambda e^u phi = 0 with biquadratic (Q2) elements on a uniform n x n
// mesh and the 3 x 3 Gauss rule, the unknowns the values at the (2n - 1)^2 interior nodes of the
// (2n + 1)^2 node grid. Only what a user must write: no Jacobian, no dF/dlambda, no fields.
class UserBratu final : public Problem {
 public:
  explicit UserBratu(int n) : n_(n), m_(2 * n + 1) {
    params_.add("lambda", 0.0, "the load");
    pattern_.resize(size(), size());
    std::vector<Eigen::Triplet<double>> coupled;
    for (int ex = 0; ex < n_; ++ex)
      for (int ey = 0; ey < n_; ++ey)
        for (int a = 0; a < 9; ++a)
          for (int b = 0; b < 9; ++b) {
            const int i = unknown(ex, ey, a), j = unknown(ex, ey, b);
            if (i >= 0 && j >= 0) coupled.emplace_back(i, j, 0.0);
          }
    pattern_.setFromTriplets(coupled.begin(), coupled.end());
    pattern_.makeCompressed();
  }

  std::string name() const override { return "user-bratu"; }
  int size() const override { return (m_ - 2) * (m_ - 2); }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Vector initial_guess() override { return Vector::Zero(size()); }
  std::vector<std::string> observable_names() const override { return {"u_max"}; }
  Status observables(const Vector& u, std::vector<double>& values) override {
    values = {u.maxCoeff()};
    return {};
  }

  Status residual(const Vector& u, Vector& F) override {
    const double lambda = params_.value(0), h = 1.0 / n_;
    const std::array<double, 3> s = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)}, w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
    F = Vector::Zero(size());
    for (int ex = 0; ex < n_; ++ex)
      for (int ey = 0; ey < n_; ++ey) {
        double ue[9];
        for (int a = 0; a < 9; ++a) {
          const int i = unknown(ex, ey, a);
          ue[a] = i >= 0 ? u[i] : 0.0;
        }
        for (int qx = 0; qx < 3; ++qx)
          for (int qy = 0; qy < 3; ++qy) {
            double N[9], dx[9], dy[9];
            for (int a = 0; a < 9; ++a) {
              const int ax = a % 3, ay = a / 3;
              N[a] = shape(ax, s[qx]) * shape(ay, s[qy]);
              dx[a] = slope(ax, s[qx]) * shape(ay, s[qy]) * 2.0 / h;
              dy[a] = shape(ax, s[qx]) * slope(ay, s[qy]) * 2.0 / h;
            }
            double value = 0.0, ux = 0.0, uy = 0.0;
            for (int a = 0; a < 9; ++a) value += N[a] * ue[a], ux += dx[a] * ue[a], uy += dy[a] * ue[a];
            const double weight = w[qx] * w[qy] * h * h / 4.0, source = lambda * std::exp(value);
            for (int a = 0; a < 9; ++a) {
              const int i = unknown(ex, ey, a);
              if (i >= 0) F[i] += weight * (dx[a] * ux + dy[a] * uy - N[a] * source);
            }
          }
      }
    return {};
  }

 private:
  // The 1D quadratic Lagrange functions on [-1, 1] with nodes -1, 0, 1, and their derivatives.
  static double shape(int k, double t) { return k == 0 ? t * (t - 1) / 2 : k == 1 ? 1 - t * t : t * (t + 1) / 2; }
  static double slope(int k, double t) { return k == 0 ? t - 0.5 : k == 1 ? -2 * t : t + 0.5; }
  // The unknown at local node a (a % 3 along x, a / 3 along y) of element (ex, ey); -1 on the boundary.
  int unknown(int ex, int ey, int a) const {
    const int gx = 2 * ex + a % 3, gy = 2 * ey + a / 3;
    if (gx == 0 || gy == 0 || gx == m_ - 1 || gy == m_ - 1) return -1;
    return (gx - 1) + (m_ - 2) * (gy - 1);
  }

  int n_, m_;  // elements and nodes per side
  ParameterSet params_;
  SparseMatrix pattern_;
};

const BranchPoint& only_fold(const test::RecordingObserver& rec) {
  const auto folds = rec.of_kind(PointKind::Fold);
  if (folds.size() != 1) throw std::runtime_error("expected one fold, found " + std::to_string(folds.size()));
  return *folds[0];
}

}  // namespace

// The user's problem, continued from lambda = 0 round its fold with the library's defaults for J
// and dF/dlambda, folds where Bratu2DProblem (its own Jacobian by automatic differentiation) does
// on the same 8 x 8 mesh. Both folds are located to 1e-12 (bratu_fold_options) where the branch is
// flat in lambda, so the different Jacobians (differences, dual numbers) and steps move lambda by
// far less than 1e-10 (they agree to 1e-13). Along the branch max u changes at about unit rate,
// and the fold's arclength is located to about the square root of the tolerance: 1e-6 (3e-7).
TEST(Problem, AUserProblemOfEquationsAloneIsTracedToTheFoldOfTheLibrarysOwn) {
  UserBratu user(8);
  Bratu2DProblem library(8, 0.0);
  ASSERT_EQ(user.size(), 15 * 15);
  test::RecordingObserver traced, reference;
  Continuation(user, test::bratu_fold_options("u_max", 2.0)).run(user.initial_guess(), traced);
  Continuation(library, test::bratu_fold_options("u_max", 2.0)).run(library.initial_guess(), reference);
  const BranchPoint& fold = only_fold(traced);
  const BranchPoint& expected = only_fold(reference);
  std::cout << std::setprecision(15) << "user fold lambda = " << fold.lambda << ", library's " << expected.lambda
            << "; max u " << fold.observables[0] << ", " << expected.observables[0] << "\n";
  EXPECT_NEAR(fold.lambda, expected.lambda, 1e-10);
  EXPECT_NEAR(fold.observables[0], expected.observables[0], 1e-6);
  EXPECT_NEAR(fold.lambda, Bratu2DProblem::kLambdaCritical, 1e-3);  // (the 8 x 8 fold: 6.8082)
}

// The defaults of the contract on the same problem: J by one-sided differences (against central
// differences of the residual, to the one-sided step's error), dF/dlambda by central differences
// (-int e^u phi, exactly the residual's lambda part), no fields, no mass matrix.
TEST(Problem, TheDefaultsAreDifferencesOfTheResidual) {
  UserBratu p(2);
  p.parameters().set("lambda", 3.0);
  const Vector u = Vector::LinSpaced(p.size(), 0.1, 0.5);
  Vector F, F0, dF;
  SparseMatrix J;
  ASSERT_TRUE(p.jacobian(u, F, J).is_ok());
  ASSERT_TRUE(p.residual(u, F0).is_ok());
  EXPECT_EQ((F - F0).norm(), 0.0);
  EXPECT_EQ(J.nonZeros(), p.jacobian_pattern().nonZeros());
  for (int c = 0; c < p.size(); ++c) {
    const double h = 1e-5;
    Vector up = u, um = u, Fp, Fm;
    up[c] += h;
    um[c] -= h;
    ASSERT_TRUE(p.residual(up, Fp).is_ok());
    ASSERT_TRUE(p.residual(um, Fm).is_ok());
    const Vector column = (Fp - Fm) / (2 * h);
    EXPECT_LT((Vector(J.col(c)) - column).lpNorm<Eigen::Infinity>(), 1e-6) << "column " << c;
  }
  ASSERT_TRUE(p.parameter_derivative(0, u, dF).is_ok());
  EXPECT_EQ(p.parameters().get("lambda"), 3.0);  // (restored)
  p.parameters().set("lambda", 0.0);
  Vector F_at_zero;
  ASSERT_TRUE(p.residual(u, F_at_zero).is_ok());
  EXPECT_LT((dF - (F0 - F_at_zero) / 3.0).lpNorm<Eigen::Infinity>(), 1e-9);  // F is affine in lambda
  const SolutionFields fields = p.fields(u);
  EXPECT_TRUE(fields.nodal.empty());
  EXPECT_EQ(fields.mesh, nullptr);
  SparseMatrix B;
  EXPECT_THROW(p.mass_matrix(u, B), NoTimeForm);
  EXPECT_FALSE(has_time_form(p));  // what a run that needs B asks before any work
  Bratu2DProblem library(2, 0.0);
  EXPECT_TRUE(has_time_form(library));
  EXPECT_TRUE(p.monitor_names().empty());
  EXPECT_EQ(p.summary(), "user-bratu");
}

// A program's own problem types (register_problem_type): added after keller's, found by name;
// refused with the reason for a bad or taken name and for a type that cannot declare or build.
TEST(ProblemRegistry, AProgramRegistersItsOwnTypes) {
  const size_t before = problem_types().size();
  auto type = [](const std::string& name) {
    ProblemType t;
    t.name = name;
    t.doc = "a test type";
    t.declare = [](SceneSchema&) {};
    t.build = [](const Scene&) -> std::unique_ptr<Problem> { return nullptr; };
    return t;
  };
  register_problem_type(type("my-problem_2"));
  ASSERT_EQ(problem_types().size(), before + 1);
  EXPECT_EQ(problem_types().back().name, "my-problem_2");
  EXPECT_EQ(problem_type("my-problem_2").doc, "a test type");
  auto refusal = [](ProblemType t) -> std::string {
    try {
      register_problem_type(std::move(t));
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_NE(refusal(type("my-problem_2")).find("is registered already"), std::string::npos);
  EXPECT_NE(refusal(type("bratu1d")).find("is registered already"), std::string::npos);
  EXPECT_NE(refusal(type("")).find("use lower-case letters"), std::string::npos);
  EXPECT_NE(refusal(type("My Problem")).find("use lower-case letters"), std::string::npos);
  ProblemType no_build = type("no-build");
  no_build.build = nullptr;
  EXPECT_NE(refusal(no_build).find("needs both declare and build"), std::string::npos);
  EXPECT_EQ(problem_types().size(), before + 1);
}

// The points of a parameter's central difference stay admissible: both sides inside the range,
// the side that would reach an open bound or cross a closed one moved back to the value itself
// (one-sided), an exact closed bound kept.
TEST(ParameterSet, DifferencePointsStayInsideTheAdmissibleRange) {
  ParameterSet ps;
  const int open = ps.add("Gamma", 4e-7, "open at zero", Range{0.0, INFINITY, true, false});
  const int closed = ps.add("t", 1.0, "closed on [0, 1]", 0.0, 1.0);
  const int free = ps.add("x", 0.5, "unbounded");
  EXPECT_EQ(ps.difference_points(open, 1e-6), std::make_pair(4e-7, 4e-7 + 1e-6));
  EXPECT_EQ(ps.difference_points(closed, 1e-6), std::make_pair(1.0 - 1e-6, 1.0));
  EXPECT_EQ(ps.difference_points(free, 0.25), std::make_pair(0.25, 0.75));
  ps.set(open, 1e-6);  // exactly h above an open bound: v - h = 0 is refused
  EXPECT_EQ(ps.difference_points(open, 1e-6).first, 1e-6);
  ps.set(closed, 1e-6);  // exactly h above a closed bound: v - h = 0 is admissible
  EXPECT_EQ(ps.difference_points(closed, 1e-6).first, 0.0);
}
