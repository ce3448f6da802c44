// What a step crossed and the order of the located points (continuation/events/EventDetector), on
// synthetic points.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "continuation/events/EventDetector.hpp"
#include "support/SyntheticPoints.hpp"

using namespace keller;
using keller::test::point;

// The crossings of a segment, in order: the upper bound, requested values (not the one landed on),
// monitors (the problem's are events, the stop thresholds ends; the same function twice is one
// search), folds.
TEST(EventDetector, TheCrossingsOfASegment) {
  ContinuationOptions o;
  o.parameter = "p";
  o.stop.upper = 1.9;
  o.events.stops = {1.2, 1.5};
  const BranchPoint cur = point(0.0, 1.0, 0.8, {0.3, -1.0, 0.3});
  const BranchPoint nxt = point(1.0, 2.0, -0.2, {-0.1, -0.5, -0.1});
  const std::vector<std::string> names = {"g", "h", "g < stop_below"};
  Landing land;
  land.value = 1.5;
  const auto c = detect_crossings(cur, nxt, land, o, names, 2);
  ASSERT_EQ(c.size(), 5u);
  EXPECT_EQ(c[0].kind, PointKind::End);
  EXPECT_EQ(c[0].target.value, 1.9);
  EXPECT_EQ(c[0].end, StopCode::UpperBound);
  EXPECT_EQ(c[1].kind, PointKind::Requested);
  EXPECT_EQ(c[1].target.value, 1.2);
  EXPECT_EQ(c[1].label, "p = 1.2");
  EXPECT_EQ(c[2].kind, PointKind::Event);
  EXPECT_EQ(c[2].target.monitor, 0);
  EXPECT_EQ(c[3].kind, PointKind::End);  // the stop threshold on the same function as monitor 0
  EXPECT_EQ(c[3].end, StopCode::StopObservable);
  EXPECT_EQ(c[3].same_as, 2);
  EXPECT_EQ(c[4].kind, PointKind::Fold);
  EXPECT_EQ(c[4].label, "max");
  // natural continuation locates no folds
  o.method = ContinuationOptions::Method::Natural;
  EXPECT_EQ(detect_crossings(cur, nxt, land, o, names, 2).size(), 4u);
  // a monitor that vanishes exactly at nxt (a landed stop) is located at nxt
  const BranchPoint on = point(1.0, 2.0, 0.8, {0.0, -1.0, 0.0});
  const auto z = detect_crossings(cur, on, land, o, names, 2);
  ASSERT_EQ(z.size(), 4u);  // the bound, the stop, monitor 0 and its threshold
  EXPECT_TRUE(z[2].at_next);
  EXPECT_TRUE(z[3].at_next);
  // a step that landed on the threshold's zero: its value there is rounding, of either sign (here
  // the sign it started with, no crossing by sign), and the zero is nxt's, with that of monitor
  // 0, the same function
  Landing zero;
  zero.monitor = 2;
  zero.end = StopCode::StopObservable;
  zero.value = NAN;
  for (double rounding : {1e-15, -1e-15}) {
    const BranchPoint landed = point(1.0, 1.4, 0.8, {rounding, -1.0, rounding});
    const auto l = detect_crossings(cur, landed, zero, o, names, 2);
    ASSERT_EQ(l.size(), 3u) << rounding;  // the stop at 1.2, monitor 0 and its threshold
    EXPECT_EQ(l[1].target.monitor, 0);
    EXPECT_TRUE(l[1].at_next);
    EXPECT_EQ(l[2].target.monitor, 2);
    EXPECT_TRUE(l[2].at_next);
    EXPECT_EQ(l[2].end, StopCode::StopObservable);
  }
}

// Located points come in order along the branch; an event that is also the located end of the
// stop observable is reported once, as the end.
TEST(EventDetector, LocatedPointsInOrderAndAnEndReportedOnce) {
  std::vector<LocatedPoint> located(3);
  located[0].point = point(0.7, 1.7, 1, {});
  located[0].point.kind = PointKind::Event;
  located[1].point = point(0.3, 1.3, 1, {});
  located[1].point.kind = PointKind::Requested;
  located[2].point = point(0.7 + 1e-5, 1.7 + 1e-9, 1, {});
  located[2].point.kind = PointKind::End;
  located[2].end = StopCode::StopObservable;
  order_located(located, 1.0, 1e-8);
  ASSERT_EQ(located.size(), 2u);
  EXPECT_EQ(located[0].point.kind, PointKind::Requested);
  EXPECT_EQ(located[1].point.kind, PointKind::End);
}

