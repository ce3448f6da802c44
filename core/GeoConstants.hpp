// The names a Gmsh .geo file declares with DefineConstant[...] (in it and the files it includes):
// the numbers a run may replace (core/GmshMesh.hpp, GmshOptions::geo_parameters). Gmsh 4.8.4's API
// cannot say which names a .geo declares (its ONELAB database lists only those given a `Name` and
// not already set, and it has no parser query), so the text is scanned: comments and strings are
// skipped, and in each DefineConstant[ ... ] every name at the top level of the list before `=`
// is declared. Include "file"; is followed (relative to the including file; at most 16 deep).
#pragma once

#include <set>
#include <string>

namespace keller {

// Throws MeshFileError naming the file if it (or an included file) cannot be read.
std::set<std::string> declared_geo_constants(const std::string& path);

}  // namespace keller
