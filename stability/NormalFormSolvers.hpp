// The linear algebra of the normal forms (stability/NormalForms.hpp), shared by the steady points'
// (NormalForms.cpp: folds, cusps, branch points) and those that need the time-dependent form
// (TimeFormNormalForms.cpp: Hopf, fold-Hopf and Bogdanov-Takens points): null and singular vectors
// by inverse iteration, GMRES on J's real factorisation for J + i s B (the first choice at a Hopf
// point), J + i s B factorised in its real block form, and GMRES on that factorisation deflated of
// a Hopf point's critical mode. Internal to keller_stability.
#pragma once

#include <chrono>
#include <complex>

#include <Eigen/Core>

#include "core/HigherDerivatives.hpp"
#include "core/Problem.hpp"
#include "core/SparseLU.hpp"
#include "stability/NormalForms.hpp"

namespace keller::normal_forms {

using Complex = std::complex<double>;
using ComplexVector = Eigen::VectorXcd;
using Direction = HigherDerivatives::Direction;
using ComplexDirection = HigherDerivatives::ComplexDirection;

double seconds_since(std::chrono::steady_clock::time_point t0);
// A start for inverse iteration with no guess: deterministic and in general position (not
// orthogonal to a symmetric or antisymmetric mode).
Vector generic_start(int n);
// Factorises J; a matrix singular to working precision (a point located exactly) gets a shift of
// 1e-12 of its largest entry, which moves its null vectors by that much. count: the factorisations.
Status factorise(SparseLU& lu, const SparseMatrix& J, long& count);
// J's null vector (transpose: its left null vector) by inverse iteration from `start`, until the
// direction changes by less than 1e-10, at most 100 solves (as the branch switcher's: slow modes
// near zero separate slowly).
Status null_vector(SparseLU& lu, Vector start, bool transpose, Vector& out);
// J's right (transpose: left) singular vector of its smallest singular value, by inverse iteration
// on J^T J (J J^T): it converges where the eigenvalues nearest zero are a complex pair or a Jordan
// block (a Bogdanov-Takens point, located where they are +-i omega with omega -> 0).
Status smallest_singular_vector(SparseLU& lu, Vector start, bool transpose, Vector& out);
// out := J^-1 rhs, with rhs first made orthogonal to psi (J's range) and the result to phi.
Status solve_bordered(SparseLU& lu, const Vector& phi, const Vector& psi, Vector rhs, Vector& out);
Status jacobian(Problem& problem, const Vector& u, SparseMatrix& J);
// J and B at u, B = I for a problem without a time-dependent form
Status jacobian_and_mass(Problem& problem, const Vector& u, SparseMatrix& J, SparseMatrix& B);
// A normal form of `kind` begun: out emptied and named, J and B at u
Status begin(Problem& problem, const Vector& u, NormalForm::Kind kind, const char* type, NormalForm& out,
             SparseMatrix& J, SparseMatrix& B);
// How the derivatives were taken, their count and time, into out.
void record(const HigherDerivatives& d, NormalForm& out);
// M v for a real M and a complex v
ComplexVector times(const SparseMatrix& M, const ComplexVector& v);

// J + i s B, factorised as the real matrix [J, -s B; s B, J] (interleaved) by the real sparse LU (MUMPS where the
// options pick it: on a coupled problem of 50,000 unknowns 2.8 times faster than UMFPACK's complex LU);
// its transpose is the block form of (J + i s B)^H.
class ShiftedLU {
 public:
  // one symbolic analysis, by METIS (the `best` ordering's search would cost more than the
  // factorisations it speeds up), kept for a second shift
  explicit ShiftedLU(SparseLUOptions options) : lu_(with_metis(options)) {}
  static SparseLUOptions with_metis(SparseLUOptions o) {
    o.ordering = SparseLUOptions::Ordering::Metis;
    return o;
  }
  Status factorize(const SparseMatrix& J, const SparseMatrix& B, double s) {
    // unknowns interleaved (Re x_i, Im x_i): the matrix is J's pattern with 2 x 2 blocks, which the
    // ordering treats as J's (the two halves one after the other fill in several times more)
    n_ = static_cast<int>(J.rows());
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(static_cast<size_t>(2 * J.nonZeros() + 2 * B.nonZeros()));
    for (int k = 0; k < J.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(J, k); it; ++it) {
        t.emplace_back(2 * it.row(), 2 * it.col(), it.value());
        t.emplace_back(2 * it.row() + 1, 2 * it.col() + 1, it.value());
      }
    for (int k = 0; k < B.outerSize(); ++k)
      for (SparseMatrix::InnerIterator it(B, k); it; ++it) {
        t.emplace_back(2 * it.row(), 2 * it.col() + 1, -s * it.value());
        t.emplace_back(2 * it.row() + 1, 2 * it.col(), s * it.value());
      }
    SparseMatrix M(2 * n_, 2 * n_);
    M.setFromTriplets(t.begin(), t.end());
    M.makeCompressed();
    return lu_.factorize(M);
  }
  // (J + i s B) x = b, or (J + i s B)^H x = b; refinement_steps as SparseLU::solve's (0: a plain
  // solve, about a fifth of a refined one, where an iteration corrects its errors anyway)
  Status solve(const ComplexVector& b, ComplexVector& x, bool adjoint = false, int refinement_steps = -1) {
    Vector rhs(2 * n_), y;
    for (int i = 0; i < n_; ++i) {
      rhs[2 * i] = b[i].real();
      rhs[2 * i + 1] = b[i].imag();
    }
    Status st = lu_.solve(rhs, y, adjoint, refinement_steps);
    if (!st.is_ok()) return st;
    x.resize(n_);
    for (int i = 0; i < n_; ++i) x[i] = Complex(y[2 * i], y[2 * i + 1]);
    return {};
  }

