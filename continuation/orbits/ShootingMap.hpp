// The period map of B(u) du/dt = -F(u, lambda) on a frozen time grid, for shooting: Phi(u0, T,
// lambda) is the state after time T from u0 by keller's integrator (continuation/time: BDF2 with its
// backward Euler start, or SDIRK4) at the times s_k T of a fixed grid of fractions s_k, recorded from
// an adaptive run at the run's tolerance. With the grid frozen, Phi is a smooth function of (u0, T,
// lambda) and its derivatives are those of the discrete steps, exactly. Every implicit solve of a
// step (BDF2: one, SDIRK4: one per stage) reads B(U) R + F(U) = 0 with the rate R affine in U,
//   BDF2:   R = (c0 U + c1 u_(k-1) + c2 u_(k-2)) / h,   SDIRK4: R = K_i = (U_i - u_n - h sum_(j<i) a_ij K_j) / (h
//   gamma),
// with h = T (s_k - s_(k-1)); linearised it is A dU = B(U) (d of the rest) + (dT / T) (terms of h) - F_lambda dlambda
// with A = (dR/dU) B(U) + J(U) + B'(U)[.] R (where B depends on u, by GMRES with A's products by
// differences, preconditioned by the rest). The monodromy matrix M = dPhi/du0 is applied to a vector by one such pass;
// its eigenvalues are the Floquet multipliers of the discrete orbit (the trivial one is 1 up to the integrator's error:
// O(h^2) with BDF2, O(h^4) with SDIRK4).
#pragma once

#include <array>
#include <memory>
#include <vector>

#include "continuation/time/TimeIntegrator.hpp"
#include "core/Newton.hpp"
#include "core/Problem.hpp"
#include "core/SparseLU.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

// The steps of one period as fractions of it: 0 < s_1 < ... < s_m = 1, the step k ending at s_k T,
// and the method: BDF2 (the first two steps the integrator's backward Euler start) or SDIRK4.
struct OrbitGrid {
  std::vector<double> fractions;
  TimeOptions::Method method = TimeOptions::Method::Bdf2;
  // From the accepted times t_1 < ... < t_m of a run started at t0 (t_m - t0 is the period).
  // Throws std::invalid_argument where they do not increase or are too few (BDF2: three).
  static OrbitGrid from_times(double t0, const std::vector<double>& times,
                              TimeOptions::Method method = TimeOptions::Method::Bdf2);
  int steps() const { return static_cast<int>(fractions.size()); }
};

// The grid of an adaptive run (continuation/time, the method and error control of `options`) from
// u0 over one period: the steps evolve would take there, frozen for shooting. Throws std::runtime_error with
// the integrator's reason where the run does not reach the period.
OrbitGrid record_grid(Problem& problem, const Vector& u0, double period, const TimeOptions& options,
                      const NewtonOptions& newton = {}, const SparseLUOptions& lu = {});

