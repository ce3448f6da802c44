// Helpers shared by the continuation engine tests (ContinuationTest, ContinuationChordTest,
// ContinuationKeptFactorisationTest, and the direct tests of the engine's parts): options for the
// cubic, points on a circle, the kept-chord options, a trace from a guess, the engine's parts
// wired together, and small diagonal problems whose chord rates are known.
#pragma once

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <random>
#include "continuation/Continuation.hpp"
#include "continuation/engine/BorderedSystem.hpp"
#include "continuation/engine/Hermite.hpp"
#include "core/ConvergenceTest.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "support/TestProblems.hpp"

namespace keller::test {

using keller::test::CubicProblem;
using keller::test::RecordingObserver;

inline SparseMatrix random_matrix(int n, unsigned seed, bool singular) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> U(-1, 1);
  Eigen::MatrixXd D = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i) {
    D(i, i) = 3 + U(rng);
    D(i, (i + 1) % n) = U(rng);
    D((i + 2) % n, i) = U(rng);
  }
  if (singular) D.row(n - 1) = D.row(0) + D.row(1);  // rank n - 1, like J at a fold
  SparseMatrix A = D.sparseView(0.0, 0.0);
  for (int i = 0; i < n; ++i) A.coeffRef(i, i) += 0.0;  // keep the diagonal in the pattern
  A.makeCompressed();
  return A;
}

// The engine's exact-Newton path (a Jacobian per corrector iteration, the whole bordered matrix
// factorised): the location tests below count its iterations. The fast defaults (a kept chord)
// are the other tests'.
inline ContinuationOptions cubic_options() {
  ContinuationOptions o;
  o.corrector.method = CorrectorOptions::Method::Newton;
  o.corrector.block_elimination = false;
  o.parameter = "lambda";
  o.stop.lower = -5.0;
  o.stop.upper = 5.0;
  o.step.initial = 0.1;
  o.step.max = 0.3;
  o.events.tolerance = 1e-12;
  return o;
}

// The unit circle by arclength s: u = cos s, lambda = sin s, with its unit tangent.
inline BranchPoint circle_point(double s) {
  BranchPoint p;
  p.s = s;
  p.u = Vector::Constant(1, std::cos(s));
  p.lambda = std::sin(s);
  p.tu = Vector::Constant(1, -std::sin(s));
  p.tlambda = std::cos(s);
  return p;
}

// Options of the ScaledLinear tests: natural steps of the given size (one step to just past
// upper), the plain chord (no Anderson mixing, so that its rate is known exactly) with the
// factorisation kept across steps, renewed by the rate rule alone.
inline ContinuationOptions kept_chord_options(double step, double upper, int max_iterations,
                                              std::vector<double> stops) {
  ContinuationOptions o;
  o.parameter = "lambda";
  o.method = ContinuationOptions::Method::Natural;
  o.step.max_angle_degrees = 89;  // the tangent turns by up to about 45 degrees on one step
  o.stop.upper = upper;
  o.step.initial = step;
  o.step.max = step;
  o.corrector.method = CorrectorOptions::Method::Chord;
  o.corrector.block_elimination = true;
  o.corrector.keep = true;
  o.corrector.anderson_depth = 0;
  o.corrector.renewal_cost = 0.0;
  o.events.branch_points = false;
  o.step.target_iterations = 8;
  o.corrector.max_iterations = max_iterations;
  o.events.stops = std::move(stops);
  return o;
}

// Traces p from its initial guess with o.
inline ContinuationResult trace_from_guess(Problem& p, const ContinuationOptions& o, RecordingObserver& rec) {
  Continuation cont(p, o);
  return cont.run(p.initial_guess(), rec);
}

// The engine's parts on a problem in its parameter "lambda", wired as Continuation wires them (the
// arclength norm of state scale 1; a point's evaluation: its observables and monitors), for the
// direct tests of the corrector, the kept factorisation, the locator and the lander.
struct EngineParts {
  EngineParts(Problem& problem, ContinuationOptions o)
      : options(std::move(o)),
        ev(problem, problem.parameters().index("lambda"), "lambda"),
        kept(problem, {}, options.corrector.block_elimination),
        norm(problem.size(), 1.0, options.theta),
        corrector(ev, kept, norm, options, {}),
        tangents(ev, kept, norm, options),
        locator(
            corrector, tangents, kept, norm, options,
            [this](BranchPoint& p, bool) {
              Status st = ev.set_parameter(p.lambda);
              if (st.is_ok()) st = ev.problem().observables(p.u, p.observables);
              if (st.is_ok()) st = ev.problem().monitors(p.u, p.monitors);
              return st;
            },
            [] { return std::string(); }),
        lander(ev, locator, options) {}
  EngineParts(const EngineParts&) = delete;  // (the parts refer to each other)
  EngineParts& operator=(const EngineParts&) = delete;
  ContinuationOptions options;
  Evaluator ev;
  KeptFactorisation kept;
  ArclengthNorm norm;
  Corrector corrector;
  TangentSolver tangents;
  EventLocator locator;
  ZeroLander lander;
};

