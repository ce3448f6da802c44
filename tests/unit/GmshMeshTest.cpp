// Gmsh meshes in and out (core/GmshMesh): node order, curved edges, the round trip of a keller mesh,
// .geo parameters. The refusals are in GmshMeshRefusalTest.cpp.
#include <gtest/gtest.h>

#include <cmath>

#include "core/BlockMeshBuilder.hpp"
#include "core/GmshMesh.hpp"
#include "problems/cylinder/CylinderProblem.hpp"
#include "support/GmshTestMeshes.hpp"

using namespace keller;
using namespace keller::test;

// Gmsh's node k of a 9-node quadrilateral (corners, then mid-edges, then centre) lands at keller's
// lexicographic node a = i + 3 j with the same reference coordinates: checked on a general straight
// quadrilateral, whose bilinear map is exact in Q2, so det J > 0, the area is the polygon's and each
// side's length its straight length.
TEST_F(GmshMeshTest, SingleQuadrilateralKeepsTheReferenceNodeOrder) {
  const std::array<Mesh::Point, 4> c = {{{0.0, 0.0}, {2.0, 0.25}, {1.5, 1.0}, {-0.25, 1.25}}};
  const Mesh m = read_gmsh_mesh(write_file(path("quad.msh"), single_quad(c).text()));
  ASSERT_EQ(m.num_elements(), 1);
  ASSERT_EQ(m.num_nodes(), 9);
  for (int a = 0; a < 9; ++a) {
    const double s = ref::node_s(a), t = ref::node_t(a);
    for (int i = 0; i < 2; ++i) {
      const double expected = 0.25 * ((1 - s) * (1 - t) * c[0][i] + (1 + s) * (1 - t) * c[1][i] +
                                      (1 + s) * (1 + t) * c[2][i] + (1 - s) * (1 + t) * c[3][i]);
      EXPECT_DOUBLE_EQ(m.node(m.element(0)[a])[i], expected) << "node " << a;
    }
  }
  EXPECT_GT(m.jacobian_range().first, 0.0);
  double shoelace = 0.0;
  for (int k = 0; k < 4; ++k) shoelace += 0.5 * (c[k][0] * c[(k + 1) % 4][1] - c[(k + 1) % 4][0] * c[k][1]);
  EXPECT_NEAR(area(m), shoelace, 1e-14);
  const std::vector<std::pair<std::string, int>> sides = {{"bottom", 0}, {"right", 1}, {"top", 2}, {"left", 3}};
  const int from[4] = {0, 1, 2, 3}, to[4] = {1, 2, 3, 0};
  for (const auto& [name, edge] : sides) {
    ASSERT_EQ(m.boundary(name).size(), 1u) << name;
    EXPECT_EQ(m.boundary(name)[0].edge, edge) << name;
    const double straight = std::hypot(c[to[edge]][0] - c[from[edge]][0], c[to[edge]][1] - c[from[edge]][1]);
    EXPECT_NEAR(length(m, name), straight, 1e-14) << name;
  }
  EXPECT_EQ(m.group_names(), std::vector<std::string>{"fluid"});
}

// A transfinite rectangle meshed from its .geo: 6 x 4 elements, area and side lengths exact to
// rounding, every edge in its physical curve.
TEST_F(GmshMeshTest, TransfiniteRectangleFromGeo) {
  const Mesh m = read_gmsh_mesh(write_file(path("rectangle.geo"), kRectangleGeo));
  EXPECT_EQ(m.num_elements(), 24);
  EXPECT_EQ(m.num_nodes(), 13 * 9);
  EXPECT_GT(m.jacobian_range().first, 0.0);
  EXPECT_NEAR(area(m), 3.0, 1e-13);
  const std::map<std::string, std::pair<std::size_t, double>> sides = {
      {"bottom", {6, 3.0}}, {"top", {6, 3.0}}, {"inflow", {4, 1.0}}, {"outflow", {4, 1.0}}};
  EXPECT_EQ(m.boundary_names().size(), sides.size());
  for (const auto& [name, expected] : sides) {
    EXPECT_EQ(m.boundary(name).size(), expected.first) << name;
    EXPECT_NEAR(length(m, name), expected.second, 1e-14) << name;
  }
  for (int n : m.boundary_nodes("outflow")) EXPECT_NEAR(m.node(n)[0], 3.0, 1e-15);
}

