#include "problems/flow/FlowOptions.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cctype>

namespace keller {

namespace {

const std::vector<std::string> kConditions = {"", "wall", "moving-wall", "inflow", "outflow", "symmetry", "traction"};
const std::vector<std::string> kObservables = {"",
                                               "force",
                                               "flow-rate",
                                               "mean-pressure",
                                               "pressure-drop",
                                               "couette-correction",
                                               "reattachment",
                                               "stream-function"};

// Names an observable cannot take: the branch and time tables' own columns, the columns every
// viscoelastic flow adds, and the flow's parameters (a parameter is a column of its branch). A
// table with one name twice could not be read back by name.
const std::vector<std::string> kReservedNames = {"row",        "kind",
                                                 "s",          "iterations",
                                                 "step",       "seconds",
                                                 "det_sign",   "tangent_parameter",
                                                 "saved_slot", "t",
                                                 "h",          "order",
                                                 "error",      "factorisations",
                                                 "rejected",   "next_step",
                                                 "min_m1",     "min_m1_x",
                                                 "min_m1_y",   "max_m3",
                                                 "Re",         "Wi",
                                                 "beta",       "b",
                                                 "Gamma"};

bool identifier(const std::string& name) {
  if (name.empty() || std::isdigit(static_cast<unsigned char>(name[0]))) return false;
  for (char c : name)
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '_') return false;
  return true;
}

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names)
    if (!n.empty()) out += (out.empty() ? "" : ", ") + n;
  return out;
}

std::array<double, 2> vector_of(const Scene& sc, const std::string& key, const std::string& what) {
  const std::vector<double>& v = sc.real_list(key);
  if (v.size() != 2) throw sc.error(key, fmt::format("{} needs two numbers [x, y], got {}", what, v.size()));
  return {v[0], v[1]};
}

}  // namespace

void FlowOptions::declare(SceneSchema& s) {
  s.section("mesh", "a Gmsh mesh of 9-node quadrilaterals (docs/meshes.md): a .msh file or a .geo meshed at run time");
  s.file_path("mesh.file", "a Gmsh .msh file (relative to the scene's folder)");
  s.file_path("mesh.geo", "a Gmsh .geo file, meshed when the run starts (relative to the scene's folder)");
  s.string("mesh.region", "", "the 2D physical group of the fluid (empty: the mesh's only one)");
  s.section("mesh.geo_parameters", "numbers passed to the .geo before it is parsed (declared there by DefineConstant)");
  s.real("mesh.geo_parameters.*", 0.0, "a number the .geo declares");
  s.section("boundaries.*", "the condition on a boundary (a 1D physical group of the mesh): every one needs one");
  s.string("boundaries.*.type", "", "wall, moving-wall, inflow, outflow, symmetry or traction (docs/boundaries.md)",
           kConditions);
  s.real_list("boundaries.*.velocity", {},
              "moving-wall: the wall's velocity [vx, vy]; inflow: a given uniform velocity instead of the fully "
              "developed profile");
  s.real("boundaries.*.mean_velocity", 1.0, "inflow: the fully developed profile's mean velocity", Range::positive());
  s.string("boundaries.*.condition", "fully-developed",
           "outflow: fully developed (tangential velocity 0, pressure datum 0) or traction free",
           {"fully-developed", "traction-free"});
  s.real_list("boundaries.*.traction", {}, "traction: the given traction T n [tx, ty]");
  s.section("observables.*", "a quantity computed at every point, usable as a stop observable or a monitor");
  s.string("observables.*.type", "",
           "force, flow-rate, mean-pressure, pressure-drop, couette-correction, reattachment or stream-function "
           "(docs/observables.md)",
           kObservables);
  s.string(
      "observables.*.boundary", "",
      "the boundary it is on (pressure-drop: from; couette-correction: the inflow; stream-function: psi = 0 there)");
  s.string("observables.*.to", "", "pressure-drop: the boundary the drop is to; couette-correction: the outflow");
  s.string("observables.*.component", "x", "force: its component", {"x", "y"});
  s.real("observables.*.scale", 1.0, "factor on the value (a half domain's force: 2)");
  s.real_list("observables.*.origin", {},
              "reattachment: lengths are measured from this point [x, y] along the wall; couette-correction: the "
              "contraction plane is x = origin[0]");
  s.real_list("observables.*.region", {}, "stream-function: the box [xmin, xmax, ymin, ymax] of the extremum");
  s.string("observables.*.per_flow_rate", "",
           "stream-function: divide psi by the |flow rate| through this boundary (empty: psi as it is)");
  s.string("observables.*.method", "reaction",
           "force: the consistent reaction where the boundary's velocity is given (else the surface integral), or "
           "always the surface integral of the traction",
           {"reaction", "surface-integral"});
  s.string("observables.*.extremum", "max", "stream-function: the maximum or the minimum of psi", {"max", "min"});
  s.boolean("observables.*.monitor", false, "also a monitor: continuation locates where it crosses zero");
  FluidOptions::declare(s, 1.0 / 9.0, 0.1);
}

