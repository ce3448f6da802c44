// What the branch and time-series files share (continuation/output/TableRows): columns found by
// name, and the refusal of an unfinished run's seed that a run cannot continue.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

#include "continuation/output/TableRows.hpp"

using namespace keller;

namespace {

// The message of what `f` throws ("" if nothing).
template <class F>
std::string thrown(F f) {
  try {
    f();
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(TableRows, AColumnIsFoundByNameOrNamedAsMissing) {
  const std::vector<std::string> columns = {"row", "kind", "s", "Wi"};
  EXPECT_EQ(column_index(columns, "row", "branch table"), 0);
  EXPECT_EQ(column_index(columns, "Wi", "branch table"), 3);
  EXPECT_THROW(column_index(columns, "wi", "branch table"), std::invalid_argument);
  EXPECT_EQ(thrown([&] { column_index(columns, "dP", "the time table"); }), "the time table has no column 'dP'");
}

// A seed continues a run with the same columns and as many unknowns; a seed without stored states
// (a time series killed before its first) has no size to compare.
TEST(TableRows, ASeedWithOtherColumnsOrUnknownsIsRefused) {
  const std::vector<std::string> columns = {"step", "t", "saved_slot"};
  const Eigen::MatrixXd two_states = Eigen::MatrixXd::Zero(2, 5);
  EXPECT_EQ(thrown([&] { check_seed("run", columns, columns, two_states, 5); }), "");
  EXPECT_EQ(thrown([&] { check_seed("run", columns, columns, Eigen::MatrixXd(), 5); }), "");
  EXPECT_EQ(thrown([&] {
              check_seed("branch", {"step", "t"}, columns, two_states, 5);
            }),
            "the unfinished branch has other columns than this run's (step,t)");
  EXPECT_EQ(thrown([&] { check_seed("run", columns, columns, two_states, 6); }),
            "the unfinished run has another number of unknowns");
}
