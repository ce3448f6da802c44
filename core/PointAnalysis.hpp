// An analysis of each converged point of a branch beyond the problem's own observables: the
// linear stability spectrum (stability/) is one. The continuation engine sees only this
// interface: columns for the branch table, an integer whose change between two points is an
// event (the number of unstable eigenvalues), a continuous function that crosses zero where that
// integer changes (the real part of the critical eigenvalue), and what is critical there.
#pragma once

#include <string>
#include <vector>

#include "core/Problem.hpp"
#include "core/SparseLU.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

struct PointAnalysisResult {
  std::vector<double> columns;  // one value per PointAnalysis::column_names() (NaN: not available)
  int count = -1;               // e.g. eigenvalues with Re(sigma) < 0
  double locator = 0.0;         // e.g. Re(sigma) of the eigenvalue nearest the imaginary axis
  double critical_imag = 0.0;   // its imaginary part (0: real)
  // How many of the values counted equal the critical one (to 1e-6 (1 + |value|)): 2 where a double
  // eigenvalue (two modes of a symmetric domain) crosses, so that a located crossing changes the
  // count by that many.
  int critical_multiplicity = 1;
  Vector critical_re, critical_im;  // its eigenvector (empty when not computed)
  std::string note;                 // what the caller should tell the user of this analysis (empty: nothing)
  // How much the analysis computed (e.g. eigenvalues over all shifts); where it grew since an
  // earlier point, that point's count may have missed what the wider analysis sees.
  int width = 0;
};

class PointAnalysis {
 public:
  virtual ~PointAnalysis() = default;
  virtual std::vector<std::string> column_names() const = 0;
  // What `count` counts, for messages ("unstable eigenvalues").
  virtual std::string count_name() const = 0;
  // Analyses the converged solution u of `problem` at its current parameter values.
  // `factorised_j`, when not null, holds a factorisation of J at exactly this u and these
  // parameters that the caller made anyway (the continuation's, for the tangent): an analysis
  // that needs J's factorisation uses it instead of making its own.
  virtual Status analyse(Problem& problem, const Vector& u, PointAnalysisResult& out,
                         SparseLU* factorised_j = nullptr) = 0;
  // Analyse every N-th accepted point (and located points when N = 1; with N > 1 a change is
  // bracketed by analysing points in between).
  virtual int every() const { return 1; }
  // Computes more from now on (a count changed without anything crossing: what it counts left the
  // set it computes); false where it cannot.
  virtual bool widen() { return false; }
  // Whether analyse() would factorise J itself (so a caller about to analyse a point gains by
  // factorising J there first and passing it).
  virtual bool uses_j_factorisation() const { return false; }
};

}  // namespace keller