 private:
  SparseLU lu_;
  int n_ = 0;
};

// (J + i s B) x = b for s != omega by GMRES, preconditioned by the factorisation of J + i omega B
// at the Hopf point, deflated of its critical mode: with B q its image and p^H B q = 1,
//   P v = (I - q p^H B) lu1^-1 (v - B q p^H v) + q p^H v / (i (s - omega)),
// exact on q ((J + i s B) q = i (s - omega) B q) and, on another mode of J phi = sigma B phi,
// (J + i s B) P = (sigma + i s) / (sigma + i omega): near 1 but for the modes within a few omega
// of the pair, GMRES's outliers. Used where RealLUShiftSolver (below) did not converge and lu1 was
// made: h20 (s = 2 omega) then costs solves on lu1 instead of a factorisation of its own (at the
// Hopf point of docs/normal_forms.md's cost table, measured when lu1 was always made: 28
// iterations, 0.44 s against 0.76 s). GMRES's residual
// estimate below 1e-12 |b|, the residual of the result checked below 1e-10 |b|; a solve that does
// not get there in max_iterations (NormalForms' krylov_iterations) reports -1 and its caller
// factorises instead.
class DeflatedShiftSolver {
 public:
  DeflatedShiftSolver(const SparseMatrix& J, const SparseMatrix& B, ShiftedLU& lu1, const ComplexVector& q,
                      const ComplexVector& p, double omega, int max_iterations)
      : J_(J), B_(B), lu1_(lu1), q_(q), p_(p), omega_(omega), max_iterations_(max_iterations) {
    Bq_ = times(B, q);
    Btp_ = times(SparseMatrix(B.transpose()), p);  // p^H B x = (B^T p)^H x, B real
  }
  // iterations, -1 where not solved (then the caller factorises)
  int solve(double s, const ComplexVector& b, ComplexVector& x) const;

