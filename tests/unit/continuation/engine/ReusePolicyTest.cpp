// The factorisation reuse policy on synthetic sequences of what happens to the kept factorisation
// (the sequences the engine makes: a step, a rejected attempt, a located point's retry, a landing
// at the branch's end, a probe).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "continuation/engine/ReusePolicy.hpp"

using namespace keller;

namespace {

bool reusable_after(const std::vector<ReuseEvent>& events) {
  ReusePolicy p;
  for (ReuseEvent e : events) p.react(e);
  return p.reusable();
}

}  // namespace

TEST(ReusePolicy, NothingMadeNothingToReuse) { EXPECT_FALSE(ReusePolicy().reusable()); }

TEST(ReusePolicy, KeptWhereItBelongsToTheBranchNotToAnIterateFarOff) {
  using E = ReuseEvent;
  struct Case {
    std::string what;
    std::vector<ReuseEvent> events;
    bool reusable;
  };
  const Case cases[] = {
      {"the start's tangent factorised at the start", {E::Factorised}, true},
      {"a step corrected on it", {E::Factorised, E::Converged}, true},
      {"a step that renewed it at an iterate and converged", {E::Factorised, E::Factorised, E::Converged}, true},
      // its last factorisation may be an iterate's far off the branch: the retry factorises afresh
      {"a step that renewed it and diverged", {E::Factorised, E::Factorised, E::Diverged}, false},
      {"a step that diverged on it without renewing it", {E::Factorised, E::Converged, E::Diverged}, false},
      // the tangent of the retried, shorter step factorises at its point: kept again
      {"a diverged step, then the tangent of the next one", {E::Diverged, E::Factorised}, true},
      // a located point's chord that gave up on it, retried on a factorisation at its prediction
      {"a located point retried afresh", {E::Converged, E::Diverged, E::Factorised, E::Converged}, true},
      {"a step whose tangent failed on it", {E::Factorised, E::Converged, E::TangentFailed}, false},
      // the branch ends on a landed zero and the step made no factorisation: the settling
      // correction makes one (the sign of det there), which is then kept
      {"a landing at the branch's end", {E::Converged, E::SignWanted}, false},
      {"... settled by a correction", {E::Converged, E::SignWanted, E::Factorised, E::Converged}, true},
      {"a probe of the determinant's sign", {E::Diverged, E::Factorised}, true},
      {"a failed factorisation or adoption", {E::Factorised, E::Converged, E::Lost}, false},
      {"the start's row taken on a factorisation made at the start", {E::Diverged, E::Accepted}, true},
  };
  for (const Case& c : cases) EXPECT_EQ(reusable_after(c.events), c.reusable) << c.what;
}
