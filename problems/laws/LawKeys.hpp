// The scene keys that choose a constitutive law, its formulation and its constants, shared by
// every problem with a fluid, declared and read in one place:
//   [fluid]        model, formulation, fene_p_dynamic_zz
//   [fluid.owens]  the Cross model's constants of the Owens law (eta_p0, eta_pinf, theta2, m,
//                  rate_scale)
//   [parameters]   the constants that are continuation parameters: b (FENE-P, FENE-CR), alpha
//                  (Giesekus), epsilon and xi (PTT)
//   [fluid.modes.<name>]  a discrete relaxation spectrum: each mode's time (relaxation time /
//                  lambda, a continuation parameter time_<name>) and viscosity (its share of the
//                  polymer viscosity; the shares sum to 1), in the order of their names. None: one
//                  mode of time 1 and share 1.
// A key the chosen law does not use is refused when set, and so is a physically meaningless
// value (alpha outside [0, 1/2], epsilon < 0, xi outside [0, 1), b <= 1, ...), with the key.
#pragma once

#include <string>
#include <vector>

#include "core/ParameterSet.hpp"
#include "core/Scene.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

// One mode of a discrete relaxation spectrum as the scene gives it.
struct ModeKeys {
  std::string name;
  double time = 1.0;       // relaxation time / lambda (lambda = Wi / Gamma)
  double viscosity = 1.0;  // share of the polymer viscosity 1 - beta
};

struct LawKeys {
  FluidModel model = FluidModel::Newtonian;
  bool log_conformation = false;
  bool dynamic_zz = false;  // FENE-P: M_zz as an unknown (needed for time-dependent forms)
  LawConstants<double> constants;
  OwensParameters owens;
  std::vector<ModeKeys> modes;  // empty: one mode (time 1, share 1), no mode parameters

  // Declares the [fluid] and [fluid.owens] keys (after the section's own doc); `models`: the laws
  // the problem takes.
  static void declare(SceneSchema& schema, const std::vector<std::string>& models, const std::string& default_model);
  // Declares the law constants among [parameters] (after that section's doc).
  static void declare_constants(SceneSchema& schema);
  // Reads them; throws SceneError for a key the law does not use, xi > 0 in the log form, modes for
  // a Newtonian fluid, a mode without a viscosity or shares that do not sum to 1.
  static LawKeys from_scene(const Scene& scene);
};

// Adds a law's constants to a problem's parameters (so that a branch can follow any of them),
// with the ranges of their scene keys; the log form has no xi.
LawParameterIndices add_law_parameters(ParameterSet& params, FluidModel model, bool log_form,
                                       const LawConstants<double>& constants);
// Adds each mode's time as the parameter time_<name> (positive) and returns their indices, in
// mode order; none for a one-mode fluid without [fluid.modes].
std::vector<int> add_mode_parameters(ParameterSet& params, const std::vector<ModeKeys>& modes);

}  // namespace keller
