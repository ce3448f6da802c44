// Degree-of-freedom map: only active fields, only on their groups, with the right bases.
#include <gtest/gtest.h>

#include <set>

#include "core/DofMap.hpp"
#include "problems/channel/ChannelMesh.hpp"

using namespace keller;

TEST(DofMap, FieldsLiveOnlyWhereDeclared) {
  const Mesh m = build_channel_mesh({}, ChannelMeshSpec::preset("M1"), true);
  const DofMap d(m, {{"velocity", Basis::Q2, {"vx", "vy"}, {"fluid"}},
                     {"pressure", Basis::P1Disc, {"p"}, {"fluid"}},
                     {"gradient", Basis::Q1, {"Lxx", "Lxy", "Lyx", "Lyy"}, {"fluid"}},
                     {"position", Basis::Q2, {"x", "y"}, {"solid"}}});
  const int fluid = m.group_index("fluid"), solid = m.group_index("solid");
  std::set<int> fluid_nodes, fluid_vertices, solid_nodes;
  int fluid_elements = 0;
  for (int e = 0; e < m.num_elements(); ++e) {
    for (int a = 0; a < 9; ++a) (m.element_group(e) == fluid ? fluid_nodes : solid_nodes).insert(m.element(e)[a]);
    if (m.element_group(e) == fluid) {
      ++fluid_elements;
      for (int v : ref::q1_node) fluid_vertices.insert(m.element(e)[v]);
    }
  }
  EXPECT_EQ(d.size(), static_cast<int>(2 * fluid_nodes.size() + 3 * fluid_elements + 4 * fluid_vertices.size() +
                                       2 * solid_nodes.size()));
  const int fv = d.field_index("velocity"), fs = d.field_index("position");
  for (int n = 0; n < m.num_nodes(); ++n) {
    EXPECT_EQ(d.node_dof(fv, n, 0) >= 0, fluid_nodes.count(n) > 0);
    EXPECT_EQ(d.node_dof(fs, n, 1) >= 0, solid_nodes.count(n) > 0);
  }
  EXPECT_FALSE(d.on_element(fv, m.elements_in_group(solid)[0]));
  EXPECT_THROW(d.field_index("conformation"), std::invalid_argument);
  // dofs are a permutation of 0..size-1
  std::vector<int> seen(d.size(), 0);
  for (int f = 0; f < d.num_fields(); ++f) {
    std::vector<int> ed(d.element_dofs_size(f));
    for (int e = 0; e < m.num_elements(); ++e) {
      if (!d.on_element(f, e)) continue;
      d.element_dofs(f, e, ed.data());
      for (int x : ed) seen.at(x) = 1;
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), d.size());
}

TEST(DofMap, NewtonianSceneHasOnlyVelocityAndPressure) {
  const Mesh m = build_channel_mesh({}, ChannelMeshSpec::preset("M1"), false);
  const DofMap d(m, {{"velocity", Basis::Q2, {"vx", "vy"}, {"fluid"}}, {"pressure", Basis::P1Disc, {"p"}, {"fluid"}}});
  EXPECT_EQ(d.size(), 2 * m.num_nodes() + 3 * m.num_elements());
  EXPECT_FALSE(d.has_field("conformation"));
  EXPECT_NE(d.describe(d.node_dof(0, 5, 1)).find("velocity.vy at node 5"), std::string::npos);
}
