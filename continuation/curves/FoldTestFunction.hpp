// The minimally augmented test function of a fold (Govaerts; as in LOCA and BifurcationKit):
// g from the bordered solve [J b; c^T 0] (v, g) = (0, 1), which vanishes exactly where J is
// singular whatever the borders b, c, as long as the bordered matrix is regular (Cramer:
// g = det J / det [J b; c^T 0]); v approximates the right null vector and w, from the adjoint
// [J^T c; b^T 0] (w, h) = (0, 1), the left one. Moving the borders to c = v / |v|, b = w / |w|
// keeps the bordered matrix regular as J changes (a step of inverse iteration).
#pragma once

#include "core/SparseLU.hpp"
#include "core/Status.hpp"
#include "core/Types.hpp"

namespace keller {

class FoldTestFunction {
 public:
  explicit FoldTestFunction(int n, SparseLUOptions lu = {});
  // Borders from a guess of the null vector (b = c = the guess, normalised); throws where it
  // vanishes or has the wrong size.
  void set_borders(const Vector& null_guess);
  // Factorises [J b; c^T 0] and solves for v, g and w.
  Status evaluate(const SparseMatrix& J);
  // Borders from the last evaluation's v and w; a failure where one vanished.
  Status update_borders();
  const Vector& v() const { return v_; }
  const Vector& w() const { return w_; }
  double g() const { return g_; }
  // g times the sign of det [J b; c^T 0]: the sign of det J whatever the borders (g's own sign flips
  // with det [J b; c^T 0] when the borders move), for a sign change counted between two points
  // evaluated with different borders.
  double signed_g() const { return g_ * det_sign_; }

 private:
  int n_;
  Vector b_, c_, v_, w_;
  double g_ = 0.0;
  int det_sign_ = 0;
  SparseLU lu_;
};

}  // namespace keller