 private:
  static constexpr double kTolerance = 1e-12;  // of GMRES's residual estimate
  static constexpr double kCheck = 1e-10;      // of the residual computed from the result
  const SparseMatrix& J_;
  const SparseMatrix& B_;
  ShiftedLU& lu1_;
  ComplexVector q_, p_, Bq_, Btp_;
  double omega_;
  int max_iterations_;
};

// Solves with J + i s B (adjoint: its conjugate transpose J^T - i s B^T) by GMRES right-
// preconditioned by J's real factorisation, the real and imaginary parts by plain solves. On a
// mode J phi = -mu B phi (growth rate mu) the preconditioned operator is 1 - i s / mu: 1 on B's
// null space and near 1 on the modes much faster than s; each mode within a few s of 0 costs
// about an iteration. At the Hopf point of docs/normal_forms.md's cost table (16,264 unknowns),
// 41 eigenvalues lie within 2.6 omega of 0: p took 33 iterations and h20 53, 8 ms each (5.4 ms
// of it the solve of both parts at once, SparseLU::solve_columns; two solves one after the other
// took 9 ms), against a complex factorisation at 5 to 10 times J's. A solve that does not
// converge within max_iterations reports -1, and the caller factorises J + i omega B.
class RealLUShiftSolver {
 public:
  RealLUShiftSolver(const SparseMatrix& J, const SparseMatrix& B, SparseLU& lu, int max_iterations)
      : J_(J),
        B_(B),
        Jt_(J.transpose()),
        Bt_(B.transpose()),
        lu_(lu),
        max_iterations_(max_iterations),
        norm_J_(J.norm()),
        norm_B_(B.norm()) {}
  // (J + i s B) x = b or (J + i s B)^H x = b: the iterations, -1 where not solved (GMRES's
  // residual estimate below 1e-12 |b|, the computed one checked below 1e-10 |b|)
  int solve(double s, const ComplexVector& b, ComplexVector& x, bool adjoint = false) const;
  // The null vector of A = J + i s B (adjoint: of A^H) with c^H x = 1, from the bordered system
  // [A, border; c^H, 0] [x; mu] = [0; 1], preconditioned by the bordered J (two solves with J per
  // step): regular where c is not orthogonal to the null vector and `border` not in A's range.
  // Where s is off the eigenvalue by delta, mu is of delta's order and x is the nearest mode's.
  int null_vector(double s, const ComplexVector& border, const ComplexVector& c, ComplexVector& x, bool adjoint) const;

 private:
  static constexpr double kTolerance = 1e-12;
  static constexpr double kCheck = 1e-10;
  ComplexVector apply(double s, const ComplexVector& v, bool adjoint) const;  // A v or A^H v
  // J^-1 v or J^-T v, plain solves; an error is kept in failed_ and gives zero
  ComplexVector precondition(const ComplexVector& v, bool adjoint) const;
  const SparseMatrix& J_;
  const SparseMatrix& B_;
  SparseMatrix Jt_, Bt_;
  SparseLU& lu_;
  int max_iterations_;
  double norm_J_, norm_B_;  // Frobenius norms
  mutable Status failed_;
};

// The critical pair at a Hopf point on J's real factorisation (RealLUShiftSolver): q and p by the
// bordered systems at omega, omega then refined by the Rayleigh quotient p^H J q / p^H B q, until
// it changes by less than 1e-12 of itself (two rounds from a spectrum's eigenvector), at most 4.
// iterations: GMRES's in all, -1 where a solve did not converge (q, p undefined: the caller takes
// critical_pair on a complex factorisation).
Status critical_pair_on_real_lu(const RealLUShiftSolver& solver, const SparseMatrix& J, const SparseMatrix& B,
                                const Eigen::VectorXcd* guess, double& omega, ComplexVector& q, ComplexVector& p,
                                int& iterations);

// The critical pair at a Hopf point on lu1, the factorisation of J + i omega B: q with (J + i
// omega B) q = 0 by inverse iteration from the guess (whichever of the pair it is: the one J + i
// omega B nearly annuls) or a generic start, p with (J + i omega B)^H p = 0, both of unit norm;
// omega refined by the Rayleigh quotient sigma = p^H J q / p^H B q = -i omega.
Status critical_pair(const SparseMatrix& J, const SparseMatrix& B, ShiftedLU& lu1, const Eigen::VectorXcd* guess,
                     double& omega, ComplexVector& q, ComplexVector& p);

}  // namespace keller::normal_forms
