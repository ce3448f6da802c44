#include "problems/components/FluidOptions.hpp"

#include "problems/laws/LawKeys.hpp"

namespace keller {

void FluidOptions::declare(SceneSchema& s, double default_beta, double default_Wi) {
  s.section("fluid", "the fluid and which physics is on");
  LawKeys::declare(
      s, {"newtonian", "oldroyd-b", "fene-p", "owens", "giesekus", "ptt-linear", "ptt-exponential", "fene-cr"},
      "newtonian");
  s.real("fluid.devss", -1.0, "DEVSS viscosity beta_a (negative: 1 - beta)");
  s.string("fluid.supg", "local", "SUPG time scale: local h/|v| or global h_c/v_c", {"local", "global"});
  s.real("fluid.supg_scale", 1.0, "factor on the SUPG time scale", Range::non_negative());
  s.real("fluid.supg_velocity_floor", 1e-3, "local SUPG: |v| floored at this fraction of the velocity scale",
         Range::positive());
  s.section("inflow", "fully developed inflow at the inflow boundary");
  s.string("inflow.profile", "parabolic", "inflow velocity profile of mean velocity Gamma (or 1)",
           {"parabolic", "power-law", "fully-developed"});
  s.real("inflow.power_law_index", 0.5, "power-law profile: index n (u_max / u_mean = (2n + 1)/(n + 1))",
         Range::positive());
  s.section("parameters", "initial values of the named continuation parameters");
  s.real("parameters.Re", 0.0,
         "Reynolds number (0: Stokes flow, the convective term not assembled, unless the run continues in Re; "
         "the flow problem always assembles it)",
         Range::non_negative());
  s.real("parameters.Wi", default_Wi, "Weissenberg number", Range::positive());
  s.real("parameters.beta", default_beta, "viscosity ratio eta_s / eta0", Range{0.0, 1.0, true, false});
  LawKeys::declare_constants(s);
}

std::string FluidOptions::describe() const {
  std::string s = std::string(to_string(model)) + " fluid";
  if (modes.size() > 1) s += " of " + std::to_string(modes.size()) + " modes";
  if (viscoelastic() && log_conformation) s += " (log-conformation)";
  return s;
}

FluidOptions FluidOptions::from_scene(const Scene& sc) {
  FluidOptions o;
  const LawKeys law = LawKeys::from_scene(sc);
  o.model = law.model;
  o.log_conformation = law.log_conformation;
  o.dynamic_zz = law.dynamic_zz;
  o.constants = law.constants;
  o.modes = law.modes;
  o.kernel.owens = law.owens;
  o.Re = sc.real("parameters.Re");
  // a branch in Re from Re = 0 starts in Stokes flow and leaves it
  o.inertia = o.Re > 0.0 || (sc.given("continuation.parameter") && sc.string("continuation.parameter") == "Re");
  o.Wi = sc.real("parameters.Wi");
  o.beta = sc.real("parameters.beta");
  o.kernel.model = o.model;
  o.kernel.log_conformation = o.log_conformation;
  o.kernel.inertia = o.inertia;
  o.kernel.devss = sc.real("fluid.devss");
  o.kernel.supg.local = sc.string("fluid.supg") == "local";
  o.kernel.supg.scale = sc.real("fluid.supg_scale");
  o.kernel.supg.velocity_floor = sc.real("fluid.supg_velocity_floor");
  o.profile = profile_kind_from_string(sc.string("inflow.profile"));
  o.power_index = sc.real("inflow.power_law_index");
  if (!o.viscoelastic()) {
    for (const char* k : {"parameters.Wi", "parameters.beta", "fluid.formulation", "fluid.devss", "fluid.supg",
                          "fluid.supg_scale", "fluid.supg_velocity_floor"})
      if (sc.differs_from_default(k)) throw sc.error(k, "has no meaning for fluid.model = \"newtonian\"");
  }
  if (o.profile != ProfileKind::PowerLaw && sc.differs_from_default("inflow.power_law_index"))
    throw sc.error("inflow.power_law_index", "applies to inflow.profile = \"power-law\" only");
  return o;
}

}  // namespace keller
