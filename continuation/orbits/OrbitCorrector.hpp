// Newton-Krylov shooting for a periodic orbit of B(u) du/dt = -F(u, lambda): the unknowns are a
// point u0 of the orbit, its period T and (on a branch) lambda; the equations
//   Phi(u0, T, lambda) - u0 = 0                 (periodicity, ShootingMap on a frozen grid)
//   <u0 - u_ref, n> = 0                          (phase: u0 on the hyperplane through u_ref normal to n)
//   <a_u, u0 - z_u> + a_T (T - z_T) + a_l (lambda - z_l) = 0   (a row fixing lambda or the arclength)
// The Newton matrix [M - I, T Phi_T, Phi_l; n^T, 0, 0; a_u^T, a_T T, a_l] (the period's unknown is
// its relative change dT / T) is never formed: GMRES (core/Gmres.hpp) applies it by one linearised
// pass per iteration, the T and lambda columns inside the pass with M's (a pass is linear in
// (v0, dT, dlambda)). M's eigenvalues are the Floquet
// multipliers: those of strongly damped modes are near 0, so M - I clusters them at -1 and GMRES
// pays about one iteration per multiplier away from 0 (Sanchez, Net, Garcia-Archilla and Simo 2004
// for Navier-Stokes). Its right preconditioner (BorderedDeflation) takes away those a neighbouring
// orbit has computed, where given (OrbitDeflation), and the border's directions: the period's
// column T f(Phi), lambda's (one pass a correction), the phase row and the closing row, by block
// elimination. The forcing term follows Eisenstat and Walker (1996, choice 2).
#pragma once

#include <functional>
#include <string>

#include "continuation/orbits/OrbitDeflation.hpp"
#include "continuation/orbits/ShootingMap.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

struct OrbitCorrectorOptions {
  int max_iterations = 12;  // Newton iterations
  // Converged when |Phi - u0|_inf <= tolerance max(|u0|_inf, 1) and the last update moved u0 by at
  // most that and T by at most tolerance T.
  double tolerance = 1e-9;
  int krylov_iterations = 60;  // GMRES iterations per Newton step
  // Called after every residual: the Newton iteration, |Phi - u0|_inf, the GMRES iterations so far
  // (a long correction's progress; empty: none).
  std::function<void(int iteration, double residual, long krylov_iterations)> progress;
};

// The linear row that closes the system: lambda fixed (a_u = 0, a_T = 0, a_l = 1), or the
// pseudo-arclength condition of a continuation step. Empty a_u: zero.
struct OrbitRow {
  Vector a_u;
  double a_T = 0.0, a_lambda = 1.0;
  Vector z_u;  // the point the row is measured from (empty: zero)
  double z_T = 0.0, z_lambda = 0.0;
};

struct OrbitCorrection {
  Status status;
  int iterations = 0;  // Newton iterations
  // GMRES iterations, each a linearised pass (on a branch one more a correction: lambda's column in
  // the preconditioner)
  long krylov_iterations = 0;
  double residual = 0.0;  // |Phi - u0|_inf at the end
};

class OrbitCorrector {
 public:
  // deflation: from a neighbouring orbit's multipliers, inside GMRES's right preconditioner
  // (BorderedDeflation; null or empty: the border alone)
  explicit OrbitCorrector(ShootingMap& map, OrbitCorrectorOptions options = {},
                          const OrbitDeflation* deflation = nullptr)
      : map_(map), options_(options), deflation_(deflation) {}

  // Corrects (u0, T) in place on the grid, with the phase hyperplane through u_ref normal to n; with
  // free_lambda also lambda (the map's parameter, which must exist), closed by `row`; without it
  // lambda stays at the problem's present value and the row is not used. On return the map holds
  // the integration of the final (u0, T, lambda), and the problem's parameter is lambda.
  OrbitCorrection correct(Vector& u0, double& T, double& lambda, bool free_lambda, const OrbitGrid& grid,
                          const Vector& u_ref, const Vector& n, const OrbitRow& row = {});

  // The tolerance of the linearised passes (ShootingMap::linearised) of a Newton step whose GMRES
  // is asked for a relative residual eta: kPassShare of eta, at least kTightPass. A pass's error is
  // its solves' added up over the period (62 tolerances in ShootingMapTest), and GMRES must still
  // reach eta with it. On docs/periodic_orbits.md's 642-unknown FSI problem (its first two orbits) a share of
  // 1e-4 took 42% fewer inner iterations and 41% less time in the passes than 1e-12 throughout,
  // with the same Newton and GMRES iterations; 1e-2 took 16 Newton iterations against 10.
  static constexpr double kPassShare = 1e-4;
  static double pass_tolerance(double eta);
  // Newton's stop, on quantities relative to the tolerance's scales: the residual at most
  // `tolerance`, and the iterate's error too. The error is the last update where that was small
  // enough; else the next update, estimated as the last one times the residuals' contraction theta
  // = |R_k| / |R_(k-1)| (Deuflhard's a posteriori estimate, |x_k - x*| ~ theta |dx_(k-1)| for Newton),
  // trusted where theta <= kTrustedContraction. It saves the iteration that would only confirm a
  // converged orbit (on docs/periodic_orbits.md's FSI problem, one in five: a period's integration
  // and ten passes).
  static constexpr double kTrustedContraction = 0.1;
  static bool converged(double residual, double last_update, double contraction, double tolerance);

 private:
  ShootingMap& map_;
  OrbitCorrectorOptions options_;
  const OrbitDeflation* deflation_;
};

}  // namespace keller
