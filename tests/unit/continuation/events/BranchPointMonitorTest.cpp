// The branch-point monitor (continuation/events/BranchPointMonitor) from given determinant signs.
#include <gtest/gtest.h>

#include <map>
#include <optional>
#include <utility>

#include "continuation/events/BranchPointMonitor.hpp"
#include "support/SyntheticPoints.hpp"

using namespace keller;
using keller::test::point;

namespace {

// A branch of points s = 0, 1, 2, ... whose determinant sign is +1 before s = crossing and -1 after.
struct SignedBranch {
  double crossing;
  std::map<double, int> probed;  // s -> sign, the probes made
  BranchPoint at(double s, bool sampled) const {
    BranchPoint p = point(s, s, 1.0, {});
    p.bordered_det_sign = sampled ? sign(s) : 0;
    return p;
  }
  int sign(double s) const { return s < crossing ? 1 : -1; }
  int probe(BranchPoint& p) {
    probed[p.s] = sign(p.s);
    p.bordered_det_sign = sign(p.s);
    return p.bordered_det_sign;
  }
};

}  // namespace

// The branch-point monitor from given signs: a change between two signs a few rows apart is
// narrowed to one step by probing the rows in between (bisection); a sign from an iterate of a
// step (not exact at its point) starts the bracket one row earlier.
TEST(BranchPointMonitor, ASignChangeIsBracketedByProbingTheRowsBetween) {
  SignedBranch b{6.5, {}};
  BranchPointMonitor m;
  m.restart(b.at(0, true));
  auto probe = [&](BranchPoint& p) { return b.probe(p); };
  std::optional<std::pair<BranchPoint, BranchPoint>> change;
  for (int s = 1; s <= 9 && !change; ++s) {
    const bool sampled = s == 3 || s == 9;  // factorisations at rows 3 and 9 only
    change = m.accepted(b.at(s, sampled), false, probe);
  }
  ASSERT_TRUE(change);
  EXPECT_EQ(change->first.s, 6.0);
  EXPECT_EQ(change->second.s, 7.0);
  EXPECT_EQ(change->first.bordered_det_sign, 1);
  EXPECT_EQ(change->second.bordered_det_sign, -1);
  // the bracket started at row 2 (row 3's sign was an iterate's) and probed about log2(8) rows
  EXPECT_LE(b.probed.size(), 3u);
  for (const auto& [s, sign] : b.probed) EXPECT_GT(s, 2.0);
}

// Without a sign for kBranchPointProbeRows rows (a chord that never renews), one is probed; and at
// the branch's last point.
TEST(BranchPointMonitor, ProbesAfterTooManyRowsWithoutASign) {
  SignedBranch b{100.0, {}};
  BranchPointMonitor m;
  m.restart(b.at(0, true));
  int probes = 0;
  for (int s = 1; s <= 3 * kBranchPointProbeRows; ++s) {
    BranchPoint p = b.at(s, false);
    if (m.needs_probe(p, false)) {
      ++probes;
      b.probe(p);
    }
    EXPECT_FALSE(m.accepted(p, true, [&](BranchPoint& q) { return b.probe(q); }));
  }
  EXPECT_EQ(probes, 3);
  EXPECT_TRUE(m.needs_probe(b.at(31, false), true));  // the last point
  EXPECT_FALSE(m.needs_probe(b.at(31, true), true));  // has its own sign
}

// Every step signed (no kept factorisation): the bracket is the step itself, nothing probed.
TEST(BranchPointMonitor, EveryStepSignedNeedsNoProbe) {
  SignedBranch b{4.5, {}};
  BranchPointMonitor m;
  m.restart(b.at(0, true));
  std::optional<std::pair<BranchPoint, BranchPoint>> change;
  for (int s = 1; s <= 6 && !change; ++s)
    change = m.accepted(b.at(s, true), true, [&](BranchPoint& q) { return b.probe(q); });
  ASSERT_TRUE(change);
  EXPECT_EQ(change->first.s, 4.0);
  EXPECT_EQ(change->second.s, 5.0);
  EXPECT_TRUE(b.probed.empty());
}
