// One-dimensional grading of element sizes along a block side: the logical vertex positions
// 0 = s_0 < s_1 < ... < s_n = 1 of n elements. All gradings are geometric progressions of
// element size, the usual choice for channel meshes because neighbouring elements then differ
// by a constant factor.
#pragma once

#include <string>
#include <vector>

namespace keller {

struct Grading {
  enum class Kind {
    Uniform,   // equal sizes
    Start,     // fine at s = 0: sizes grow by a constant factor towards s = 1
    End,       // fine at s = 1
    BothEnds,  // fine at both ends, coarse in the middle (symmetric)
  };
  Kind kind = Kind::Uniform;
  double ratio = 1.0;  // largest element size / smallest element size (>= 1)

  static Grading uniform() { return {}; }
  static Grading start(double ratio) { return {Kind::Start, ratio}; }
  static Grading end(double ratio) { return {Kind::End, ratio}; }
  static Grading both_ends(double ratio) { return {Kind::BothEnds, ratio}; }

  // Logical vertex positions for n elements; throws std::invalid_argument if n < 1 or ratio < 1.
  std::vector<double> vertices(int n) const;
};

// The ratio for a one-sided grading of n elements over a length L whose smallest element has
// size h_min (h_min < L / n); used to match element sizes across a block interface.
double grading_ratio_for_smallest(int n, double length, double h_min);

}  // namespace keller
