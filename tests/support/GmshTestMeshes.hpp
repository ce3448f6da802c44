// Helpers of the Gmsh mesh tests (tests/unit/GmshMeshTest.cpp, GmshMeshRefusalTest.cpp): meshes and
// .msh files made by hand, a fixture with a scratch folder, areas, lengths and mesh comparison.
#pragma once

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "core/GmshMesh.hpp"
#include "support/TestSupport.hpp"

namespace keller::test {

inline const double kPi = std::acos(-1.0);

inline std::string write_file(const std::string& path, const std::string& text) {
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

inline double area(const Mesh& m) {
  double a = 0.0;
  for (int e = 0; e < m.num_elements(); ++e) {
    double xy[9][2];
    m.element_nodes(e, xy);
    std::array<QpGeometry<double>, ref::kQp> g;
    EXPECT_TRUE(map_element(xy, g)) << "element " << e;
    for (const auto& q : g) a += q.wdetJ;
  }
  return a;
}

inline double length(const Mesh& m, const std::string& boundary) {
  double l = 0.0;
  for (const BoundaryEdge& be : m.boundary(boundary)) {
    double xy[9][2];
    m.element_nodes(be.element, xy);
    std::array<EdgeQpGeometry<double>, ref::kEdgeQp> g;
    EXPECT_TRUE(map_edge(xy, be.edge, g));
    for (const auto& q : g) l += q.wds;
  }
  return l;
}

// A .msh file in Gmsh's plain format 2.2, written by hand so that a test controls every element.
struct Msh22 {
  std::vector<Mesh::Point> nodes;  // tag = index + 1
  struct Element {
    int type, physical, entity;
    std::vector<int> nodes;  // node tags
  };
  std::vector<Element> elements;                         // tag = index + 1
  std::vector<std::tuple<int, int, std::string>> names;  // dim, physical tag, name

  std::string text() const {
    std::string t = "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n" + std::to_string(names.size()) + "\n";
    for (const auto& [dim, tag, name] : names) t += fmt::format("{} {} \"{}\"\n", dim, tag, name);
    t += fmt::format("$EndPhysicalNames\n$Nodes\n{}\n", nodes.size());
    for (std::size_t n = 0; n < nodes.size(); ++n)
      t += fmt::format("{} {:.17g} {:.17g} 0\n", n + 1, nodes[n][0], nodes[n][1]);
    t += fmt::format("$EndNodes\n$Elements\n{}\n", elements.size());
    for (std::size_t e = 0; e < elements.size(); ++e) {
      t += fmt::format("{} {} 2 {} {}", e + 1, elements[e].type, elements[e].physical, elements[e].entity);
      for (int n : elements[e].nodes) t += fmt::format(" {}", n);
      t += "\n";
    }
    return t + "$EndElements\n";
  }
};

// One straight quadrilateral with corners p0..p3 counter-clockwise as a 9-node Gmsh element (corners,
// mid-edges, centre: the bilinear map's points), its four sides as named 3-node lines.
inline Msh22 single_quad(const std::array<Mesh::Point, 4>& c) {
  auto bilinear = [&](double s, double t) {
    Mesh::Point p{};
    for (int i = 0; i < 2; ++i)
      p[i] = 0.25 * ((1 - s) * (1 - t) * c[0][i] + (1 + s) * (1 - t) * c[1][i] + (1 + s) * (1 + t) * c[2][i] +
                     (1 - s) * (1 + t) * c[3][i]);
    return p;
  };
  Msh22 m;
  // Gmsh's 9-node quadrilateral: corners (-1,-1) (1,-1) (1,1) (-1,1), mid-edges 01 12 23 30, centre.
  const double st[9][2] = {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}, {0, -1}, {1, 0}, {0, 1}, {-1, 0}, {0, 0}};
  for (const auto& p : st) m.nodes.push_back(bilinear(p[0], p[1]));
  m.names = {{1, 1, "bottom"}, {1, 2, "right"}, {1, 3, "top"}, {1, 4, "left"}, {2, 5, "fluid"}};
  m.elements = {{8, 1, 1, {1, 2, 5}},
                {8, 2, 2, {2, 3, 6}},
                {8, 3, 3, {3, 4, 7}},
                {8, 4, 4, {4, 1, 8}},
                {10, 5, 1, {1, 2, 3, 4, 5, 6, 7, 8, 9}}};
  return m;
}

// Builds a keller Mesh from straight elements given by corner boxes [x0,x1]x[y0,y1], merging nodes
// at equal positions; every outer edge in boundary "wall".
struct BoxMesh {
  std::vector<Mesh::Point> nodes;
  std::map<Mesh::Point, int> index;
  std::vector<std::array<int, 9>> elements;
  int node(double x, double y) {
    auto [it, fresh] = index.emplace(Mesh::Point{x, y}, static_cast<int>(nodes.size()));
    if (fresh) nodes.push_back({x, y});
    return it->second;
  }
  int box(double x0, double x1, double y0, double y1) {
    std::array<int, 9> el{};
    for (int a = 0; a < 9; ++a) {
      const double s = ref::node_s(a), t = ref::node_t(a);
      el[a] = node(x0 + 0.5 * (s + 1) * (x1 - x0), y0 + 0.5 * (t + 1) * (y1 - y0));
    }
    elements.push_back(el);
    return static_cast<int>(elements.size()) - 1;
  }
  Mesh mesh(std::map<std::string, std::vector<BoundaryEdge>> boundaries) const {
    return Mesh(nodes, elements, std::vector<int>(elements.size(), 0), {"fluid"}, std::move(boundaries), {});
  }
};

// Every edge of one element only, in "wall".
inline std::map<std::string, std::vector<BoundaryEdge>> outer_edges(const std::vector<std::array<int, 9>>& elements) {
  std::map<std::pair<int, int>, std::vector<BoundaryEdge>> uses;
  for (int e = 0; e < static_cast<int>(elements.size()); ++e)
    for (int k = 0; k < 4; ++k) {
      const int a = elements[e][ref::edge_nodes[k][0]], b = elements[e][ref::edge_nodes[k][2]];
      uses[{std::min(a, b), std::max(a, b)}].push_back({e, k});
    }
  std::vector<BoundaryEdge> wall;
  for (const auto& [key, list] : uses)
    if (list.size() == 1) wall.push_back(list[0]);
  return {{"wall", wall}};
}

// A rectangle L x 1, transfinite 6 x 4 quadrilaterals of order 2; L a DefineConstant.
inline const char* const kRectangleGeo = R"(// a rectangle for GmshMeshTest
DefineConstant[ L = {3, Name "Parameters/L"}, unused_default = 1 ];
Point(1) = {0, 0, 0}; Point(2) = {L, 0, 0}; Point(3) = {L, 1, 0}; Point(4) = {0, 1, 0};
Line(1) = {1, 2}; Line(2) = {2, 3}; Line(3) = {3, 4}; Line(4) = {4, 1};
Curve Loop(1) = {1, 2, 3, 4};
Plane Surface(1) = {1};
Transfinite Curve{1, 3} = 7; Transfinite Curve{2, 4} = 5;
Transfinite Surface{1};
Recombine Surface{1};
Mesh.ElementOrder = 2;
Mesh.SecondOrderIncomplete = 0;
Physical Surface("fluid") = {1};
Physical Curve("bottom") = {1}; Physical Curve("outflow") = {2}; Physical Curve("top") = {3};
Physical Curve("inflow") = {4};
)";

