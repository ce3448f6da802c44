// Meshes: element and node counts of the reference meshes, areas, gluing, grading, errors.
#include <gtest/gtest.h>

#include <cmath>
#include <set>

#include "core/BlockMeshBuilder.hpp"
#include "problems/channel/ChannelMesh.hpp"

using namespace keller;

namespace {
double area(const Mesh& m, int group) {
  double a = 0;
  for (int e : m.elements_in_group(group)) {
    double xy[9][2];
    m.element_nodes(e, xy);
    std::array<QpGeometry<double>, ref::kQp> g;
    EXPECT_TRUE(map_element(xy, g));
    for (const auto& q : g) a += q.wdetJ;
  }
  return a;
}
}  // namespace

// model.md's table: M1 400 elements / 1705 nodes, M2 900 / 3757, M3 1600 / 6609.
TEST(ChannelMesh, ReferenceMeshesHaveThePublishedCounts) {
  const std::vector<std::tuple<std::string, int, int>> table = {
      {"M1", 400, 1705}, {"M2", 900, 3757}, {"M3", 1600, 6609}};
  for (const auto& [name, elements, nodes] : table) {
    const Mesh m = build_channel_mesh({}, ChannelMeshSpec::preset(name), true);
    EXPECT_EQ(m.num_elements(), elements) << name;
    EXPECT_EQ(m.num_nodes(), nodes) << name;
  }
}

TEST(ChannelMesh, AreasAndBoundaries) {
  ChannelGeometry g;
  g.thickness = 0.25;
  const ChannelMeshSpec s = ChannelMeshSpec::preset("M1");
  const Mesh m = build_channel_mesh(g, s, true);
  EXPECT_NEAR(area(m, m.group_index("fluid")), 19.0, 1e-12);
  EXPECT_NEAR(area(m, m.group_index("solid")), 5.0 * 0.25, 1e-12);
  EXPECT_EQ(static_cast<int>(m.boundary("inflow").size()), s.ny_fluid);
  EXPECT_EQ(static_cast<int>(m.boundary("outflow").size()), s.ny_fluid);
  EXPECT_EQ(static_cast<int>(m.boundary("bottom_wall").size()), s.nx_upstream + s.nx_deformable + s.nx_downstream);
  EXPECT_EQ(static_cast<int>(m.boundary("top_wall").size()), s.nx_upstream + s.nx_downstream);
  // the interface holds the fluid's top edges and the solid's bottom edges, on the same nodes
  EXPECT_EQ(static_cast<int>(m.boundary("interface").size()), 2 * s.nx_deformable);
  EXPECT_EQ(static_cast<int>(m.boundary_nodes("interface").size()), 2 * s.nx_deformable + 1);
  for (int n : m.boundary_nodes("interface")) EXPECT_NEAR(m.node(n)[1], 1.0, 1e-15);
  for (int n : m.boundary_nodes("inflow")) EXPECT_NEAR(m.node(n)[0], 0.0, 1e-15);
  for (int n : m.boundary_nodes("outflow")) EXPECT_NEAR(m.node(n)[0], 19.0, 1e-14);
  for (int n : m.boundary_nodes("wall_top")) EXPECT_NEAR(m.node(n)[1], 1.25, 1e-15);
  const auto [jmin, jmax] = m.jacobian_range();
  EXPECT_GT(jmin, 0.0);
}

TEST(ChannelMesh, GradingConcentratesElementsAtTheDeformableEnds) {
  const ChannelMeshSpec s = ChannelMeshSpec::preset("M2");
  const Mesh m = build_channel_mesh({}, s, false);
  const MeshBlock& def = m.block("deformable");
  std::vector<double> w;
  for (int i = 0; i < def.nx; ++i) w.push_back(m.node(def.node(2 * i + 2, 0))[0] - m.node(def.node(2 * i, 0))[0]);
  const double wmax = *std::max_element(w.begin(), w.end()), wmin = *std::min_element(w.begin(), w.end());
  EXPECT_NEAR(wmax / wmin, s.ratio_x, 1e-10);
  EXPECT_NEAR(w.front(), wmin, 1e-14);
  EXPECT_NEAR(w.back(), wmin, 1e-14);
  // the upstream column next to the deformable section matches its end column
  const MeshBlock& up = m.block("upstream");
  const double last_up = m.node(up.node(2 * up.nx, 0))[0] - m.node(up.node(2 * up.nx - 2, 0))[0];
  EXPECT_NEAR(last_up, wmin, 1e-9);
  // rows are finest at both walls
  std::vector<double> h;
  for (int j = 0; j < def.ny; ++j) h.push_back(m.node(def.node(0, 2 * j + 2))[1] - m.node(def.node(0, 2 * j))[1]);
  EXPECT_NEAR(*std::max_element(h.begin(), h.end()) / *std::min_element(h.begin(), h.end()), s.ratio_y, 1e-10);
  EXPECT_NEAR(h.front(), h.back(), 1e-14);
}

TEST(BlockMesh, GluedNodesAreShared) {
  BlockMeshBuilder b;
  const int a = b.add_block({"a", "g", 2, 3, {}, {}, [](double s, double t) { return Mesh::Point{s, t}; }, {}});
  const int c = b.add_block({"b", "g", 4, 3, {}, {}, [](double s, double t) { return Mesh::Point{1 + s, t}; }, {}});
  b.connect(a, Side::Right, c, Side::Left);
  const Mesh m = b.build();
  EXPECT_EQ(m.num_nodes(), 5 * 7 + 9 * 7 - 7);
  std::set<int> left, right;
  for (int j = 0; j < 7; ++j) EXPECT_EQ(m.blocks()[0].node(4, j), m.blocks()[1].node(0, j));
}

TEST(BlockMesh, RejectsBadInput) {
  BlockMeshBuilder b;
  const int a = b.add_block({"a", "g", 2, 3, {}, {}, [](double s, double t) { return Mesh::Point{s, t}; }, {}});
  const int c = b.add_block({"b", "g", 2, 2, {}, {}, [](double s, double t) { return Mesh::Point{1 + s, t}; }, {}});
  b.connect(a, Side::Right, c, Side::Left);
  EXPECT_THROW(b.build(), std::invalid_argument);  // 3 rows glued to 2

  BlockMeshBuilder apart;
  const int p = apart.add_block({"a", "g", 1, 1, {}, {}, [](double s, double t) { return Mesh::Point{s, t}; }, {}});
  const int q = apart.add_block({"b", "g", 1, 1, {}, {}, [](double s, double t) { return Mesh::Point{2 + s, t}; }, {}});
  apart.connect(p, Side::Right, q, Side::Left);
  EXPECT_THROW(apart.build(), std::invalid_argument);  // sides do not touch

  BlockMeshBuilder inverted;
  inverted.add_block({"a", "g", 1, 1, {}, {}, [](double s, double t) { return Mesh::Point{-s, t}; }, {}});
  EXPECT_THROW(inverted.build(), std::invalid_argument);
}

TEST(Grading, RatiosAndMatching) {
  const auto v = Grading::start(8.0).vertices(4);
  EXPECT_NEAR((v[4] - v[3]) / (v[1] - v[0]), 8.0, 1e-12);
  EXPECT_DOUBLE_EQ(v.front(), 0.0);
  EXPECT_DOUBLE_EQ(v.back(), 1.0);
  const double r = grading_ratio_for_smallest(10, 7.0, 0.1);
  const auto w = Grading::start(r).vertices(10);
  EXPECT_NEAR(7.0 * (w[1] - w[0]), 0.1, 1e-12);
  EXPECT_THROW(Grading::start(0.5).vertices(3), std::invalid_argument);
}
