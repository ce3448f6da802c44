#include "problems/laws/LawKeys.hpp"

namespace keller {

void LawKeys::declare(SceneSchema& s, const std::vector<std::string>& models, const std::string& default_model) {
  s.string("fluid.model", default_model, "constitutive law", models);
  s.string("fluid.formulation", "conformation", "unknown of the constitutive equation: M or log M",
           {"conformation", "log-conformation"});
  s.boolean("fluid.fene_p_dynamic_zz", false,
            "FENE-P: keep M_zz as an unknown (needed for time-dependent forms) instead of f M_zz = 1");
}

LawKeys LawKeys::from_scene(const Scene& sc) {
  LawKeys k;
  const std::string& m = sc.string("fluid.model");
  k.model = fluid_model_from_string(m);
  k.log_conformation = sc.string("fluid.formulation") == "log-conformation";
  k.dynamic_zz = sc.boolean("fluid.fene_p_dynamic_zz");
  k.b = sc.real("parameters.b");
  if (k.model != FluidModel::FeneP) {
    for (const char* key : {"parameters.b", "fluid.fene_p_dynamic_zz"})
      if (sc.differs_from_default(key))
        throw sc.error(key, "applies to fluid.model = \"fene-p\" only (got \"" + m + "\")");
  }
  return k;
}

}  // namespace keller
