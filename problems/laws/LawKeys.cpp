#include "problems/laws/LawKeys.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>

namespace keller {

namespace {

const Range kB = Range::above(1.0);
const Range kAlpha = Range::between(0.0, 0.5);
const Range kEpsilon = Range::non_negative();
const Range kXi{0.0, 1.0, false, true};
const char* kBDoc = "FENE-P and FENE-CR extensibility (tr M < 3b)";
const char* kAlphaDoc = "Giesekus mobility (0: Oldroyd-B; 1/2 the largest with a monotone shear stress)";
const char* kEpsilonDoc = "PTT extensibility epsilon (0: Oldroyd-B, or Johnson-Segalman with xi > 0)";
const char* kXiDoc =
    "PTT slip xi of the Gordon-Schowalter derivative (0: upper-convected); the conformation formulation only";

}  // namespace

void LawKeys::declare(SceneSchema& s, const std::vector<std::string>& models, const std::string& default_model) {
  s.string("fluid.model", default_model, "constitutive law", models);
  s.string("fluid.formulation", "conformation", "unknown of the constitutive equation: M or log M",
           {"conformation", "log-conformation"});
  s.boolean("fluid.fene_p_dynamic_zz", false,
            "FENE-P: keep M_zz as an unknown (needed for time-dependent forms) instead of f M_zz = 1");
  const OwensParameters o;
  s.section("fluid.owens",
            "the Owens law's Cross model eta_p(r) = eta_p0 (1 + theta1 r^m) / (1 + theta2 r^m), "
            "theta1 = theta2 eta_pinf / eta_p0, r = gdot U0 / (Gamma W) in 1/s (Fang and Owens' fit of blood)");
  s.real("fluid.owens.eta_p0", o.eta_p0, "zero-shear polymer viscosity in Pa s", Range::positive());
  s.real("fluid.owens.eta_pinf", o.eta_pinf, "infinite-shear polymer viscosity in Pa s (<= eta_p0)",
         Range::non_negative());
  s.real("fluid.owens.theta2", o.theta2, "time constant theta2 in s^m", Range::positive());
  s.real("fluid.owens.m", o.m, "Cross exponent m (<= 1 keeps the shear stress increasing)",
         Range{0.0, 1.0, true, false});
  s.real("fluid.owens.rate_scale", o.rate_scale, "U0 / W in 1/s: the dimensional shear rate of a model rate of Gamma",
         Range::positive());
  s.section("fluid.modes.*",
            "one mode of a discrete relaxation spectrum (a multi-mode fluid, each mode its own conformation field; "
            "none: one mode)");
  s.real("fluid.modes.*.time", 1.0,
         "the mode's relaxation time / lambda (lambda = Wi / Gamma); the continuation parameter time_<name>",
         Range::positive());
  s.real("fluid.modes.*.viscosity", 0.0,
         "the mode's share of the polymer viscosity 1 - beta (the shares sum to 1); required", Range::non_negative());
}

void LawKeys::declare_constants(SceneSchema& s) {
  s.real("parameters.b", 100.0, kBDoc, kB);
  s.real("parameters.alpha", 0.1, kAlphaDoc, kAlpha);
  s.real("parameters.epsilon", 0.25, kEpsilonDoc, kEpsilon);
  s.real("parameters.xi", 0.0, kXiDoc, kXi);
}

LawKeys LawKeys::from_scene(const Scene& sc) {
  LawKeys k;
  const std::string& m = sc.string("fluid.model");
  k.model = fluid_model_from_string(m);
  k.log_conformation = sc.string("fluid.formulation") == "log-conformation";
  k.dynamic_zz = sc.boolean("fluid.fene_p_dynamic_zz");
  k.constants.b = sc.real("parameters.b");
  k.constants.alpha = sc.real("parameters.alpha");
  k.constants.epsilon = sc.real("parameters.epsilon");
  k.constants.xi = sc.real("parameters.xi");
  auto only = [&](const char* key, bool used, const std::string& which) {
    if (!used && sc.differs_from_default(key))
      throw sc.error(key, "applies to " + which + " only (fluid.model = \"" + m + "\")");
  };
  only("parameters.b", uses_b(k.model), "fluid.model = \"fene-p\" or \"fene-cr\"");
  only("fluid.fene_p_dynamic_zz", k.model == FluidModel::FeneP, "fluid.model = \"fene-p\"");
  only("parameters.alpha", uses_alpha(k.model), "fluid.model = \"giesekus\"");
  only("parameters.epsilon", is_ptt(k.model), "fluid.model = \"ptt-linear\" or \"ptt-exponential\"");
  only("parameters.xi", is_ptt(k.model), "fluid.model = \"ptt-linear\" or \"ptt-exponential\"");
  for (const char* key :
       {"fluid.owens.eta_p0", "fluid.owens.eta_pinf", "fluid.owens.theta2", "fluid.owens.m", "fluid.owens.rate_scale"})
    only(key, k.model == FluidModel::Owens, "fluid.model = \"owens\"");
  if (k.log_conformation && k.constants.xi != 0.0)
    throw sc.error("parameters.xi",
                   "must be 0 with fluid.formulation = \"log-conformation\": the Gordon-Schowalter source 2 xi D "
                   "does not commute with M, which the log form's decomposition needs (use the conformation form)");
  k.owens.eta_p0 = sc.real("fluid.owens.eta_p0");
  k.owens.eta_pinf = sc.real("fluid.owens.eta_pinf");
  k.owens.theta2 = sc.real("fluid.owens.theta2");
  k.owens.m = sc.real("fluid.owens.m");
  k.owens.rate_scale = sc.real("fluid.owens.rate_scale");
  if (k.owens.eta_pinf > k.owens.eta_p0)
    throw sc.error("fluid.owens.eta_pinf", "is larger than fluid.owens.eta_p0 (" + std::to_string(k.owens.eta_p0) +
                                               "): the Cross model of blood thins, eta_pinf <= eta_p0");
  double total = 0.0;
  std::string last;
  // in the order of their names, however the scene lists them (the first has the field "conformation")
  std::vector<std::string> names = sc.members("fluid.modes");
  std::sort(names.begin(), names.end());
  for (const std::string& name : names) {
    const std::string at = "fluid.modes." + name + ".";
    if (k.model == FluidModel::Newtonian) throw sc.error(at + "time", "a Newtonian fluid has no relaxation modes");
    ModeKeys mode{name, sc.real(at + "time"), sc.real(at + "viscosity")};
    if (!sc.given(at + "viscosity") || !(mode.viscosity > 0.0))
      throw sc.error(at + "viscosity", "every mode needs its share of the polymer viscosity, > 0");
    total += mode.viscosity;
    last = at + "viscosity";
    k.modes.push_back(std::move(mode));
  }
  if (!k.modes.empty() && std::abs(total - 1.0) > 1e-9)
    throw sc.error(last, fmt::format("the modes' viscosities sum to {:.12g}, not 1: each is a share of the polymer "
                                     "viscosity (eta_p,k / eta_p)",
                                     total));
  return k;
}

LawParameterIndices add_law_parameters(ParameterSet& params, FluidModel model, bool log_conformation,
                                       const LawConstants<double>& constants) {
  LawParameterIndices ix;
  if (uses_b(model)) ix.b = params.add("b", constants.b, kBDoc, kB);
  if (uses_alpha(model)) ix.alpha = params.add("alpha", constants.alpha, kAlphaDoc, kAlpha);
  if (is_ptt(model)) {
    ix.epsilon = params.add("epsilon", constants.epsilon, kEpsilonDoc, kEpsilon);
    // the log form has no slip: xi stays 0 there
    ix.xi = log_conformation ? -1 : params.add("xi", constants.xi, kXiDoc, kXi);
  }
  return ix;
}

std::vector<int> add_mode_parameters(ParameterSet& params, const std::vector<ModeKeys>& modes) {
  std::vector<int> ix;
  for (const ModeKeys& m : modes)
    ix.push_back(params.add(
        "time_" + m.name, m.time,
        fmt::format("relaxation time / lambda of mode {} (share {:g} of the polymer viscosity)", m.name, m.viscosity),
        Range::positive()));
  return ix;
}

}  // namespace keller
