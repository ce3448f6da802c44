// Builds a Mesh from logically rectangular blocks. Each block maps the unit square of logical
// coordinates (s, t) smoothly to physical space; its vertices sit at graded logical positions
// and its mid-side and centre nodes at the logical midpoints, so a block whose map is affine in
// (s, t) gives straight-sided, bilinear elements (which keeps Q2 exact for quadratics), and a
// curved map gives isoparametric curved edges. Blocks are glued along whole sides; glued nodes
// are merged topologically and checked to coincide geometrically.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "core/Grading.hpp"
#include "core/Mesh.hpp"

namespace keller {

enum class Side { Bottom = 0, Right = 1, Top = 2, Left = 3 };

struct BlockSpec {
  std::string name;
  std::string group;   // element group, e.g. "fluid" or "solid"
  int nx = 1, ny = 1;  // elements along s and t
  Grading grading_s, grading_t;
  std::function<Mesh::Point(double s, double t)> map;  // (s, t) in [0,1]^2 -> (x, y)
  std::array<std::string, 4> side_names;               // boundary name per Side, "" for none
};

class BlockMeshBuilder {
 public:
  int add_block(BlockSpec spec);  // returns the block index
  // Glue side sa of block a to side sb of block b. Both sides are traversed in increasing
  // logical coordinate and must have the same number of elements.
  void connect(int a, Side sa, int b, Side sb);
  // Throws std::invalid_argument on inconsistent input (side lengths, non-coincident glued
  // nodes, inverted elements).
  Mesh build() const;

 private:
  struct Connection {
    int a;
    Side sa;
    int b;
    Side sb;
  };
  std::vector<BlockSpec> blocks_;
  std::vector<Connection> connections_;
};

}  // namespace keller
