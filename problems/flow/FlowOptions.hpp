// The scene of a `flow` problem: a mesh from Gmsh (a .msh file, or a .geo meshed at run time with
// numbers from the scene), the fluid (any keller fluid and formulation, Stokes or Navier-Stokes),
// a condition on every named boundary, and the observables the scene declares. Keys: [mesh] file /
// geo / region, [mesh.geo_parameters], [boundaries.<name>], [observables.<name>] and the fluid's
// ([fluid], [inflow], [parameters]); docs/flow.md lists them.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "core/Scene.hpp"
#include "problems/components/FlowEquations.hpp"
#include "problems/flow/FlowObservables.hpp"

namespace keller {

struct FlowOptions {
  std::string mesh_path;  // a .msh or .geo file, as the scene names it resolved against the scene's folder
  bool geo = false;       // mesh_path is a .geo to mesh at run time
  std::map<std::string, double> geo_parameters;
  std::string region;  // the fluid's 2D physical group ("": the mesh's only one)
  FluidOptions fluid;
  FlowBoundaries boundaries;
  std::vector<std::string>
      boundary_names;  // every boundary the scene gives a condition, for the check against the mesh
  std::vector<FlowObservableSpec> observables;

  static void declare(SceneSchema& schema);
  // Throws SceneError naming the key for a condition or observable that lacks what it needs
  // (a moving wall without its velocity, a force without its boundary, ...).
  static FlowOptions from_scene(const Scene& scene);
};

}  // namespace keller