// A surface whose curve loop runs clockwise gives clockwise elements (det J < 0 everywhere): the
// surface is reversed, not inverted, and is read counter-clockwise with the same area.
TEST_F(GmshMeshTest, ClockwiseSurfaceIsReordered) {
  const std::string geo = replace(kRectangleGeo, "Curve Loop(1) = {1, 2, 3, 4};", "Curve Loop(1) = {-4, -3, -2, -1};");
  const Mesh m = read_gmsh_mesh(write_file(path("clockwise.geo"), geo));
  EXPECT_GT(m.jacobian_range().first, 0.0);
  EXPECT_NEAR(area(m), 3.0, 1e-13);
  EXPECT_NEAR(length(m, "bottom"), 3.0, 1e-14);
}

// Geo parameters replace a DefineConstant's default before the .geo is parsed.
TEST_F(GmshMeshTest, GeoParameterChangesTheGeometry) {
  const std::string geo = write_file(path("rectangle.geo"), kRectangleGeo);
  const Mesh m = read_gmsh_mesh(geo, {{{"L", 5.0}}});
  EXPECT_NEAR(area(m), 5.0, 1e-13);
  EXPECT_NEAR(length(m, "top"), 5.0, 1e-14);
  // a DefineConstant without a Name, in an included file
  write_file(path("size.geo"), "DefineConstant[ L = 3 ];\n");
  const std::string with_include = replace(
      kRectangleGeo, "DefineConstant[ L = {3, Name \"Parameters/L\"}, unused_default = 1 ];", "Include \"size.geo\";");
  EXPECT_NEAR(area(read_gmsh_mesh(write_file(path("included.geo"), with_include), {{{"L", 0.5}}})), 0.5, 1e-14);
}

TEST_F(GmshMeshTest, UndeclaredGeoParameterIsRefused) {
  const std::string geo = write_file(path("rectangle.geo"), kRectangleGeo);
  const std::string message = refusal(geo, {{{"H", 2.0}}});
  EXPECT_NE(message.find(geo), std::string::npos) << message;
  EXPECT_NE(message.find("'H' is not declared"), std::string::npos) << message;
  EXPECT_NE(message.find("DefineConstant"), std::string::npos) << message;
  EXPECT_NE(message.find("L, unused_default"), std::string::npos) << message;
  // a plain assignment `L = 3;` is not a declaration (it would override the number silently)
  const std::string plain = write_file(
      path("plain.geo"),
      replace(kRectangleGeo, "DefineConstant[ L = {3, Name \"Parameters/L\"}, unused_default = 1 ];", "L = 3;"));
  EXPECT_NE(refusal(plain, {{{"L", 2.0}}}).find("'L' is not declared"), std::string::npos);
  // a .msh has no parameters
  const std::string msh = write_file(path("quad.msh"), single_quad({{{0, 0}, {1, 0}, {1, 1}, {0, 1}}}).text());
  EXPECT_NE(refusal(msh, {{{"L", 2.0}}}).find("geo parameters apply to a .geo"), std::string::npos);
}