FlowOptions FlowOptions::from_scene(const Scene& sc) {
  FlowOptions o;
  const bool file = !sc.string("mesh.file").empty(), geo = !sc.string("mesh.geo").empty();
  if (file == geo)
    throw sc.error(file ? "mesh.geo" : "mesh.file", "a flow needs exactly one of mesh.file (a .msh) and mesh.geo");
  o.geo = geo;
  o.mesh_path = sc.string(geo ? "mesh.geo" : "mesh.file");
  for (const std::string& name : sc.members("mesh.geo_parameters")) {
    if (!geo) throw sc.error("mesh.geo_parameters." + name, "geo parameters need mesh.geo");
    o.geo_parameters[name] = sc.real("mesh.geo_parameters." + name);
  }
  o.region = sc.string("mesh.region");
  o.fluid = FluidOptions::from_scene(sc);
  // The convective term (and the velocity's time derivative) always: Re is a parameter a trace,
  // a curve or a study varies from any start, Re = 0 included, and a term assembled only where the
  // scene's Re > 0 left a branch in Re from 0 a Stokes flow at every Re (rho Re = 0 multiplies it at
  // Re = 0, so a Stokes flow's values are unchanged).
  o.fluid.inertia = true;
  o.fluid.kernel.inertia = true;

  for (const std::string& name : sc.members("boundaries")) {
    const std::string at = "boundaries." + name + ".";
    const std::string type = sc.string(at + "type");
    auto only = [&](const char* key, bool applies) {
      if (!applies && sc.differs_from_default(at + key))
        throw sc.error(at + key, fmt::format("does not apply to a boundary of type \"{}\"", type));
    };
    only("velocity", type == "moving-wall" || type == "inflow");
    only("mean_velocity", type == "inflow" && sc.real_list(at + "velocity").empty());
    only("condition", type == "outflow");
    only("traction", type == "traction");
    o.boundary_names.push_back(name);
    if (type.empty()) throw sc.error(at + "type", "every boundary needs a type: " + listed(kConditions));
    if (type == "wall") o.boundaries.walls.push_back(name);
    if (type == "symmetry") o.boundaries.symmetry.push_back(name);
    if (type == "moving-wall")
      o.boundaries.driven_walls.push_back({name, vector_of(sc, at + "velocity", "a moving wall")});
    if (type == "traction") o.boundaries.tractions.push_back({name, vector_of(sc, at + "traction", "a traction")});
    if (type == "outflow") o.boundaries.outflows.push_back({name, sc.string(at + "condition") == "fully-developed"});
    if (type == "inflow") {
      InflowCondition in;
      in.boundary = name;
      in.fully_developed = sc.real_list(at + "velocity").empty();
      if (!in.fully_developed) in.velocity = vector_of(sc, at + "velocity", "a given inflow");
      in.mean_velocity = sc.real(at + "mean_velocity");
      o.boundaries.inflows.push_back(in);
    }
  }

  for (const std::string& name : sc.members("observables")) {
    const std::string at = "observables." + name + ".";
    const std::string type = sc.string(at + "type");
    if (type.empty()) throw sc.error(at + "type", "every observable needs a type: " + listed(kObservables));
    if (!identifier(name))
      throw sc.error(at + "type",
                     fmt::format("the observable's name \"{}\" is a column name: letters, digits and _ only, "
                                 "not starting with a digit",
                                 name));
    if (std::find(kReservedNames.begin(), kReservedNames.end(), name) != kReservedNames.end())
      throw sc.error(at + "type",
                     fmt::format("the name \"{}\" is taken by a column of every branch or time table or by a "
                                 "parameter ({}); rename [observables.{}]",
                                 name, listed(kReservedNames), name));
    FlowObservableSpec spec;
    spec.name = name;
    auto need = [&](const char* key) -> const std::string& {
      const std::string& v = sc.string(at + key);
      if (v.empty()) throw sc.error(at + key, fmt::format("an observable of type \"{}\" needs it", type));
      return v;
    };
    auto only = [&](const char* key, bool applies) {
      if (!applies && sc.differs_from_default(at + key))
        throw sc.error(at + key, fmt::format("does not apply to an observable of type \"{}\"", type));
    };
    only("to", type == "pressure-drop" || type == "couette-correction");
    only("component", type == "force");
    only("origin", type == "reattachment" || type == "couette-correction");
    only("region", type == "stream-function");
    only("extremum", type == "stream-function");
    only("per_flow_rate", type == "stream-function");
    only("method", type == "force");
    spec.boundary = need("boundary");
    if (type == "pressure-drop" || type == "couette-correction") spec.other = need("to");
    spec.scale = sc.real(at + "scale");
    spec.monitor = sc.boolean(at + "monitor");
    if (type == "force") {
      spec.kind = FlowObservableSpec::Kind::Force;
      spec.component = sc.string(at + "component") == "x" ? 0 : 1;
      spec.surface_integral = sc.string(at + "method") == "surface-integral";
    } else if (type == "flow-rate") {
      spec.kind = FlowObservableSpec::Kind::FlowRate;
    } else if (type == "mean-pressure") {
      spec.kind = FlowObservableSpec::Kind::MeanPressure;
    } else if (type == "pressure-drop") {
      spec.kind = FlowObservableSpec::Kind::PressureDrop;
    } else if (type == "couette-correction") {
      spec.kind = FlowObservableSpec::Kind::CouetteCorrection;
      spec.origin = vector_of(sc, at + "origin", "a Couette correction's contraction plane");
    } else if (type == "reattachment") {
      spec.kind = FlowObservableSpec::Kind::Reattachment;
      spec.origin = vector_of(sc, at + "origin", "a reattachment length's origin");
    } else {
      spec.kind = FlowObservableSpec::Kind::StreamFunctionExtremum;
      const std::vector<double>& r = sc.real_list(at + "region");
      if (r.size() != 4 || !(r[0] < r[1] && r[2] < r[3]))
        throw sc.error(at + "region", "needs a box [xmin, xmax, ymin, ymax] with xmin < xmax and ymin < ymax");
      spec.region = {r[0], r[1], r[2], r[3]};
      spec.maximum = sc.string(at + "extremum") == "max";
      spec.other = sc.string(at + "per_flow_rate");
    }
    o.observables.push_back(spec);
  }
  return o;
}

}  // namespace keller