// A part of the tangent turns where it changes sign above rounding: kTangentRounding of the
// tangent's largest part at either end. Two parts of rounding size (1e-20 on a unit tangent: a
// curve along which that unknown stays constant) are no turn, whatever their signs; the same pair
// on a tangent of size 1e-12 is one (the share, not the size, decides); a fold of the parameter
// follows the same rule.
TEST(EventDetector, ATurnIsASignChangeAboveTheTangentsRounding) {
  BranchPoint cur = point(0.0, 1.0, 1.0, {}), nxt = point(1.0, 2.0, -1.0, {});
  cur.tu = Vector::Constant(3, 0.5);
  nxt.tu = Vector::Constant(3, -0.5);
  EXPECT_TRUE(turns(0.3, -0.2, cur, nxt));
  EXPECT_FALSE(turns(0.3, 0.2, cur, nxt));
  EXPECT_FALSE(turns(1e-20, -3e-21, cur, nxt));
  EXPECT_FALSE(turns(0.99e-10, -0.99e-10, cur, nxt));
  EXPECT_TRUE(turns(1.01e-10, -1e-30, cur, nxt));  // one end above the band: a turn
  EXPECT_TRUE(turns(-1e-30, 1.01e-10, cur, nxt));
  BranchPoint small_cur = cur, small_nxt = nxt;
  small_cur.tu *= 1e-12;
  small_nxt.tu *= 1e-12;
  small_cur.tlambda = small_nxt.tlambda = 0.0;
  EXPECT_TRUE(turns(1e-20, -3e-21, small_cur, small_nxt));
  // in detect_crossings: a turning unknown (index 1) whose part is rounding is not an event, nor
  // is a parameter part of rounding size a fold
  ContinuationOptions o;
  o.parameter = "p";
  const std::vector<AugmentedProblem::NamedUnknown> turning = {{1, "q"}};
  cur.tu[1] = 2e-21;
  nxt.tu[1] = -4e-22;
  cur.tlambda = 3e-21;
  nxt.tlambda = -1e-21;
  EXPECT_TRUE(detect_crossings(cur, nxt, std::nullopt, o, {}, 0, turning).empty());
  cur.tu[1] = 0.1;
  nxt.tlambda = -0.1;
  cur.tlambda = 0.1;
  const auto c = detect_crossings(cur, nxt, std::nullopt, o, {}, 0, turning);
  ASSERT_EQ(c.size(), 2u);
  EXPECT_EQ(c[0].kind, PointKind::Fold);
  EXPECT_EQ(c[1].label, "q max");
}

// Monitors are usable where each is finite or NaN of a partial monitor; infinity never is.
TEST(EventDetector, MonitorsAreUsableWhereFiniteOrUndefinedWhereTheyMayBe) {
  EXPECT_TRUE(monitors_usable({0.5, -2.0, 0.0}, {}));
  EXPECT_FALSE(monitors_usable({0.5, NAN, 0.0}, {}));
  EXPECT_TRUE(monitors_usable({0.5, NAN, 0.0}, {1}));
  EXPECT_FALSE(monitors_usable({0.5, NAN, 0.0}, {2}));
  EXPECT_FALSE(monitors_usable({0.5, INFINITY, 0.0}, {1}));
  EXPECT_FALSE(monitors_usable({0.5, 1.0, -INFINITY}, {2}));
  EXPECT_TRUE(monitors_usable({}, {0}));
  // a step from an undefined value to exactly 0 is no zero at its end
  ContinuationOptions o;
  o.parameter = "p";
  const BranchPoint undefined = point(0.0, 1.0, 1.0, {NAN}), zero = point(1.0, 1.1, 1.0, {0.0});
  EXPECT_TRUE(detect_crossings(undefined, zero, std::nullopt, o, {"g"}, 1).empty());
  EXPECT_EQ(detect_crossings(point(0.0, 1.0, 1.0, {0.5}), zero, std::nullopt, o, {"g"}, 1).size(), 1u);
}