// Curved edges are kept: a quarter annulus 1 <= r <= 2 at three sizes.
// Theory: Gmsh puts an edge's middle node on the arc at its parametric (angular) midpoint, so each
// boundary edge of angle d is the quadratic through three points of the circle. The gap between arc
// and quadratic is an odd cubic in the edge's parameter to leading order (the interpolation error
// f'''/6 s (s^2 - 1)), whose integral vanishes, so the area each edge misses is O(d^5), not O(d^4):
// over O(1/d) edges the area error is O(h^4), twice the order 2 of the geometry (the superconvergence
// of the isoparametric area). The Gauss rule integrates det J of the Q2 map exactly, so the area is
// exactly that of the region the quadratic edges bound. Measured errors below: 1.16e-4, 7.29e-6,
// 4.56e-7 (8, 32, 128 elements), observed orders 3.995 and 3.999.
TEST_F(GmshMeshTest, CurvedBoundaryAreaConvergesAtTheOrderOfTheGeometry) {
  const std::string geo = write_file(path("annulus.geo"), R"(
DefineConstant[ n = 2 ];
Point(1) = {0, 0, 0}; Point(2) = {1, 0, 0}; Point(3) = {2, 0, 0}; Point(4) = {0, 2, 0}; Point(5) = {0, 1, 0};
Line(1) = {2, 3}; Circle(2) = {3, 1, 4}; Line(3) = {4, 5}; Circle(4) = {5, 1, 2};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = n + 1; Transfinite Curve{2, 4} = 2 * n + 1;
Transfinite Surface{1};
Recombine Surface{1};
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 0;
Physical Surface("fluid") = {1};
Physical Curve("axes") = {1, 3}; Physical Curve("outer") = {2}; Physical Curve("inner") = {4};
)");
  std::vector<double> errors;
  for (double n : {2.0, 4.0, 8.0}) {
    const Mesh m = read_gmsh_mesh(geo, {{{"n", n}}});
    EXPECT_EQ(m.num_elements(), static_cast<int>(2 * n * n));
    EXPECT_GT(m.jacobian_range().first, 0.0);
    errors.push_back(std::abs(area(m) - 0.75 * kPi));
    // every node of the curved boundaries on its circle, the middle nodes included
    for (int node : m.boundary_nodes("outer")) EXPECT_NEAR(std::hypot(m.node(node)[0], m.node(node)[1]), 2.0, 1e-14);
    for (int node : m.boundary_nodes("inner")) EXPECT_NEAR(std::hypot(m.node(node)[0], m.node(node)[1]), 1.0, 1e-14);
  }
  for (int k = 0; k < 2; ++k) {
    const double order = std::log2(errors[k] / errors[k + 1]);
    // the O(h^5) remainder moves the observed order by less than 0.05 from the coarsest pair on
    EXPECT_NEAR(order, 4.0, 0.05) << "errors " << errors[k] << " " << errors[k + 1];
  }
}

// The cylinder's block mesh (curved edges on the cylinder) written and read back.
TEST_F(GmshMeshTest, CylinderMeshRoundTrip) {
  const Mesh original = build_cylinder_mesh(CylinderOptions{});
  write_gmsh_mesh(original, path("cylinder.msh"));
  expect_same_mesh(original, read_gmsh_mesh(path("cylinder.msh")));
}

// Two groups glued along an interface that both sides list (as the channel's fluid and solid do):
// the line's direction keeps the element it belongs to.
TEST_F(GmshMeshTest, TwoGroupRoundTripKeepsBothSidesOfAnInterface) {
  BlockMeshBuilder builder;
  BlockSpec fluid{"fluid",
                  "fluid",
                  3,
                  2,
                  {},
                  {},
                  [](double s, double t) {
                    return Mesh::Point{2 * s, t};
                  },
                  {"bottom", "outflow", "interface", "inflow"}};
  BlockSpec solid{"solid",
                  "solid",
                  3,
                  1,
                  {},
                  {},
                  [](double s, double t) {
                    return Mesh::Point{2 * s, 1 + 0.3 * t + 0.1 * t * std::sin(kPi * s)};
                  },
                  {"interface", "solid_right", "solid_top", "solid_left"}};
  const int f = builder.add_block(fluid), s = builder.add_block(solid);
  builder.connect(f, Side::Top, s, Side::Bottom);
  const Mesh original = builder.build();
  ASSERT_EQ(original.boundary("interface").size(), 6u);
  write_gmsh_mesh(original, path("two.msh"));
  expect_same_mesh(original, read_gmsh_mesh(path("two.msh")));
}

// A .geo run can hand back the mesh Gmsh made; read from a file, it is the same mesh.
TEST_F(GmshMeshTest, GeneratedMeshIsReturnedAsMshBytes) {
  const std::string geo = write_file(path("rectangle.geo"), kRectangleGeo);
  std::string bytes;
  const Mesh m = read_gmsh_mesh(geo, {{{"L", 4.0}}}, &bytes);
  ASSERT_EQ(bytes.rfind("$MeshFormat\n4.1 1 8", 0), 0u) << bytes.substr(0, 40);
  expect_same_mesh(m, read_gmsh_mesh(write_file(path("generated.msh"), bytes)));
  EXPECT_NEAR(area(m), 4.0, 1e-13);
}
