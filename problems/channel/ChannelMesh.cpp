#include "problems/channel/ChannelMesh.hpp"

#include <algorithm>
#include <stdexcept>

#include "core/BlockMeshBuilder.hpp"

namespace keller {

ChannelMeshSpec ChannelMeshSpec::preset(const std::string& name) {
  // Refinement factors 1, 1.5, 2, 3, 4 of M1; M1..M3 have the element and node counts of the
  // reference study (M1: 400 elements, 1705 nodes; M2: 900, 3757; M3: 1600, 6609).
  static const std::vector<std::pair<std::string, double>> factors = {
      {"M1", 1.0}, {"M2", 1.5}, {"M3", 2.0}, {"M4", 3.0}, {"M5", 4.0}};
  for (const auto& [n, f] : factors) {
    if (n != name) continue;
    ChannelMeshSpec s;
    s.name = name;
    s.nx_upstream = static_cast<int>(10 * f);
    s.nx_deformable = static_cast<int>(20 * f);
    s.nx_downstream = static_cast<int>(10 * f);
    s.ny_fluid = static_cast<int>(8 * f);
    s.ny_solid = static_cast<int>(4 * f);
    return s;
  }
  throw std::invalid_argument("unknown mesh '" + name + "' (M1, M2, M3, M4, M5)");
}

std::vector<std::string> ChannelMeshSpec::preset_names() { return {"M1", "M2", "M3", "M4", "M5"}; }

Mesh build_channel_mesh(const ChannelGeometry& g, const ChannelMeshSpec& s, bool with_solid) {
  if (s.nx_upstream < 1 || s.nx_deformable < 1 || s.nx_downstream < 1 || s.ny_fluid < 1 || s.ny_solid < 1)
    throw std::invalid_argument("channel mesh: every block needs at least one element in each direction");
  const double Lu = g.upstream_length, L = g.deformable_length, Ld = g.downstream_length, t = g.thickness;
  const Grading gy = Grading::both_ends(s.ratio_y);
  const Grading gx_def = Grading::both_ends(s.ratio_x);
  const std::vector<double> sv = gx_def.vertices(s.nx_deformable);
  const double h_end = L * sv[1];  // width of the deformable block's end columns
  auto rigid_ratio = [&](int n, double length) { return std::max(grading_ratio_for_smallest(n, length, h_end), 1.0); };

  BlockMeshBuilder b;
  BlockSpec up{"upstream",
               "fluid",
               s.nx_upstream,
               s.ny_fluid,
               Grading::end(rigid_ratio(s.nx_upstream, Lu)),
               gy,
               [=](double u, double v) {
                 return Mesh::Point{Lu * u, v};
               },
               {"bottom_wall", "", "top_wall", "inflow"}};
  BlockSpec def{"deformable",
                "fluid",
                s.nx_deformable,
                s.ny_fluid,
                gx_def,
                gy,
                [=](double u, double v) {
                  return Mesh::Point{Lu + L * u, v};
                },
                {"bottom_wall", "", "interface", ""}};
  BlockSpec down{"downstream",
                 "fluid",
                 s.nx_downstream,
                 s.ny_fluid,
                 Grading::start(rigid_ratio(s.nx_downstream, Ld)),
                 gy,
                 [=](double u, double v) {
                   return Mesh::Point{Lu + L + Ld * u, v};
                 },
                 {"bottom_wall", "outflow", "top_wall", ""}};
  const int iu = b.add_block(up), id = b.add_block(def), idn = b.add_block(down);
  b.connect(iu, Side::Right, id, Side::Left);
  b.connect(id, Side::Right, idn, Side::Left);
  if (with_solid) {
    if (!(t > 0.0)) throw std::invalid_argument("channel mesh: wall thickness must be > 0");
    BlockSpec wall{"wall",
                   "solid",
                   s.nx_deformable,
                   s.ny_solid,
                   gx_def,
                   Grading::uniform(),
                   [=](double u, double v) {
                     return Mesh::Point{Lu + L * u, 1.0 + t * v};
                   },
                   {"interface", "wall_right", "wall_top", "wall_left"}};
    const int iw = b.add_block(wall);
    b.connect(id, Side::Top, iw, Side::Bottom);
  }
  return b.build();
}

Mesh build_wall_mesh(const ChannelGeometry& g, const ChannelMeshSpec& s) {
  if (s.nx_deformable < 1 || s.ny_solid < 1)
    throw std::invalid_argument("wall mesh: the wall needs at least one element in each direction");
  if (!(g.thickness > 0.0)) throw std::invalid_argument("wall mesh: wall thickness must be > 0");
  const double Lu = g.upstream_length, L = g.deformable_length, t = g.thickness;
  BlockMeshBuilder b;
  b.add_block({"wall",
               "solid",
               s.nx_deformable,
               s.ny_solid,
               Grading::both_ends(s.ratio_x),
               Grading::uniform(),
               [=](double u, double v) {
                 return Mesh::Point{Lu + L * u, 1.0 + t * v};
               },
               {"interface", "wall_right", "wall_top", "wall_left"}});
  return b.build();
}

void declare_channel_mesh_keys(SceneSchema& s) {
  s.section("geometry", "channel lengths in units of the channel width W");
  s.real("geometry.upstream_length", 7.0, "Lu, length of the rigid channel upstream of the deformable section",
         Range::positive());
  s.real("geometry.deformable_length", 5.0, "L, length of the deformable section", Range::positive());
  s.real("geometry.downstream_length", 7.0, "Ld, length of the rigid channel downstream", Range::positive());
  s.section("mesh", "named meshes M1..M5 (element counts of the reference study) or explicit sizes");
  s.string("mesh.name", "M1", "mesh preset; 'custom' takes the sizes below", {"M1", "M2", "M3", "M4", "M5", "custom"});
  // 10^4 elements a side: (2 nx + 1)(2 ny + 1) nodes stay far inside int
  const Range count = Range::between(0, 10'000);
  s.integer("mesh.nx_upstream", 0, "fluid columns upstream (custom meshes; 0 with a preset)", count);
  s.integer("mesh.nx_deformable", 0, "fluid and solid columns along the deformable section (custom)", count);
  s.integer("mesh.nx_downstream", 0, "fluid columns downstream (custom)", count);
  s.integer("mesh.ny_fluid", 0, "fluid rows across the channel (custom)", count);
  s.integer("mesh.ny_solid", 0, "solid rows across the wall (custom)", count);
  s.real("mesh.ratio_x", 3.0, "deformable section: widest / narrowest column (fine at both ends)", Range::at_least(1));
  s.real("mesh.ratio_y", 2.0, "fluid rows: widest / narrowest (fine at both walls)", Range::at_least(1));
}

ChannelGeometry channel_geometry_from(const Scene& scene) {
  ChannelGeometry g;
  g.upstream_length = scene.real("geometry.upstream_length");
  g.deformable_length = scene.real("geometry.deformable_length");
  g.downstream_length = scene.real("geometry.downstream_length");
  return g;
}

ChannelMeshSpec channel_mesh_spec_from(const Scene& scene) {
  const std::string name = scene.string("mesh.name");
  ChannelMeshSpec s;
  const char* sizes[] = {"mesh.nx_upstream", "mesh.nx_deformable", "mesh.nx_downstream", "mesh.ny_fluid",
                         "mesh.ny_solid"};
  if (name == "custom") {
    s.name = "custom";
    for (const char* k : sizes)
      if (scene.integer(k) < 1) throw scene.error(k, "a custom mesh needs every size >= 1");
    s.nx_upstream = static_cast<int>(scene.integer("mesh.nx_upstream"));
    s.nx_deformable = static_cast<int>(scene.integer("mesh.nx_deformable"));
    s.nx_downstream = static_cast<int>(scene.integer("mesh.nx_downstream"));
    s.ny_fluid = static_cast<int>(scene.integer("mesh.ny_fluid"));
    s.ny_solid = static_cast<int>(scene.integer("mesh.ny_solid"));
  } else {
    for (const char* k : sizes)
      if (scene.differs_from_default(k))
        throw scene.error(k, "explicit sizes need mesh.name = \"custom\" (got \"" + name + "\")");
    s = ChannelMeshSpec::preset(name);
  }
  s.ratio_x = scene.real("mesh.ratio_x");
  s.ratio_y = scene.real("mesh.ratio_y");
  return s;
}

}  // namespace keller
