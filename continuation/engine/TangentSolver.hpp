// Unit tangents of the branch: the solution (v, mu) of [J F_p; c^T d] (v, mu) = (0, 1), normalised in
// the arclength norm and oriented along the previous tangent. From the factorisation at hand; or,
// at a converged point whose J was not factorised there (a kept factorisation), by Richardson
// iteration on the exact tangent system at the point preconditioned by the kept factorisation
// and Anderson-accelerated (GMRES on this linear system), with J v by central differences; a
// factorisation at the point where that iteration does not converge.
#pragma once

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "continuation/engine/KeptFactorisation.hpp"

namespace keller {

struct Tangent {
  Vector tu;
  double tl = 0.0;
  int det_sign = 0;         // sign of det J where J was factorised at the point, else 0
  bool factorised = false;  // a factorisation was made for it
};

class TangentSolver {
 public:
  TangentSolver(Evaluator& ev, KeptFactorisation& kept, const ArclengthNorm& norm, const ContinuationOptions& options);

  // At a first point (u, lambda): J factorised there with the row (0, 1) (-J^-1 F_p, 1), or a
  // generic row where J is singular (a start on a fold); oriented so that the parameter moves
  // in options.direction.
  Status initial(const Vector& u, double lambda, Tangent& t);
  // At the converged point p under border row c: from the kept factorisation by iteration (when
  // kept and not refresh), else from a factorisation made at p. near: a point close to p whose
  // tangent starts the iteration (a bracket end of a located point), or null (it starts at zero).
  Status at_point(const BranchPoint& p, const Constraint& c, const Vector& tu_prev, double tl_prev, bool refresh,
                  Tangent& t, const BranchPoint* near = nullptr);
  // From the factorisation at hand (made wherever it was).
  Status from_factorisation(const Vector& tu_prev, double tl_prev, Tangent& t);
  // Solves spent on tangents by iteration.
  long iterations() const { return iterations_; }
  // The error an iteration's tangent is estimated to have: the length of its correction times
  // the factor by which the corrections fall (correction / previous, where that is below 1), the
  // correction itself where they do not fall or at the first (previous 0).
  static double error_left(double correction, double previous);
  // Whether a tangent (v, mu) of length size with that error (and mu_error in its parameter part)
  // is accurate enough: error within 1e-4 of size, and the sign of mu certain (mu_error below half
  // of |mu|) or, where mu is about as small as its error, error within 1e-6 of size.
  static bool accurate(double error, double size, double mu_error, double mu);

 private:
  // The tangent system at p solved by iteration on the kept factorisation; false where it does
  // not converge (t untouched).
  bool by_iteration(const BranchPoint& p, const Constraint& c, const Vector& tu_prev, double tl_prev, Tangent& t,
                    Status& st, const BranchPoint* near);
  // Normalises (v, mu) and orients it along (tu_prev, tl_prev) where given; the sign of det J
  // from mu and the bordered determinant.
  Status unit(Vector v, double mu, const Vector& tu_prev, double tl_prev, Tangent& t) const;
  Evaluator& ev_;
  KeptFactorisation& kept_;
  const ArclengthNorm& norm_;
  const ContinuationOptions& options_;
  long iterations_ = 0;
};

}  // namespace keller
