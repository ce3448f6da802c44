// An admissible interval of a number, [lo, hi] with either end open or infinite: the range of a
// scene key and of a problem's parameter (one type, so the two can be compared).
#pragma once

#include <limits>
#include <string>

namespace keller {

struct Range {
  double lo = -std::numeric_limits<double>::infinity();
  double hi = std::numeric_limits<double>::infinity();
  bool lo_open = false, hi_open = false;

  static Range any() { return {}; }
  static Range positive() { return {0.0, std::numeric_limits<double>::infinity(), true, false}; }
  static Range non_negative() { return {0.0, std::numeric_limits<double>::infinity(), false, false}; }
  static Range at_least(double v) { return {v, std::numeric_limits<double>::infinity(), false, false}; }
  static Range above(double v) { return {v, std::numeric_limits<double>::infinity(), true, false}; }
  static Range between(double a, double b) { return {a, b, false, false}; }
  bool contains(double v) const;
  std::string describe() const;  // "> 0", "in [0.1, 0.4]", ">= 1", "any number"

  // Whether every value this range admits, `outer` admits too.
  bool within(const Range& outer) const;
};

}  // namespace keller
