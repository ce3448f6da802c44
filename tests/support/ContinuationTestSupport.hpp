// Helpers shared by the continuation engine tests (ContinuationTest, ContinuationChordTest):
// options for the cubic, points on a circle, the kept-chord options and a trace from a guess.
#pragma once

#include <gtest/gtest.h>
#include <Eigen/Dense>
#include <cmath>
#include <iostream>
#include <random>
#include "continuation/BorderedSystem.hpp"
#include "continuation/Continuation.hpp"
#include "continuation/Hermite.hpp"
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

}  // namespace keller::test
