// What a run says of points it detected but could not locate (continuation/events/RepeatedNotes), on
// synthetic sequences of notes.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "continuation/events/RepeatedNotes.hpp"

using namespace keller;

// Notes of points detected but not located: the first of a run of the same at successive steps is
// said, the rest summed up in one line where the run ends (a step without it, another note, the
// end of the branch).
TEST(RepeatedNotes, ARunOfTheSameNoteIsSaidOnceThenCounted) {
  RepeatedNotes r;
  const RepeatedNotes::Note bp{"branch-point 'det sign change'", "branch-point 'det sign change' ... after row 3"};
  const RepeatedNotes::Note fold{"fold 'min'", "fold 'min' ... after row 9"};
  EXPECT_EQ(r.step({bp}, 3), std::vector<std::string>{bp.text});
  EXPECT_TRUE(r.step({bp}, 4).empty());
  EXPECT_TRUE(r.step({bp}, 6).empty());
  const auto after_gap = r.step({}, 7);
  ASSERT_EQ(after_gap.size(), 1u);
  EXPECT_EQ(after_gap[0],
            "branch-point 'det sign change' detected but not located again at 2 successive steps, the "
            "last after row 6");
  EXPECT_EQ(r.step({bp}, 8), std::vector<std::string>{bp.text});  // a new run
  const auto other = r.step({fold}, 9);
  EXPECT_EQ(other, std::vector<std::string>{fold.text});  // nothing repeated before it: no summary
  EXPECT_TRUE(r.step({fold}, 10).empty());
  const auto end = r.finish();
  ASSERT_EQ(end.size(), 1u);
  EXPECT_NE(end[0].find("again at 1 successive step, the last after row 10"), std::string::npos) << end[0];
  EXPECT_TRUE(r.finish().empty());
  // two notes at every step are two runs, each said once and counted apart
  RepeatedNotes both;
  EXPECT_EQ(both.step({bp, fold}, 1).size(), 2u);
  for (int row = 2; row <= 5; ++row) EXPECT_TRUE(both.step({fold, bp}, row).empty()) << row;
  const auto ends = both.step({fold}, 6);
  ASSERT_EQ(ends.size(), 1u);
  EXPECT_NE(ends[0].find("det sign change' detected but not located again at 4 successive steps"), std::string::npos)
      << ends[0];
  const auto last = both.finish();
  ASSERT_EQ(last.size(), 1u);
  EXPECT_NE(last[0].find("fold 'min' detected but not located again at 5 successive steps"), std::string::npos)
      << last[0];
}
