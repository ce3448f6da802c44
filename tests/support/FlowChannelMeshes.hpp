// Straight channels of FlowEquations' boundary tests: a block mesh of the channel 0 <= x' <= L,
// 0 <= y' <= H placed by a rotation, and its conditions (inflow, outflow, two walls).
#pragma once

#include <array>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

#include "core/BlockMeshBuilder.hpp"
#include "problems/components/FlowEquations.hpp"

namespace keller::test {

using Map = std::function<Mesh::Point(double, double)>;  // local channel coordinates (x', y') -> (x, y)

inline Map rotation(double degrees) {
  if (degrees == 0) return [](double x, double y) { return Mesh::Point{x, y}; };
  if (degrees == 90) return [](double x, double y) { return Mesh::Point{-y, x}; };
  if (degrees == 180) return [](double x, double y) { return Mesh::Point{-x, -y}; };
  const double a = degrees * std::numbers::pi / 180, c = std::cos(a), s = std::sin(a);
  return [c, s](double x, double y) { return Mesh::Point{c * x - s * y, s * x + c * y}; };
}

// The channel 0 <= x' <= L, 0 <= y' <= H, placed by `map`; sides bottom, outflow, top, inflow.
inline Mesh channel(double L, double H, int nx, int ny, const Map& map,
                    std::array<std::string, 4> names = {"bottom", "outflow", "top", "inflow"}) {
  BlockMeshBuilder b;
  b.add_block(
      {"channel", "fluid", nx, ny, Grading{}, Grading{}, [=](double s, double t) { return map(L * s, H * t); }, names});
  return b.build();
}

inline FlowBoundaries channel_bc(bool fully_developed_outflow) {
  FlowBoundaries bc;
  bc.inflows = {{"inflow"}};
  bc.outflows = {{"outflow", fully_developed_outflow}};
  bc.walls = {"bottom", "top"};
  return bc;
}

}  // namespace keller::test
