#include "core/GmshMesh.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <set>
#include <unordered_map>

#include "core/GeoConstants.hpp"
#include "core/GmshProcess.hpp"
#include "core/GmshSession.hpp"
#include "core/ImportedMesh.hpp"
#include "core/IoError.hpp"
#include "core/PendingFile.hpp"

namespace keller {

namespace {

constexpr int kGmshQuad9 = 10;  // Gmsh's element types: 9-node quadrilateral, 3-node line
constexpr int kGmshLine3 = 8;
// Gmsh's node k of a 9-node quadrilateral (corners, mid-edges, centre, counter-clockwise) at
// keller's node a = i + 3 j (core/ReferenceElement.hpp).
constexpr std::array<int, 9> kGmshOfKeller = {0, 4, 1, 7, 8, 5, 3, 6, 2};

const char* const kQuadOrder2 =
    "`Recombine Surface{...};` (or `Mesh.RecombineAll = 1;`, with `Mesh.SubdivisionAlgorithm = 1;` if "
    "triangles remain), `Mesh.ElementOrder = 2;` and `Mesh.SecondOrderIncomplete = 0;`";

bool has_extension(const std::string& path, const std::string& ext) {
  std::string e = std::filesystem::path(path).extension().string();
  std::transform(e.begin(), e.end(), e.begin(), [](unsigned char c) { return std::tolower(c); });
  return e == ext;
}

bool is_name(const std::string& s) {
  return !s.empty() && (std::isalpha(static_cast<unsigned char>(s[0])) || s[0] == '_') &&
         std::all_of(s.begin(), s.end(), [](unsigned char c) { return std::isalnum(c) || c == '_'; });
}

void check_geo_parameters(const std::string& path, const GmshOptions& options) {
  if (options.geo_parameters.empty()) return;
  const std::set<std::string> declared = declared_geo_constants(path);
  for (const auto& [name, value] : options.geo_parameters) {
    if (!is_name(name) || !declared.count(name)) {
      throw MeshFileError(
          fmt::format("{}: geo parameter '{}' is not declared in it; a parameter must be declared in the .geo with "
                      "`DefineConstant[ {} = {{default, Name \"...\"}} ];` (declared there: {})",
                      path, name, is_name(name) ? name : "name",
                      declared.empty() ? "none" : fmt::format("{}", fmt::join(declared, ", "))));
    }
    if (!std::isfinite(value))
      throw MeshFileError(fmt::format("{}: geo parameter '{}' is not a finite number", path, name));
  }
}

std::string group_name(const GmshSession& session, int dim, int tag) {
  const std::string name = session.api().physical_name(dim, tag);
  if (name.empty()) {
    throw MeshFileError(fmt::format(
        "{}: physical {} {} has no name; keller refers to groups by name: in the .geo, write `Physical {}(\"name\") = "
        "{{...}};`",
        session.file(), dim == 2 ? "surface" : "curve", tag, dim == 2 ? "Surface" : "Curve"));
  }
  return name;
}

// What a 2D or 1D element of the wrong kind should be, and what to change in the .geo.
std::string element_refusal(const GmshSession& session, int type, std::size_t tag, int dim, const std::string& group) {
  const GmshApi::ElementType properties = session.api().element_type(type);
  const int order = properties.order, num_primary = properties.num_primary_nodes;
  std::string fix;
  if (dim == 1) {
    fix = "set `Mesh.ElementOrder = 2;` and `Mesh.SecondOrderIncomplete = 0;` (3-node lines)";
  } else if (num_primary == 3) {
    fix = std::string("recombine the triangles into quadrilaterals of order 2: ") + kQuadOrder2;
  } else if (num_primary == 4 && order == 1) {
    fix = "set `Mesh.ElementOrder = 2;` and `Mesh.SecondOrderIncomplete = 0;`";
  } else if (num_primary == 4 && order == 2) {
    fix = "set `Mesh.SecondOrderIncomplete = 0;` (9-node quadrilaterals, with their centre node)";
  } else if (num_primary == 4) {
    fix = "set `Mesh.ElementOrder = 2;` and `Mesh.SecondOrderIncomplete = 0;`";
  } else {
    fix = std::string("make quadrilaterals of order 2: ") + kQuadOrder2;
  }
  return fmt::format(
      "{}: element {} of physical {} '{}' is a {} (Gmsh element type {}, {} nodes); keller needs {}: in "
      "the .geo, {}",
      session.file(), tag, dim == 2 ? "surface" : "curve", group, properties.name, type, properties.num_nodes,
      dim == 2 ? "9-node quadrilaterals (\"Quadrilateral 9\")" : "3-node lines (\"Line 3\")", fix);
}

struct RawElements {
  std::vector<std::size_t> tags;
  std::vector<std::size_t> nodes;  // Gmsh node tags, n per element
};

// The elements of one physical group, entity by entity (entity tag -> elements of the wanted type).
std::vector<std::pair<int, RawElements>> group_elements(const GmshSession& session, int dim, int group_tag,
                                                        const std::string& name, int wanted_type) {
  std::vector<std::pair<int, RawElements>> out;
  for (int entity : session.api().entities_for_physical_group(dim, group_tag)) {
    const GmshApi::Elements elements = session.api().elements(dim, entity);
    const auto& [types, tags, nodes] = elements;
    RawElements raw;
    for (std::size_t t = 0; t < types.size(); ++t) {
      if (tags[t].empty()) continue;
      if (types[t] != wanted_type) throw MeshFileError(element_refusal(session, types[t], tags[t][0], dim, name));
      raw.tags.insert(raw.tags.end(), tags[t].begin(), tags[t].end());
      raw.nodes.insert(raw.nodes.end(), nodes[t].begin(), nodes[t].end());
    }
    out.emplace_back(entity, std::move(raw));
  }
  return out;
}

// What Gmsh may allocate reading a .msh: it needs some hundred bytes per byte of the file at most;
// 1000 per byte and 2 GB for the library itself are far above that, and far below what a damaged
// node or element count asks for.
std::size_t msh_memory_limit(const std::string& path) {
  constexpr std::size_t kBase = std::size_t{2} << 30, kPerByte = 1000;
  return kBase + kPerByte * static_cast<std::size_t>(std::filesystem::file_size(path));
}

// Gmsh's model (already read or meshed) as an ImportedMesh.
ImportedMesh gather(const GmshSession& session) {
  ImportedMesh mesh;
  mesh.file = session.file();
  GmshApi& api = session.api();
  if (api.dimension() > 2)
    throw MeshFileError(session.file() + ": the mesh is 3D; keller solves 2D flows: mesh the geometry in 2D");
  const auto surfaces = api.physical_groups(2);
  const auto curves = api.physical_groups(1);
  if (surfaces.empty()) {
    throw MeshFileError(session.file() +
                        ": no 2D physical group (no 2D mesh, or its surfaces in no group); keller's element groups are "
                        "the named physical surfaces: in the .geo, add `Physical Surface(\"fluid\") = {...};`");
  }
  struct Quad {
    std::size_t tag;
    int surface, group;
    std::array<std::size_t, 9> nodes;
  };
  std::vector<Quad> quads;
  std::unordered_map<std::size_t, std::string> group_of_element;
  for (const auto& [dim, tag] : surfaces) {
    const std::string name = group_name(session, 2, tag);
    auto it = std::find(mesh.group_names.begin(), mesh.group_names.end(), name);
    const int group = static_cast<int>(it - mesh.group_names.begin());
    if (it == mesh.group_names.end()) mesh.group_names.push_back(name);
    for (const auto& [surface, raw] : group_elements(session, 2, tag, name, kGmshQuad9)) {
      for (std::size_t e = 0; e < raw.tags.size(); ++e) {
        auto [seen, fresh] = group_of_element.emplace(raw.tags[e], name);
        if (!fresh && seen->second == name) continue;
        if (!fresh) {
          throw MeshFileError(fmt::format(
              "{}: element {} is in two physical surfaces, '{}' and '{}'; each element belongs to one group: in the "
              ".geo, put each surface in one Physical Surface",
              session.file(), raw.tags[e], seen->second, name));
        }
        Quad q{raw.tags[e], surface, group, {}};
        for (int a = 0; a < 9; ++a) q.nodes[a] = raw.nodes[9 * e + kGmshOfKeller[a]];
        quads.push_back(q);
      }
    }
  }
  std::sort(quads.begin(), quads.end(), [](const Quad& a, const Quad& b) { return a.tag < b.tag; });
  if (quads.empty())
    throw MeshFileError(session.file() + ": the physical surfaces hold no elements: mesh the surfaces in 2D");

  std::vector<std::size_t> node_tags;
  for (const Quad& q : quads) node_tags.insert(node_tags.end(), q.nodes.begin(), q.nodes.end());
  std::sort(node_tags.begin(), node_tags.end());
  node_tags.erase(std::unique(node_tags.begin(), node_tags.end()), node_tags.end());
  std::unordered_map<std::size_t, int> index;
  for (std::size_t n = 0; n < node_tags.size(); ++n) index[node_tags[n]] = static_cast<int>(n);
  std::vector<std::size_t> all_tags;
  std::vector<double> coords;
  api.nodes(all_tags, coords);
  mesh.nodes.assign(node_tags.size(), {0.0, 0.0});
  std::vector<char> found(node_tags.size(), 0);
  std::size_t off_plane = 0;  // the used node farthest from z = 0 (its index in all_tags)
  double extent = 0.0, off = 0.0;
  for (std::size_t k = 0; k < all_tags.size(); ++k) {
    auto it = index.find(all_tags[k]);
    if (it == index.end()) continue;
    if (std::abs(coords[3 * k + 2]) > off) {
      off = std::abs(coords[3 * k + 2]);
      off_plane = k;
    }
    extent = std::max({extent, std::abs(coords[3 * k]), std::abs(coords[3 * k + 1])});
    mesh.nodes[it->second] = {coords[3 * k], coords[3 * k + 1]};
    found[it->second] = 1;
  }
  if (off > 1e-12 * std::max(extent, 1.0)) {
    throw MeshFileError(
        fmt::format("{}: node {} is at z = {} off the plane z = 0; keller's meshes are plane: in the "
                    ".geo, put every point at z = 0",
                    session.file(), all_tags[off_plane], coords[3 * off_plane + 2]));
  }
  for (std::size_t n = 0; n < node_tags.size(); ++n)
    if (!found[n])
      throw MeshFileError(fmt::format("{}: node {} of an element is not in the file", session.file(), node_tags[n]));
  mesh.node_tags = node_tags;
  for (const Quad& q : quads) {
    ImportedQuad quad{{}, q.tag, q.surface, q.group};
    for (int a = 0; a < 9; ++a) quad.nodes[a] = index.at(q.nodes[a]);
    mesh.quads.push_back(quad);
  }

  for (const auto& [dim, tag] : curves) {
    const std::string name = group_name(session, 1, tag);
    std::vector<ImportedLine>& lines = mesh.boundaries[name];
    for (const auto& [curve, raw] : group_elements(session, 1, tag, name, kGmshLine3)) {
      for (std::size_t e = 0; e < raw.tags.size(); ++e) {
        ImportedLine line{{}, raw.tags[e]};
        for (int a = 0; a < 3; ++a) {
          auto it = index.find(raw.nodes[3 * e + a]);
          if (it == index.end()) {
            throw MeshFileError(fmt::format(
                "{}: line element {} of physical curve '{}' (Gmsh curve {}) is not an edge of the 2D elements: its "
                "node {} is in no element of a physical surface; in the .geo, put in physical curves only curves "
                "that bound a physical surface",
                session.file(), raw.tags[e], name, curve, raw.nodes[3 * e + a]));
          }
          line.nodes[a] = it->second;
        }
        lines.push_back(line);
      }
    }
    std::sort(lines.begin(), lines.end(), [](const ImportedLine& a, const ImportedLine& b) { return a.tag < b.tag; });
  }
  return mesh;
}

// A keller Mesh as Gmsh's model: one discrete surface per element group, one discrete curve per
// boundary (its lines counter-clockwise around their element), the physical groups named.
void make_model(GmshApi& api, const Mesh& mesh) {
  api.add_model("keller");
  const int num_groups = static_cast<int>(mesh.group_names().size());
  for (int g = 0; g < num_groups; ++g) api.add_discrete_entity(2, g + 1);
  std::vector<std::size_t> node_tags(mesh.num_nodes());
  std::vector<double> coords;
  for (int n = 0; n < mesh.num_nodes(); ++n) {
    node_tags[n] = static_cast<std::size_t>(n) + 1;
    coords.insert(coords.end(), {mesh.node(n)[0], mesh.node(n)[1], 0.0});
  }
  api.add_nodes(2, 1, node_tags, coords);
  for (int g = 0; g < num_groups; ++g) {
    std::vector<std::size_t> tags, nodes;
    for (int e : mesh.elements_in_group(g)) {
      tags.push_back(static_cast<std::size_t>(e) + 1);
      std::array<std::size_t, 9> gmsh_nodes{};
      for (int a = 0; a < 9; ++a) gmsh_nodes[kGmshOfKeller[a]] = static_cast<std::size_t>(mesh.element(e)[a]) + 1;
      nodes.insert(nodes.end(), gmsh_nodes.begin(), gmsh_nodes.end());
    }
    api.add_elements_by_type(g + 1, kGmshQuad9, tags, nodes);
    api.add_physical_group(2, {g + 1}, g + 1);
    api.set_physical_name(2, g + 1, mesh.group_names()[g]);
  }
  std::size_t next_tag = static_cast<std::size_t>(mesh.num_elements()) + 1;
  int curve = 0;
  for (const std::string& name : mesh.boundary_names()) {
    ++curve;
    api.add_discrete_entity(1, curve);
    std::vector<std::size_t> tags, nodes;
    for (const BoundaryEdge& be : mesh.boundary(name)) {
      tags.push_back(next_tag++);
      for (int a : ccw_edge_line[be.edge]) nodes.push_back(static_cast<std::size_t>(mesh.element(be.element)[a]) + 1);
    }
    api.add_elements_by_type(curve, kGmshLine3, tags, nodes);
    api.add_physical_group(1, {curve}, curve);
    api.set_physical_name(1, curve, name);
  }
}

// The child's answer: the mesh it read and the .msh bytes of a generated mesh.
std::string encode(const ImportedMesh& raw, const std::string& generated) {
  ByteWriter out;
  out.text(raw.file);
  out.values(raw.nodes);
  out.values(raw.node_tags);
  out.value(raw.group_names.size());
  for (const std::string& name : raw.group_names) out.text(name);
  out.values(raw.quads);
  out.value(raw.boundaries.size());
  for (const auto& [name, lines] : raw.boundaries) {
    out.text(name);
    out.values(lines);
  }
  out.text(generated);
  return out.take();
}

ImportedMesh decode(const std::string& bytes, std::string& generated) {
  ByteReader in(bytes);
  ImportedMesh raw;
  raw.file = in.text();
  raw.nodes = in.values<Mesh::Point>();
  raw.node_tags = in.values<std::size_t>();
  raw.group_names.resize(in.value<std::size_t>());
  for (std::string& name : raw.group_names) name = in.text();
  raw.quads = in.values<ImportedQuad>();
  const auto num_boundaries = in.value<std::size_t>();
  for (std::size_t b = 0; b < num_boundaries; ++b) {
    const std::string name = in.text();
    raw.boundaries[name] = in.values<ImportedLine>();
  }
  generated = in.text();
  return raw;
}

}  // namespace

Mesh read_gmsh_mesh(const std::string& path, const GmshOptions& options) {
  return read_gmsh_mesh(path, options, nullptr);
}

Mesh read_gmsh_mesh(const std::string& path, const GmshOptions& options, std::string* generated_msh) {
  const bool geo = has_extension(path, ".geo");
  if (!geo && !has_extension(path, ".msh"))
    throw MeshFileError(path + ": not a Gmsh file keller reads: give a mesh (.msh) or a geometry (.geo)");
  if (!geo && !options.geo_parameters.empty()) {
    throw MeshFileError(path +
                        ": geo parameters apply to a .geo geometry meshed at run time, not to a .msh mesh: "
                        "remove them, or give the .geo");
  }
  if (!std::ifstream(path, std::ios::binary) || std::filesystem::is_directory(path))
    throw MeshFileError(path + ": cannot be read (no such file, or no permission)");
  if (geo) check_geo_parameters(path, options);
  const std::string answer = run_gmsh_child(path, "reading", geo ? 0 : msh_memory_limit(path), [&] {
    GmshSession session(path);
    session.open(options.geo_parameters);
    if (geo) session.run("meshing", [&] { session.api().generate(2); });
    ImportedMesh raw;
    session.run("reading the mesh of", [&] { raw = gather(session); });
    return encode(raw, geo && generated_msh ? session.msh_bytes() : std::string());
  });
  std::string generated;
  Mesh mesh = build_imported_mesh(decode(answer, generated));
  if (geo && generated_msh) *generated_msh = std::move(generated);
  return mesh;
}

void write_gmsh_mesh(const Mesh& mesh, const std::string& path) {
  const std::string bytes = run_gmsh_child(path, "writing", 0, [&] {
    GmshSession session(path);
    session.run("making the mesh of", [&] { make_model(session.api(), mesh); });
    return session.msh_bytes();
  });
  try {
    PendingFile file(path);
    file.write(bytes);
    file.commit();
  } catch (const IoError& e) {
    throw MeshFileError(path + ": cannot be written: " + e.what());
  }
}

}  // namespace keller
