// Folds of the Bratu problems located by the continuation engine converge to the published
// critical values under refinement, at the order of the discretisation.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>

#include "continuation/Continuation.hpp"
#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Bratu2DProblem.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

using test::bratu_fold_options;

// Central differences: the discrete fold is lambda_c + O(h^2), and u(1/2) there too.
TEST(BratuFold, OneDimensionalFoldConvergesAtSecondOrder) {
  std::vector<double> err, umid;
  for (int n : {16, 32, 64, 128}) {
    Bratu1DProblem p(n, 0.0);
    Continuation cont(p, bratu_fold_options("u_mid", 4.0));
    test::RecordingObserver rec;
    const auto r = cont.run(p.initial_guess(), rec);
    const auto folds = rec.of_kind(PointKind::Fold);
    ASSERT_EQ(folds.size(), 1u) << "n = " << n;
    const double lf = folds[0]->lambda;
    err.push_back(Bratu1DProblem::kLambdaCritical - lf);
    umid.push_back(folds[0]->observables[0]);
    std::cout << std::setprecision(12) << "n = " << n << ": fold lambda = " << lf << ", error " << err.back()
              << ", u(1/2) = " << umid.back() << "\n";
    // the branch went round the fold and came back along the upper branch until u(1/2) > 4,
    // with lambda below the fold value all along
    EXPECT_EQ(r.code, StopCode::StopObservable) << r.reason;
    EXPECT_NEAR(rec.points.back().observables[0], 4.0, 1e-9);
    for (const auto& pt : rec.points) EXPECT_LE(pt.lambda, lf + 1e-12);
    bool upper = false;
    for (const auto& pt : rec.points) upper |= pt.observables[0] > 3.0 && pt.lambda < 2.0;
    EXPECT_TRUE(upper);
    EXPECT_GT(err.back(), 0.0);  // central differences approach lambda_c from below
  }
  for (size_t k = 0; k + 1 < err.size(); ++k) {
    const double order = std::log2(err[k] / err[k + 1]);
    std::cout << "  observed order " << order << "\n";
    EXPECT_NEAR(order, 2.0, 0.05);
  }
  EXPECT_NEAR(umid.back(), 1.1868421686, 1e-4);  // published u(1/2) at the fold
  EXPECT_LT(std::abs(umid.back() - 1.1868421686), std::abs(umid.front() - 1.1868421686) / 40);
}

// Q2 elements: the fold value behaves like an eigenvalue of the linearised problem, which Q2
// approximates to O(h^4) (twice the energy-norm order); observed 3.89, 3.95, 3.99 for n = 4..32,
// with the n = 32 fold 5.7e-7 above 6.8081244226, and max u there 1.3916618 against the
// published 1.39166121.
TEST(BratuFold, TwoDimensionalFoldConvergesToThePublishedValue) {
  std::vector<double> err, umax;
  std::vector<int> sizes = {4, 8, 16, 32};
  for (int n : sizes) {
    Bratu2DProblem p(n, 0.0);
    Continuation cont(p, bratu_fold_options("u_max", 2.0));
    test::RecordingObserver rec;
    cont.run(p.initial_guess(), rec);
    const auto folds = rec.of_kind(PointKind::Fold);
    ASSERT_EQ(folds.size(), 1u) << "n = " << n;
    err.push_back(folds[0]->lambda - Bratu2DProblem::kLambdaCritical);
    umax.push_back(folds[0]->observables[0]);
    std::cout << std::setprecision(12) << "n = " << n << ": fold lambda = " << folds[0]->lambda << ", error "
              << err.back() << ", max u = " << folds[0]->observables[0] << "\n";
  }
  for (size_t k = 0; k + 1 < err.size(); ++k) {
    EXPECT_GT(err[k], 0.0);
    const double order = std::log2(err[k] / err[k + 1]);
    std::cout << "  observed order " << order << "\n";
    EXPECT_NEAR(order, 4.0, 0.2);
  }
  EXPECT_LT(std::abs(err.back()), 1e-6);
  // max u at the fold: 2.1e-3, 1.4e-4, 8.8e-6, 5.5e-7 from the published value
  EXPECT_NEAR(umax.back(), 1.39166121, 2e-6);
  EXPECT_LT(std::abs(umax.back() - 1.39166121), std::abs(umax[1] - 1.39166121) / 100);
}

// The chord corrector (one factorisation per step while the residual falls by chord_rate per
// iteration) and block elimination of the bordered system (on J's factorisation, with its
// fallback at the fold itself) trace the same branch: the same located fold to the event
// tolerance; the chord corrector with fewer factorisations than Newton's.
TEST(BratuFold, ChordCorrectorAndBlockEliminationFindTheSameFold) {
  using C = CorrectorOptions::Method;
  struct Variant {
    const char* name;
    C corrector;
    bool block;
  };
  const Variant variants[] = {{"newton", C::Newton, false},
                              {"chord", C::Chord, false},
                              {"block", C::Newton, true},
                              {"chord+block", C::Chord, true},
                              {"chord+block+reuse", C::Chord, true}};
  double fold[5];
  long factorisations[5];
  for (int k = 0; k < 5; ++k) {
    Bratu1DProblem p(64, 0.0);
    ContinuationOptions o = bratu_fold_options("u_mid", 4.0);
    o.corrector.method = variants[k].corrector;
    o.corrector.block_elimination = variants[k].block;
    o.corrector.keep = false;
    o.corrector.anderson_depth = 0;  // the plain chord
    if (k == 4) {
      // factorisations kept across steps; tangents by iteration (no determinant: no branch points)
      o.corrector.keep = true;
      o.events.branch_points = false;
      o.step.target_iterations = 8;  // chord iterations cost a solve, not a factorisation
      o.corrector.max_iterations = 16;
    }
    Continuation cont(p, o);
    test::RecordingObserver rec;
    const auto r = cont.run(p.initial_guess(), rec);
    ASSERT_EQ(r.code, StopCode::StopObservable) << variants[k].name << ": " << r.reason;
    const auto folds = rec.of_kind(PointKind::Fold);
    ASSERT_EQ(folds.size(), 1u) << variants[k].name;
    fold[k] = folds[0]->lambda;
    factorisations[k] = r.factorisations;
    std::cout << variants[k].name << ": fold at " << std::setprecision(14) << fold[k] << ", " << r.points << " points, "
              << r.factorisations << " corrector factorisations\n";
    EXPECT_NEAR(fold[k], fold[0], 1e-11) << variants[k].name;
  }
  EXPECT_LT(factorisations[1], factorisations[0]);
  // kept across steps: fewer factorisations than the chord corrector that refactorises at each step
  EXPECT_LT(factorisations[4], factorisations[3]);
}
