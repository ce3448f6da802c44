#include "continuation/engine/ReusePolicy.hpp"

namespace keller {

void ReusePolicy::react(ReuseEvent e) {
  switch (e) {
    // a factorisation made at a point the branch passes near, or at a converged point, is kept
    case ReuseEvent::Factorised:
    case ReuseEvent::Converged:
    case ReuseEvent::Accepted: reusable_ = true; return;
    // one that may belong to an iterate far off the branch, or none at all, is not; nor one the
    // next correction must replace to learn a determinant's sign
    case ReuseEvent::Lost:
    case ReuseEvent::Diverged:
    case ReuseEvent::TangentFailed:
    case ReuseEvent::SignWanted: reusable_ = false; return;
  }
}

}  // namespace keller