inline std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

class GmshMeshTest : public ::testing::Test {
 protected:
  std::string dir = scratch_dir("gmsh_mesh");
  std::string path(const std::string& name) const { return dir + "/" + name; }
  // The message of the MeshFileError read_gmsh_mesh throws ("" if it reads the file).
  std::string refusal(const std::string& file, const GmshOptions& options = {}) const {
    try {
      read_gmsh_mesh(file, options);
    } catch (const MeshFileError& e) {
      return e.what();
    }
    return "";
  }
};

inline void expect_same_mesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.num_nodes(), b.num_nodes());
  ASSERT_EQ(a.num_elements(), b.num_elements());
  for (int n = 0; n < a.num_nodes(); ++n) {
    EXPECT_EQ(a.node(n)[0], b.node(n)[0]) << "node " << n;  // exact: the .msh is binary
    EXPECT_EQ(a.node(n)[1], b.node(n)[1]) << "node " << n;
  }
  for (int e = 0; e < a.num_elements(); ++e) {
    EXPECT_EQ(a.element(e), b.element(e)) << "element " << e;
    EXPECT_EQ(a.element_group(e), b.element_group(e)) << "element " << e;
  }
  EXPECT_EQ(a.group_names(), b.group_names());
  ASSERT_EQ(a.boundary_names(), b.boundary_names());
  for (const std::string& name : a.boundary_names()) {
    ASSERT_EQ(a.boundary(name).size(), b.boundary(name).size()) << name;
    for (std::size_t k = 0; k < a.boundary(name).size(); ++k) {
      EXPECT_EQ(a.boundary(name)[k].element, b.boundary(name)[k].element) << name << " " << k;
      EXPECT_EQ(a.boundary(name)[k].edge, b.boundary(name)[k].edge) << name << " " << k;
    }
  }
}

}  // namespace keller::test
