// Gmsh meshes in and out, through the Gmsh C++ API (libgmsh): a .msh file (any version Gmsh reads)
// or a .geo file meshed at run time becomes keller's Mesh of 9-node quadrilaterals, and a Mesh
// becomes a .msh file. docs/meshes.md is the user's page: what a .geo must contain and every
// refusal.
//
// What is read: the 2D elements of the 2D physical groups (the element groups, by name) and the
// line elements of the 1D physical groups (the boundaries, by name, as lists of element edges).
// Elements in no physical group are ignored, as Gmsh does when groups exist. Every 2D element must
// be a 9-node quadrilateral (Gmsh type 10: `Recombine`, `Mesh.ElementOrder = 2`,
// `Mesh.SecondOrderIncomplete = 0`), every line of a 1D group a 3-node line; the mesh must be
// conforming, no element inverted or degenerate, and every edge on the outer boundary in a 1D
// physical group. Anything else is refused with a MeshFileError before any work. Curved edges are
// kept (the mid-edge and centre nodes where Gmsh put them). Nodes are numbered in the order of
// their Gmsh tags, elements in the order of theirs; an element of a clockwise surface (det J < 0
// at every Gauss point of every element of that surface) is reordered counter-clockwise.
//
// Gmsh runs in a child process for each call (core/GmshProcess.hpp): a file that crashes Gmsh, makes
// it exit or ask for all the memory is refused like any other, and none of Gmsh's output reaches
// the terminal.
#pragma once

#include <map>
#include <string>

#include "core/Mesh.hpp"
#include "core/MeshFileError.hpp"

namespace keller {

struct GmshOptions {
  // .geo only: numbers set before the geometry is parsed. Each name must be declared in the .geo
  // (or a file it includes) with DefineConstant[ name = default ... ], which the number replaces;
  // a name the .geo does not declare that way is refused, naming it and the file.
  std::map<std::string, double> geo_parameters;
};

// Reads a .msh file, or meshes a .geo file in 2D with the .geo's own settings, into keller's Mesh.
// Throws MeshFileError for a file that cannot be read or a mesh keller cannot use.
Mesh read_gmsh_mesh(const std::string& path, const GmshOptions& options = {});
// The same; for a .geo, *generated_msh (when not null) receives the mesh Gmsh made, as the bytes
// of a binary .msh 4.1 file holding the elements of its physical groups, so that a run can store
// the mesh it used (read_gmsh_mesh of those bytes written to a file gives the same Mesh). For a
// .msh it is left as it is.
Mesh read_gmsh_mesh(const std::string& path, const GmshOptions& options, std::string* generated_msh);

// Writes a Mesh as a binary .msh 4.1 file (binary: node positions exact to the bit) with its element
// groups as 2D physical groups and its boundaries as 1D physical groups of 3-node lines; node n and
// element e get Gmsh tag n + 1 and e + 1, so that read_gmsh_mesh gives back the same nodes,
// connectivity, groups and boundaries (nodes in no element are not kept, nor the Mesh's blocks).
// The file is written under a temporary name and renamed when complete (core/PendingFile).
// Throws MeshFileError naming the file when it cannot be written.
void write_gmsh_mesh(const Mesh& mesh, const std::string& path);

}  // namespace keller
