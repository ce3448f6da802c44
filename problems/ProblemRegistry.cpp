#include "problems/ProblemRegistry.hpp"

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
#include "problems/rheometry/SteadyShearProblem.hpp"

namespace keller {

const std::vector<ProblemType>& problem_types() {
  static const std::vector<ProblemType> types = {
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
         "AMD/COLAMD, METIS and NESDIS tried, the least fill kept: METIS halves AMD's fill here and best cuts "
         "another 19% on M2 (docs/performance.md)"}}},
      {"cylinder",
       "confined-cylinder benchmark (radius 1, channel half-width 2)",
       CylinderOptions::declare,
       [](const Scene& s) -> std::unique_ptr<Problem> {
         return std::make_unique<CylinderProblem>(CylinderOptions::from_scene(s));
       },
       {{"linear_solver.ordering", "best",
         "the least fill of AMD/COLAMD, METIS and NESDIS: METIS alone cuts AMD's fill by 35% on C3 "
         "(docs/performance.md)"}}},
      {"wall", "the neo-Hookean wall of the collapsible channel alone, under follower pressures", WallOptions::declare,
       [](const Scene& s) -> std::unique_ptr<Problem> {
         return std::make_unique<WallProblem>(WallOptions::from_scene(s));
       }},
      {"steady-shear",
       "steady homogeneous simple shear of a viscoelastic law: its steady-shear viscosity against the shear rate",
       SteadyShearOptions::declare, SteadyShearProblem::from_scene},
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
  };
  return types;
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