struct ShootingOptions {
  // Each step's Newton solve: the map is only as smooth as its steps are converged, so tighter
  // than a time integration's (the residual relative to the problem's residual scale).
  NewtonOptions newton = tight_newton();
  SparseLUOptions lu;
  // The linearised passes keep the factorisations of the steps' matrices while they take at most
  // this many bytes together (SparseLU's numeric size; dense LUs for problems of up to
  // kDenseSize unknowns); a step beyond it is refactorised in every pass.
  double memory_budget = 2e9;
  // How a linearised solve A dU = rhs is done. Factorised: A assembled and factorised at every
  // implicit solve of the period (exact; a factorisation per solve and Newton iteration, for small
  // problems). Preconditioned: GMRES with A dU by central differences of the solve's residual
  // (B'[dU] R included), preconditioned by factorisations of A made at a few solves of the period (a
  // new one where the coefficient dR/dU has moved by 30% since the last, as evolve's chord does, or
  // kAnchorSpan solves on: two SDIRK4 steps, ten BDF2 steps). Auto:
  // Factorised up to kFactorisedSize unknowns where B is constant and the period's factorisations
  // fit in memory_budget together (measured on the first), else Preconditioned. Where B varies
  // every solve is a GMRES anyway (the B' term), and a factorisation of each solve's matrix, made
  // again at every Newton iteration, costs more than the iterations it saves (the collapsible
  // docs/periodic_orbits.md's coarse moving-mesh problem, 1,944 unknowns: 3.8 inner iterations a solve against 6.6, but
  // 1,100 factorisations per iteration; a Newton iteration of 10 passes took 122 s against 40 s).
  enum class Linearisation { Auto, Factorised, Preconditioned };
  Linearisation linearisation = Linearisation::Auto;
  static constexpr int kFactorisedSize = 2000;
  // The linearisation Auto takes (Factorised or Preconditioned; others as asked) for n unknowns,
  // B varying or not, and `solves` factorisations of `bytes` each against the budget (bytes < 0:
  // not measured, taken to fit).
  static Linearisation linearisation_for(Linearisation asked, int n, bool mass_varies, double bytes, long solves,
                                         double budget);
  // On docs/periodic_orbits.md's FSI problem (1,944 unknowns, SDIRK4, 515 solves a period; the first two
  // orbits, 61 passes): spans of 50, 20, 10 and 5 solves took 196k, 162k, 142k and 119k inner
  // iterations for 1719, 1867, 2225 and 2786 factorisations, and 10 the least time in the passes
  // (21% below 50's).
  static constexpr int kAnchorSpan = 10;
  // Preconditioned: the anchors' factorisations serve on from one integrate to the next on the same
  // grid (method and fractions) while the start u0, the period and the parameters have each moved by
  // at most kAnchorDrift of their size (anchor_drift) since the anchors were factorised; the Newton
  // iterations of one correction move them far less. They only precondition: a staler anchor costs
  // GMRES iterations, never accuracy. On docs/periodic_orbits.md's FSI problem (four orbits): 1,030 of
  // 4,505 factorisations saved for the same inner iterations (316,859 against 316,015); at 1e-2 the
  // anchors served on from one orbit to the next (the parameter 0.5% on) and cost 13% more inner iterations.
  static constexpr double kAnchorDrift = 1e-3;
  // The largest of |b - a|_inf / max(1, |a|_inf) over the pairs (a, b): u0, the period, the
  // parameters. Infinite where the sizes differ.
  static double anchor_drift(const Vector& u0_then, const Vector& u0_now, const std::vector<double>& then,
                             const std::vector<double>& now);
  static bool keeps_anchors(double drift) { return drift <= kAnchorDrift; }
  static NewtonOptions tight_newton();
  // The sparse LU of a problem of n unknowns: UMFPACK where `asked` is Auto and n <= kUmfpackSize,
  // else `asked`. A period takes thousands of solves of small matrices, and a MUMPS call has a
  // fixed cost of tens of microseconds (its Fortran interface), more than a small solve itself.
  static constexpr int kUmfpackSize = 2000;
  // The forward steps' LU options (integrate, record_grid): `lu` without iterative refinement. The
  // steps' Newton is a chord iteration on a kept factorisation, whose error is the kept matrix's
  // age, not the solve's rounding; refinement against the kept matrix bought nothing there (the
  // FSI problem of docs/periodic_orbits.md, its first two orbits: 42,653 chord iterations without
  // it against 42,751 with 2 steps) and took three quarters of the forward time (27.8 s against
  // 112.8 s). Newton now skips it on every chord iteration (NewtonSolver::refinement_steps); this
  // also drops it on a fresh factorisation's solves, whose error the next chord iterations correct
  // as well: the first two orbits' forward time 28.3 s with it against 32.3 s with Newton's policy
  // alone (the two runs side by side). The linearised passes keep `lu`'s refinement where they
  // solve with a solve's own matrix.
  static SparseLUOptions chord_lu(SparseLUOptions lu);
  static SparseLUOptions::Backend backend_for(SparseLUOptions::Backend asked, int n);
};

class ShootingMap {
 public:
  // Problems of up to this many unknowns factorise their step matrices dense.
  static constexpr int kDenseSize = 64;

  // parameter: the index of lambda in problem.parameters() (-1: no parameter derivative). Throws
  // NoTimeForm where the problem has no mass matrix.
  ShootingMap(Problem& problem, int parameter, ShootingOptions options = {});
  ~ShootingMap();
  ShootingMap(const ShootingMap&) = delete;
  ShootingMap& operator=(const ShootingMap&) = delete;

