// The scene keys that choose a constitutive law and its formulation, shared by every problem
// with a fluid: fluid.model, fluid.formulation and fluid.fene_p_dynamic_zz, declared in one place,
// read with the FENE-P extensibility parameters.b (which each problem declares in its
// [parameters]).
#pragma once

#include <string>
#include <vector>

#include "core/Scene.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

struct LawKeys {
  FluidModel model = FluidModel::Newtonian;
  bool log_conformation = false;
  bool dynamic_zz = false;  // FENE-P: M_zz as an unknown (needed for time-dependent forms)
  double b = 100.0;

  // Declares the [fluid] keys (after the section's own doc); `models`: the laws the problem takes.
  static void declare(SceneSchema& schema, const std::vector<std::string>& models, const std::string& default_model);
  // Reads them; throws SceneError for parameters.b or fluid.fene_p_dynamic_zz with another law.
  static LawKeys from_scene(const Scene& scene);
};

}  // namespace keller
