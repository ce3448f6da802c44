// Bracketing by bisection (continuation/events/Bracket) on a given sequence.
#include <gtest/gtest.h>

#include <vector>

#include "continuation/events/Bracket.hpp"

using namespace keller;

// Bisection finds the adjacent pair where a property first differs from its first value, with
// about log2(n) evaluations; a failed evaluation gives nothing.
TEST(Bracket, BisectionFindsTheChange) {
  const std::vector<int> counts = {0, 0, 0, 0, 0, 1, 1, 1, 1, 1, 1};
  int evaluations = 0;
  const auto pair = bisect_change(counts.size(), 0, [&](size_t i) {
    ++evaluations;
    return counts[i];
  });
  ASSERT_TRUE(pair);
  EXPECT_EQ(pair->first, 4u);
  EXPECT_EQ(pair->second, 5u);
  EXPECT_LE(evaluations, 4);
  EXPECT_FALSE(bisect_change(counts.size(), 0, [](size_t) { return -1; }));
  const auto adjacent = bisect_change(2, 0, [](size_t) { return -1; });  // nothing to evaluate
  ASSERT_TRUE(adjacent);
  EXPECT_EQ(adjacent->second, 1u);
}
