#include "continuation/events/Bracket.hpp"

#include <stdexcept>

namespace keller {

std::optional<std::pair<size_t, size_t>> bisect_change(size_t n, int first,
                                                       const std::function<int(size_t)>& value_at) {
  if (n < 2) throw std::invalid_argument("bisect_change: need at least two points");
  size_t lo = 0, hi = n - 1;
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    const int v = value_at(mid);
    if (v < 0) return std::nullopt;
    (v == first ? lo : hi) = mid;
  }
  return std::make_pair(lo, hi);
}

}  // namespace keller
