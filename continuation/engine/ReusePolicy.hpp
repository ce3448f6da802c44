// Whether the next correction may start on the kept factorisation (the chord's first iteration on
// it, under that correction's own row) instead of factorising at its prediction: one policy, a pure
// function of what happened to the factorisation (tested on synthetic sequences of events).
// KeptFactorisation reacts to its own factorisations and adoptions; the corrector says how each
// correction ended; the stepper says where the start takes its row, where a step's tangent failed
// and where the next correction must factorise. Nothing else decides.
#pragma once

namespace keller {

// What happens to the kept factorisation.
enum class ReuseEvent {
  Factorised,     // a factorisation or an adoption succeeded (at a point of the branch, a correction's
                  // iterate, or the point where the solve of the start made it)
  Lost,           // a factorisation or an adoption failed: nothing to start on
  Converged,      // a correction ended converged: its last factorisation lies close to the branch
  Diverged,       // a correction failed (or gave up on the kept factorisation): its last one may
                  // belong to an iterate far off the branch
  Accepted,       // a point of the branch (the start) took it under its own row
  TangentFailed,  // a step's tangent failed on it: the step is rejected and tried again shorter
  SignWanted,     // the branch ends on this step (it lands on a bound, or on a zero without having
                  // factorised): the next correction makes one (the sign of det at the branch's
                  // end, for branch points)
};

class ReusePolicy {
 public:
  // After e: whether the next correction may start on the factorisation.
  void react(ReuseEvent e);
  // (a factorisation usable under another row, block elimination, is needed besides:
  // KeptFactorisation::reusable)
  bool reusable() const { return reusable_; }

 private:
  bool reusable_ = false;  // nothing made yet
};

}  // namespace keller