  Problem& problem() { return problem_; }
  int parameter() const { return parameter_; }
  // Phi(u0, period) at the parameters' present values: integrates on the grid, keeps the states
  // and assembles the steps' matrices for the linearised passes. A failed step is a status.
  Status integrate(const Vector& u0, double period, const OrbitGrid& grid);
  // u_0 ... u_m of the last integrate (u_m = Phi).
  const std::vector<Vector>& states() const { return states_; }
  const Vector& end() const { return states_.back(); }
  double period() const { return period_; }
  // du/dt at the end of the period: the last solve's rate (BDF2: r_m; SDIRK4: K_5 of the last step).
  Vector end_rate() const;
  // dPhi = M v0 + (dPhi/dT) dT + (dPhi/dlambda) dlambda at the last integrate's (u0, T, lambda).
  // tolerance: where a solve is a GMRES (Preconditioned, or B varying), its residual relative to
  // its right-hand side, clamped to [kTightPass, 1e-2]. A Newton step's GMRES asks
  // no more than its forcing term of the products (OrbitCorrector::pass_tolerance); multipliers
  // take the tightest. With every solve's matrix factorised and B constant a pass is exact anyway.
  static constexpr double kTightPass = 1e-12;
  Status linearised(const Vector& v0, double dT, double dlambda, Vector& out, double tolerance = kTightPass);

  // The last integrate's largest local error estimate, in the integrator's weighted norm at
  // (rtol, atol) over its differential unknowns (continuation/time): SDIRK4's embedded estimate
  // h sum_j (b_j - b_hat_j) K_j of every step, from the stages' rates. At most 1: every step of the
  // grid would pass the error test an adaptive run applies, on this orbit. BDF2: +inf (no estimate
  // kept).
  double step_error(double rtol, double atol) const;

  // Whether the last integrate's passes are exact (every solve's matrix factorised, B constant)
  // rather than GMRES to the tolerance asked.
  bool exact_passes() const { return !preconditioned_ && !mass_varies_; }

  struct Counts {
    long steps = 0;              // forward steps integrated
    long newton_iterations = 0;  // of the forward steps
    long factorisations = 0;     // forward (the integrator's) and linearised (the steps' own)
    long passes = 0;             // linearised passes
    long inner_iterations = 0;   // products A x of the linearised solves' GMRES (their guesses' included)
    double forward_seconds = 0, linearised_seconds = 0;
  };
  const Counts& counts() const { return counts_; }

 private:
  struct Solve;
  struct Anchor;
  Status assemble(Solve& solve);
  Status factorise(Solve& solve);
  // factorisation_bytes_, from a factorisation of the first solve's matrix
  Status measure_factorisation();
  // Preconditioned: the anchors' factorisations, and the solve's residual G(U) = B(U) R(U) + F(U)
  Status anchor_lu(int anchor, SparseLU*& lu);
  // the last integrate's anchors where they serve on at (u0, period) on grid (else none, and
  // anchor_origin_ renewed)
  std::vector<Anchor> reusable_anchors(const Vector& u0, double period, const OrbitGrid& grid);
  Status solve_residual(const Solve& solve, const Vector& U, Vector& G);
  // B(U) x at the solve's state
  Status apply_mass(const Solve& solve, const Vector& x, Vector& out);
  // dU = A^-1 rhs for a solve (with the B' term where B varies)
  // guess: a first approximation of dU (empty: none), taken where it leaves less of rhs to solve for
  Status solve_linearised(Solve& solve, const Vector& rhs, Vector& dU, double tolerance, const Vector& guess);
  // the right-hand side's parameter term: -F_lambda(U) dlambda (F_lambda kept within the memory budget)
  Status parameter_term(Solve& solve, double dlambda, Vector& rhs);
  const SparseMatrix& mass(const Solve& solve) const;

  Problem& problem_;
  int parameter_;
  ShootingOptions options_;
  double period_ = 0.0;
  TimeOptions::Method method_ = TimeOptions::Method::Bdf2;
  bool mass_varies_ = false;  // B depends on u (then B'[v] R enters every linearised solve)
  SparseMatrix mass_;         // B where it is constant
  std::vector<Vector> states_;
  std::vector<Solve> solves_;  // in order: one per BDF2 step, kStages per SDIRK4 step
  std::vector<double> steps_;  // the step lengths h_k
  double stored_bytes_ = 0.0;
  double factorisation_bytes_ = -1.0;    // one factorisation's numeric size (-1: not measured yet)
  std::unique_ptr<SparseLU> shared_lu_;  // for the solves whose factorisations are not kept
  int shared_anchor_ = -1;               // Preconditioned: the anchor shared_lu_ holds
  bool preconditioned_ = false;
  std::vector<Anchor> anchors_;
  // where the anchors were factorised: u0, then the period and the parameters, and the grid
  struct AnchorOrigin {
    Vector u0;
    std::vector<double> scalars;
    std::vector<double> fractions;
    TimeOptions::Method method = TimeOptions::Method::Bdf2;
  } anchor_origin_;
  Counts counts_;
};

}  // namespace keller
