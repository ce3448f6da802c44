// The error of a mesh file keller cannot use (core/GmshMesh.hpp): its message names the file, the
// element or physical group (with the tags Gmsh shows) and what to change.
#pragma once

#include <stdexcept>

namespace keller {

class MeshFileError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace keller
