// Bracketing a change along a sequence of points by bisection (pure): the adjacent pair where an
// integer property (a count of unstable eigenvalues, a determinant's sign) first differs from
// its value at the first point, evaluating it at about log2(n) points in between. Used where the
// property is known only at some points of a branch (spectra every N points, determinant signs
// from the factorisations a kept chord makes).
#pragma once

#include <cstddef>
#include <functional>
#include <optional>
#include <utility>

namespace keller {

// Points 0 .. n-1 (n >= 2) whose property at 0 is `first` and at n-1 differs from it. value_at(i)
// evaluates it at 0 < i < n-1 (negative: could not be evaluated). Returns (lo, lo + 1) with
// value(lo) == first and value(lo + 1) != first, as bisection finds them; nothing where an
// evaluation failed. (With several changes inside, one of them.)
std::optional<std::pair<size_t, size_t>> bisect_change(size_t n, int first, const std::function<int(size_t)>& value_at);

}  // namespace keller
