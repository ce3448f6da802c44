// An observable that is the smallest of several smooth functions (a margin to the nearest of many
// places, as an event curve's switch margin) is only piecewise smooth: where the smallest changes
// near its zero, Newton and the secant lose their speed there. A problem that knows the pieces
// offers them by deriving from this interface as well: which piece is smallest at a state, and
// the value and gradient of a given piece, each a function of the state alone (no piece is held
// between calls). The stepper locates such an observable's zero piece by piece
// (Continuation::locate_zero); the engine finds the interface in one place (pieces_of()).
#pragma once

#include "core/Problem.hpp"

namespace keller {

class ObservablePieces {
 public:
  virtual ~ObservablePieces() = default;
  // Whether the observable (an index into the problem's observables) is the smallest of pieces.
  virtual bool has_pieces(int observable) const = 0;
  // The piece smallest at u (at the parameters' present values), -1 where there is none.
  virtual Status smallest_piece(int observable, const Vector& u, int& piece) = 0;
  // A piece's value at u, and its gradient in u (at the parameters' present values).
  virtual Status piece_value(int observable, int piece, const Vector& u, double& value) = 0;
  virtual Status piece_gradient(int observable, int piece, const Vector& u, Vector& gradient) = 0;
};

// The problem's pieces; null where it offers none.
inline ObservablePieces* pieces_of(Problem& problem) { return dynamic_cast<ObservablePieces*>(&problem); }

}  // namespace keller
