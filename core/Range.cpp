#include "core/Range.hpp"

#include <fmt/format.h>

#include <cmath>

namespace keller {

bool Range::contains(double v) const {
  if (std::isnan(v)) return false;
  if (lo_open ? !(v > lo) : !(v >= lo)) return false;
  if (hi_open ? !(v < hi) : !(v <= hi)) return false;
  return true;
}

std::string Range::describe() const {
  const bool has_lo = std::isfinite(lo), has_hi = std::isfinite(hi);
  if (!has_lo && !has_hi) return "any number";
  if (lo == hi && !lo_open && !hi_open) return fmt::format("{}", lo);
  if (has_lo && !has_hi) return fmt::format("{} {}", lo_open ? ">" : ">=", lo);
  if (!has_lo && has_hi) return fmt::format("{} {}", hi_open ? "<" : "<=", hi);
  return fmt::format("in {}{}, {}{}", lo_open ? "(" : "[", lo, hi, hi_open ? ")" : "]");
}

bool Range::within(const Range& outer) const {
  const bool lo_ok = lo > outer.lo || (lo == outer.lo && (lo_open || !outer.lo_open));
  const bool hi_ok = hi < outer.hi || (hi == outer.hi && (hi_open || !outer.hi_open));
  return lo_ok && hi_ok;
}

}  // namespace keller