// (x, y) and the determinant sign against a dense LU of [J b; c^T d] (x, y) = (f, g): to 1e-12.
inline void expect_dense_solution(const SparseMatrix& J, const Vector& b, const Vector& c, double d, const Vector& f,
                                  double g, const Vector& x, double y, int det_sign) {
  const long n = J.rows();
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n + 1, n + 1);
  A.topLeftCorner(n, n) = Eigen::MatrixXd(J);
  A.block(0, n, n, 1) = b;
  A.block(n, 0, 1, n) = c.transpose();
  A(n, n) = d;
  Vector rhs(n + 1);
  rhs << f, g;
  const Vector ref = A.fullPivLu().solve(rhs);
  EXPECT_LT((x - ref.head(n)).cwiseAbs().maxCoeff(), 1e-12 * ref.cwiseAbs().maxCoeff());
  EXPECT_NEAR(y, ref[n], 1e-12 * ref.cwiseAbs().maxCoeff());
  EXPECT_EQ(det_sign, A.determinant() > 0 ? 1 : -1);
}

// The Problem boilerplate of the small diagonal problems below: F_i depends on u_i and one
// parameter "lambda" only; observable u0.
class DiagonalProblem : public Problem {
 public:
  DiagonalProblem(std::string name, int n, double lambda0) : name_(std::move(name)), n_(n), pattern_(n, n) {
    params_.add("lambda", lambda0, name_);
    for (int i = 0; i < n; ++i) pattern_.insert(i, i) = 0.0;
    pattern_.makeCompressed();
  }
  std::string name() const override { return name_; }
  int size() const override { return n_; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override {
    F.resize(n_);
    for (int i = 0; i < n_; ++i) F[i] = f(i, u[i], lambda());
    return {};
  }
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override {
    residual(u, F);
    J = pattern_;
    for (int i = 0; i < n_; ++i) J.valuePtr()[i] = df_du(i, u[i], lambda());
    return {};
  }
  Status parameter_derivative(int, const Vector& u, Vector& dF) override {
    dF.resize(n_);
    for (int i = 0; i < n_; ++i) dF[i] = df_dlambda(i, u[i], lambda());
    return {};
  }
  std::vector<std::string> observable_names() const override { return {"u0"}; }
  Status observables(const Vector& u, std::vector<double>& v) override {
    v = {u[0]};
    return {};
  }
  SolutionFields fields(const Vector&) const override { return {}; }

 protected:
  virtual double f(int i, double u, double lambda) const = 0;
  virtual double df_du(int i, double u, double lambda) const = 0;
  virtual double df_dlambda(int i, double u, double lambda) const = 0;
  double lambda() const { return params_.value(0); }

 private:
  std::string name_;
  int n_;
  ParameterSet params_;
  SparseMatrix pattern_;
};

// F_i = (1 + lambda) d_i u_i - 1, d_i = 1 + i: u_i = 1 / ((1 + lambda) d_i). With a factorisation
// kept from lambda_b the chord contracts the error of a correction at lambda by exactly
// |1 - (1 + lambda) / (1 + lambda_b)| per iteration.
class ScaledLinear final : public DiagonalProblem {
 public:
  // scale multiplies F: its rounding floor is about 1e-16 x scale
  explicit ScaledLinear(int n, double scale = 1.0) : DiagonalProblem("scaled-linear", n, 0.0), scale_(scale) {}
  Vector initial_guess() override {
    Vector u(size());
    for (int i = 0; i < size(); ++i) u[i] = 1.0 / (1 + i);
    return u;
  }

 private:
  double f(int i, double u, double l) const override { return scale_ * ((1 + l) * (1 + i) * u - 1); }
  double df_du(int i, double, double l) const override { return scale_ * (1 + l) * (1 + i); }
  double df_dlambda(int i, double u, double) const override { return scale_ * (1 + i) * u; }
  double scale_;
};

}  // namespace keller::test
