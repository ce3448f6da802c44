// Geometry and meshes of the channel of model.md: a 2D channel of width 1 made of an upstream
// rigid part (length Lu), a deformable part (length L, where the solid wall of thickness t sits
// on top) and a downstream rigid part (Ld). Named meshes M1..M5 reproduce the element counts
// of the reference study (M1 400, M2 900, M3 1600 elements fluid + solid; M4, M5 finer), and
// grade elements towards the ends of the deformable section and towards the walls.
#pragma once

#include <string>
#include <vector>

#include "core/Mesh.hpp"
#include "core/Scene.hpp"

namespace keller {

struct ChannelGeometry {
  double upstream_length = 7.0;    // Lu
  double deformable_length = 5.0;  // L
  double downstream_length = 7.0;  // Ld
  double thickness = 0.4;          // t, wall thickness (solid block only)
  double total_length() const { return upstream_length + deformable_length + downstream_length; }
};

struct ChannelMeshSpec {
  std::string name = "M1";
  int nx_upstream = 10, nx_deformable = 20, nx_downstream = 10;  // fluid columns per block
  int ny_fluid = 8;                                              // fluid rows
  int ny_solid = 4;                                              // solid rows (deformable wall)
  double ratio_x = 3.0;  // deformable block: largest / smallest column width (fine at both ends)
  double ratio_y = 2.0;  // fluid rows: largest / smallest (fine at both walls)
  // The rigid blocks are graded geometrically so that the column next to the deformable
  // section matches its end column.

  static ChannelMeshSpec preset(const std::string& name);  // "M1".."M5"; throws on unknown
  static std::vector<std::string> preset_names();
  int fluid_elements() const { return (nx_upstream + nx_deformable + nx_downstream) * ny_fluid; }
  int solid_elements() const { return nx_deformable * ny_solid; }
};

// Blocks: "upstream", "deformable", "downstream" (group "fluid") and, if with_solid, "wall"
// (group "solid"). Boundaries: inflow, outflow, bottom_wall, top_wall (rigid top, both rigid
// parts), interface (top of the deformable fluid block; also bottom of the solid), and for the
// solid: wall_top, wall_left, wall_right.
Mesh build_channel_mesh(const ChannelGeometry& geometry, const ChannelMeshSpec& spec, bool with_solid);

// The wall block alone (group "solid", boundaries interface, wall_top, wall_left, wall_right),
// with the same columns as the wall of build_channel_mesh.
Mesh build_wall_mesh(const ChannelGeometry& geometry, const ChannelMeshSpec& spec);

// Scene keys of [geometry] and [mesh], and reading them back.
void declare_channel_mesh_keys(SceneSchema& schema);
ChannelGeometry channel_geometry_from(const Scene& scene);
ChannelMeshSpec channel_mesh_spec_from(const Scene& scene);

}  // namespace keller
