#include "problems/ProblemRegistry.hpp"

#include <algorithm>

#include <fmt/format.h>

#include <stdexcept>

#include "problems/analytic/Bratu1DProblem.hpp"
#include "problems/analytic/Bratu2DProblem.hpp"
#include "problems/analytic/Brusselator1DProblem.hpp"
#include "problems/analytic/Pitchfork1DProblem.hpp"
#include "problems/analytic/ShiftedBratu1DProblem.hpp"
#include "problems/channel/ChannelProblem.hpp"
#include "problems/channel/CollapsibleChannelProblem.hpp"
#include "problems/channel/WallProblem.hpp"
#include "problems/cylinder/CylinderProblem.hpp"
#include "problems/flow/FlowProblem.hpp"
#include "problems/rheometry/RheometryProblem.hpp"

namespace keller {

namespace {

// Peak resident memory of keller solve, measured on the AMD EPYC VM (docs/performance.md): the
// process itself, and per element or interval of the cheapest physics of each problem (the lower
// estimate: a Newtonian fluid; viscoelastic ones take about twice as much).
constexpr double kProcessBytes = 20e6;
constexpr double kChannelElementBytes = 40e3;      // channel_stokes on M2: 49 MB, 720 elements
constexpr double kCollapsibleElementBytes = 90e3;  // Newtonian collapsible channel on M2: 103 MB, 900 elements
constexpr double kWallElementBytes = 60e3;         // wall_pressure on M2: 33 MB, 180 elements
constexpr double kBratu2DElementBytes = 4e3;       // bratu2d on 300 x 300: 430 MB
constexpr double kIntervalBytes = 100.0;           // bratu1d on 10^6 intervals: 147 MB

// The key that sets a channel mesh's size: its preset, or the largest of the explicit counts.
template <HomogeneousFlow F>
std::unique_ptr<Problem> rheometry(const Scene& s) {
  return std::make_unique<RheometryProblem>(RheometryOptions::from_scene(s, F));
}

std::string channel_size_key(const Scene& s) {
  if (s.string("mesh.name") != "custom") return "mesh.name";
  std::string key = "mesh.nx_upstream";
  for (const char* k : {"mesh.nx_deformable", "mesh.nx_downstream", "mesh.ny_fluid", "mesh.ny_solid"})
    if (s.integer(k) > s.integer(key)) key = k;
  return key;
}

ProblemType::Memory per_element(double elements, double bytes, std::string key) {
  return {kProcessBytes + elements * bytes, std::move(key), fmt::format("{:.0f} elements", elements)};
}

ProblemType::Memory per_interval(const Scene& s, const std::string& key, double unknowns_per_interval) {
  const double n = static_cast<double>(s.integer(key));
  return {kProcessBytes + n * unknowns_per_interval * kIntervalBytes, key, fmt::format("{:.0f} intervals", n)};
}

// The registry's types with their memory estimates.
std::vector<ProblemType> with_memory(std::vector<ProblemType> types) {
  const auto channel = [](double bytes, bool solid) {
    return [bytes, solid](const Scene& s) {
      const ChannelMeshSpec m = channel_mesh_spec_from(s);
      return per_element(m.fluid_elements() + (solid ? m.solid_elements() : 0), bytes, channel_size_key(s));
    };
  };
  for (ProblemType& t : types) {
    if (t.name == "channel") t.memory = channel(kChannelElementBytes, false);
    if (t.name == "collapsible-channel") t.memory = channel(kCollapsibleElementBytes, true);
    if (t.name == "wall")
      t.memory = [](const Scene& s) {
        return per_element(channel_mesh_spec_from(s).solid_elements(), kWallElementBytes, channel_size_key(s));
      };
    if (t.name == "cylinder")  // Newtonian Q2-P1disc elements, as the channel's
      t.memory = [](const Scene& s) {
        const CylinderMeshSpec m = CylinderOptions::from_scene(s).mesh;
        return per_element(static_cast<double>(m.elements()), kChannelElementBytes,
                           m.name == "custom" ? "mesh.n_quarter" : "mesh.name");
      };
    if (t.name == "bratu2d")
      t.memory = [](const Scene& s) {
        const double n = static_cast<double>(s.integer("bratu.intervals"));
        // (beyond the problem's own cap its refusal says why, not an estimate)
        if (n > Bratu2DProblem::max_elements_per_side) return ProblemType::Memory{};
        return per_element(n * n, kBratu2DElementBytes, "bratu.intervals");
      };
    if (t.name == "bratu1d" || t.name == "bratu1d-shifted")
      t.memory = [](const Scene& s) { return per_interval(s, "bratu.intervals", 1); };
    if (t.name == "pitchfork1d") t.memory = [](const Scene& s) { return per_interval(s, "pitchfork.intervals", 1); };
    if (t.name == "brusselator1d")
      t.memory = [](const Scene& s) { return per_interval(s, "brusselator.intervals", 2); };
  }
  return types;
}

}  // namespace

static std::vector<ProblemType>& registry() {
  static std::vector<ProblemType> types = with_memory({
      {"channel", "steady flow in the 19 x 1 channel of model.md", ChannelOptions::declare,
       [](const Scene& s) -> std::unique_ptr<Problem> {
         return std::make_unique<ChannelProblem>(ChannelOptions::from_scene(s));
       }},
      {"collapsible-channel",
       "the collapsible channel of model.md: any fluid, neo-Hookean wall, moving mesh",
       CollapsibleOptions::declare,
       [](const Scene& s) -> std::unique_ptr<Problem> {
         return std::make_unique<CollapsibleChannelProblem>(CollapsibleOptions::from_scene(s));
       },
       {{"linear_solver.ordering", "best",
         "orderings tried, the best kept (MUMPS: the fewest flops of METIS, PORD, AMD; UMFPACK: the least fill "
         "of AMD/COLAMD, METIS, NESDIS, where METIS halves AMD's fill and best cuts another 19% on M2; "
         "docs/orderings.md)"}}},
      {"cylinder",
       "confined-cylinder benchmark (radius 1, channel half-width 2)",
       CylinderOptions::declare,
       [](const Scene& s) -> std::unique_ptr<Problem> {
         return std::make_unique<CylinderProblem>(CylinderOptions::from_scene(s));
       },
       {{"linear_solver.ordering", "best",
         "orderings tried, the best kept (MUMPS: PORD on W3; UMFPACK: METIS, which cuts AMD's fill by 35% on "
         "C3; docs/orderings.md)"}}},
      {"flow",
       "steady flow of any fluid in a 2D geometry from Gmsh, with a condition on every named boundary (docs/flow.md)",
       FlowOptions::declare,
       [](const Scene& s) -> std::unique_ptr<Problem> {
         return std::make_unique<FlowProblem>(FlowOptions::from_scene(s));
       },
       {{"linear_solver.ordering", "best",
         "orderings tried, the best kept: the fill of a mesh the user made is not known in advance "
         "(docs/orderings.md)"}}},
      {"wall", "the neo-Hookean wall of the collapsible channel alone, under follower pressures", WallOptions::declare,
       [](const Scene& s) -> std::unique_ptr<Problem> {
         return std::make_unique<WallProblem>(WallOptions::from_scene(s));
       }},
      {"steady-shear",
       "steady homogeneous simple shear of a viscoelastic law: its viscosity and normal stresses against the rate",
       RheometryOptions::declare, rheometry<HomogeneousFlow::Shear>},
      {"planar-extension", "steady planar extension of a viscoelastic law: its extensional viscosity against the rate",
       RheometryOptions::declare, rheometry<HomogeneousFlow::PlanarExtension>},
      {"uniaxial-extension",
       "steady uniaxial extension of a viscoelastic law: its extensional viscosity against the rate",
       RheometryOptions::declare, rheometry<HomogeneousFlow::UniaxialExtension>},
      {"bratu1d", "1D Bratu problem by central differences (test problem)", Bratu1DProblem::declare,
       Bratu1DProblem::from_scene},
      {"bratu1d-shifted", "1D Bratu problem with a linear term mu u (test problem: fold curves)",
       ShiftedBratu1DProblem::declare, ShiftedBratu1DProblem::from_scene},
      {"bratu2d", "2D Bratu problem with Q2 elements (test problem)", Bratu1DProblem::declare,
       Bratu2DProblem::from_scene},
      {"pitchfork1d", "1D pitchfork u'' + lambda u - u^3 + eps = 0 by central differences (test problem)",
       Pitchfork1DProblem::declare, Pitchfork1DProblem::from_scene},
      {"brusselator1d", "1D Brusselator with no-flux ends by central differences (test problem: Hopf)",
       Brusselator1DOptions::declare, Brusselator1DProblem::from_scene},
  });
  return types;
}

const std::vector<ProblemType>& problem_types() { return registry(); }

void register_problem_type(ProblemType type) {
  const bool named = !type.name.empty() && std::all_of(type.name.begin(), type.name.end(), [](char c) {
    return (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '-' || c == '_';
  });
  if (!named)
    throw std::invalid_argument("problem type name '" + type.name +
                                "': use lower-case letters, digits, '-' and '_' (it is [problem] type in a scene)");
  for (const ProblemType& t : registry())
    if (t.name == type.name) throw std::invalid_argument("problem type '" + type.name + "' is registered already");
  if (!type.declare || !type.build)
    throw std::invalid_argument("problem type '" + type.name + "' needs both declare and build");
  registry().push_back(std::move(type));
}

const ProblemType& problem_type(const std::string& name) {
  for (const auto& t : problem_types())
    if (t.name == name) return t;
  std::string known;
  for (const auto& t : problem_types()) known += (known.empty() ? "" : ", ") + t.name;
  throw std::invalid_argument("unknown problem type '" + name + "' (" + known + ")");
}

std::vector<std::string> problem_type_names() {
  std::vector<std::string> out;
  for (const auto& t : problem_types()) out.push_back(t.name);
  return out;
}

}  // namespace keller
