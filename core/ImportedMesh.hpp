// A mesh as a mesh file gives it, before keller uses it: nodes, 9-node quadrilaterals in keller's
// node order (core/ReferenceElement.hpp) with the file's element and surface tags, and named
// boundaries of 3-node lines. build_imported_mesh checks it and makes keller's Mesh; the reader of
// Gmsh files (core/GmshMesh) fills it, and the checks are tested on it directly.
#pragma once

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include "core/Mesh.hpp"

namespace keller {

struct ImportedQuad {
  std::array<int, 9> nodes;  // indices into ImportedMesh::nodes, keller's order
  std::size_t tag = 0;       // the element's tag in the file
  int surface = 0;           // the tag of the surface it was meshed on
  int group = 0;             // index into ImportedMesh::group_names
};

// The nodes of edge k of a 9-node element (0 bottom, 1 right, 2 top, 3 left) as a line running
// counter-clockwise around the element: its start, its end, its middle.
inline constexpr std::array<std::array<int, 3>, 4> ccw_edge_line = {{{0, 2, 1}, {2, 8, 5}, {8, 6, 7}, {6, 0, 3}}};

struct ImportedLine {
  std::array<int, 3> nodes;  // the two ends, then the middle (indices into nodes, -1: not a quad node)
  std::size_t tag = 0;
};

struct ImportedMesh {
  std::string file;  // named in every error
  std::vector<Mesh::Point> nodes;
  std::vector<std::size_t> node_tags;  // the file's tag of each node
  std::vector<std::string> group_names;
  std::vector<ImportedQuad> quads;
  std::map<std::string, std::vector<ImportedLine>> boundaries;
};

// Checks and converts, throwing MeshFileError (naming the file, the element or group by its tag and
// what to change) for: an element with det J <= 0 at some Gauss point and > 0 at another
// (degenerate), an element with det J < 0 at every Gauss point in a surface that also has
// counter-clockwise elements (inverted; a surface whose elements are all clockwise is reordered),
// an edge of more than two elements, two elements sharing an edge's ends but not its middle node,
// an edge of one element that meets other elements' boundary edges (a hanging node, or two
// surfaces meshed without sharing their curve), a boundary line that is no element edge, and an
// edge of one element in no boundary. A boundary line on an edge of two elements (a line inside
// the domain) is listed with the element on its left, the one it runs counter-clockwise around.
Mesh build_imported_mesh(const ImportedMesh& raw);

}  // namespace keller
