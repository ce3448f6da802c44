// The spectrum scheduler (continuation/events/SpectrumScheduler) from given counts.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "continuation/events/SpectrumScheduler.hpp"
#include "support/SyntheticPoints.hpp"

using namespace keller;
using keller::test::point;

namespace {

class CountingAnalysis final : public PointAnalysis {
 public:
  explicit CountingAnalysis(int every) : every_(every) {}
  std::vector<std::string> column_names() const override { return {}; }
  std::string count_name() const override { return "unstable"; }
  Status analyse(Problem&, const Vector&, PointAnalysisResult&, SparseLU*) override { return {}; }
  int every() const override { return every_; }

 private:
  int every_;
};

}  // namespace

// Spectra every 4 points and at the last step; a change of the count between two analysed points
// is bracketed by analysing the points in between (bisection).
TEST(SpectrumScheduler, EveryNPointsAndAChangeBracketedByBisection) {
  CountingAnalysis analysis(4);
  SpectrumScheduler s(&analysis);
  EXPECT_FALSE(s.due(1, 100));
  EXPECT_TRUE(s.due(4, 100));
  EXPECT_TRUE(s.due(7, 7));
  auto count_at = [](double lambda) { return lambda < 2.5 ? 0 : 1; };
  BranchPoint start = point(0, 0, 1, {});
  start.index = 0;
  start.analysed = true;
  start.count = 0;
  s.restart(start, false);
  int analysed = 0;
  auto analyse = [&](BranchPoint& p) {
    ++analysed;
    p.analysed = true;
    p.count = count_at(p.lambda);
  };
  std::vector<BranchPoint> rows;
  for (int k = 1; k <= 3; ++k) {
    BranchPoint p = point(k, k, 1, {});
    p.index = k;
    s.reported(p);
    rows.push_back(p);
  }
  BranchPoint cur = rows.back(), nxt = point(4, 4, 1, {});
  analyse(nxt);
  const auto change = s.change_at(cur, nxt, analyse);
  ASSERT_TRUE(change);
  ASSERT_TRUE(change->bracketed);
  EXPECT_EQ(change->a->lambda, 2.0);
  EXPECT_EQ(change->b->lambda, 3.0);
  EXPECT_FALSE(change->this_step);
  EXPECT_EQ(change->description, "unstable 0 -> 1");
  EXPECT_LE(analysed, 3);  // nxt and two in between
}
