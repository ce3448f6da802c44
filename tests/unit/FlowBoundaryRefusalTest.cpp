// Conditions of FlowEquations that a mesh cannot carry, each refused before any work with a
// message naming the boundary and what is wrong with it.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "core/BlockMeshBuilder.hpp"
#include "problems/components/FlowEquations.hpp"
#include "support/FlowChannelMeshes.hpp"

using namespace keller;
using namespace keller::test;

namespace {

std::string refusal(const Mesh& mesh, const FlowBoundaries& bc) {
  ParameterSet params;
  try {
    FlowEquations flow(mesh, "fluid", FluidOptions{}, bc, params, -1);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(FlowBoundaries, RefusesConditionsTheMeshCannotCarry) {
  const Mesh straight = channel(3, 1, 3, 2, rotation(0)), tilted = channel(3, 1, 3, 2, rotation(30));
  auto has = [](const std::string& message, const std::string& part) {
    EXPECT_NE(message.find(part), std::string::npos) << "message: '" << message << "'\nexpected: '" << part << "'";
  };
  {  // a boundary the mesh lacks
    FlowBoundaries bc = channel_bc(true);
    bc.walls.push_back("nozzle");
    has(refusal(straight, bc),
        "the mesh has no boundary 'nozzle' (given a wall condition); its boundaries: bottom, "
        "inflow, outflow, top");
  }
  {  // named twice
    FlowBoundaries bc = channel_bc(true);
    bc.symmetry = {"top"};
    has(refusal(straight, bc), "boundary 'top' has two conditions (wall and symmetry)");
  }
  {  // a curved inlet
    BlockMeshBuilder b;
    b.add_block({"c",
                 "fluid",
                 3,
                 2,
                 Grading{},
                 Grading{},
                 [](double s, double t) {
                   return Mesh::Point{3 * s + 0.1 * std::sin(std::numbers::pi * t) * (1 - s), t};
                 },
                 {"bottom", "outflow", "top", "inflow"}});
    has(refusal(b.build(), channel_bc(true)), "fully developed inflow 'inflow': the boundary is not straight");
  }
  {  // two inlets under one name
    BlockMeshBuilder b;
    for (double y0 : {0.0, 2.0})
      b.add_block({y0 == 0 ? "lower" : "upper",
                   "fluid",
                   2,
                   1,
                   Grading{},
                   Grading{},
                   [=](double s, double t) {
                     return Mesh::Point{2 * s, y0 + t};
                   },
                   {"bottom", "outflow", "top", "inflow"}});
    has(refusal(b.build(), channel_bc(true)), "fully developed inflow 'inflow': the boundary is not a single segment");
  }
  {  // both ends of the inlet on symmetry lines
    FlowBoundaries bc = channel_bc(true);
    bc.walls = {};
    bc.symmetry = {"bottom", "top"};
    has(refusal(straight, bc), "fully developed inflow 'inflow': both its ends lie on symmetry lines");
  }
  {  // a sloped symmetry line
    FlowBoundaries bc = channel_bc(false);
    bc.walls = {"top"};
    bc.symmetry = {"bottom"};
    has(refusal(tilted, bc), "symmetry line 'bottom': its edge from");
    has(refusal(tilted, bc), "runs along neither x nor y; keller's velocity unknowns are v_x and v_y");
  }
  {  // a sloped fully developed outflow
    has(refusal(tilted, channel_bc(true)), "fully developed outflow 'outflow': its edge from");
  }
  {  // a fully developed inflow of zero mean velocity
    FlowBoundaries bc = channel_bc(true);
    bc.inflows[0].mean_velocity = 0;
    has(refusal(straight, bc),
        "inflow 'inflow': the mean velocity of a fully developed inflow must be finite and "
        "non-zero (got 0)");
  }
  EXPECT_EQ(refusal(tilted, channel_bc(false)), "");  // a traction-free outflow may face any way
}
