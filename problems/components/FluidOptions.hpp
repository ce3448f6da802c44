// The fluid of a flow problem as its scene gives it: the constitutive law, its formulation and
// constants (LawKeys), Re, Wi, beta, the stabilisation and the inflow profile; their scene keys,
// declared and read in one place for every problem with a fluid.
#pragma once

#include <string>
#include <vector>

#include "core/Scene.hpp"
#include "problems/kernels/ViscoelasticFlowKernel.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/InflowProfile.hpp"
#include "problems/laws/LawKeys.hpp"

namespace keller {

struct FluidOptions {
  FluidModel model = FluidModel::Newtonian;
  bool log_conformation = false;
  bool dynamic_zz = false;  // FENE-P: M_zz as an unknown (needed for time-dependent forms)
  double Re = 0.0;
  double Wi = 0.1;
  double beta = 0.001 / 0.198;
  LawConstants<double> constants;  // b, alpha, epsilon, xi (the Owens constants: kernel.owens)
  std::vector<ModeKeys> modes;     // a multi-mode fluid's spectrum; empty: one mode
  bool inertia = false;
  ViscoelasticKernelOptions kernel;
  ProfileKind profile = ProfileKind::Parabolic;
  double power_index = 0.5;

  bool viscoelastic() const { return model != FluidModel::Newtonian; }
  // "oldroyd-b fluid", "giesekus fluid of 3 modes (log-conformation)": for a problem's summary.
  std::string describe() const;
  int conformation_components() const { return model == FluidModel::FeneP && dynamic_zz ? 4 : 3; }

  // Keys of [fluid], [inflow] and the fluid's entries of [parameters], with problem-specific
  // defaults for beta and Wi.
  static void declare(SceneSchema& schema, double default_beta, double default_Wi);
  // Throws SceneError for keys that the chosen fluid does not use (a law's constant for another
  // law, Wi or a formulation for a Newtonian fluid).
  static FluidOptions from_scene(const Scene& scene);
};

}  // namespace keller
