// Steady homogeneous flows of a viscoelastic law, in either formulation: simple shear
// (`steady-shear`), planar extension (`planar-extension`) and uniaxial extension
// (`uniaxial-extension`). The state is the one the flow kernels reach where v . grad M = 0 and L
// is the flow's constant velocity gradient, from the kernels' own pointwise constitutive residual
// (conformation_rate, or log_conformation_rate with M = exp(Psi)). Traced in log10 of the rate, it
// gives a law's viscosity, normal stress coefficients and extensional viscosity over decades of
// rates: what a user compares with their rheometer's data before using a fitted law in a flow.
//
//   shear      v = (gdot y, 0):                 L = [[0, gdot], [0, 0]]
//   planar     v = (eps x, -eps y, 0):          L = diag(eps, -eps), Lzz = 0
//   uniaxial   v = (eps x, -eps y/2, -eps z/2): L = diag(eps, -eps/2), Lzz = -eps/2
// Extension carries M_zz as an unknown (4 unknowns, M_xy = 0 in the solution); shear has M_xx,
// M_xy, M_yy and, for FENE-P with fluid.fene_p_dynamic_zz, M_zz. A conformation that is not
// positive definite is refused (InvalidState): the equations have such roots, which are no state
// of the law, and a long step in fast extension can reach them; the corrector then shortens it.
//
// Units (model.md): the channel's, so that a state here is the state at a point of the channel
// flow with the same local rate. The parameter log10_rate is log10 of the dimensional rate r
// (1/s); the model rate is r Gamma / rate_scale (rate_scale = U0 / W = 100 1/s, the Owens law's
// fluid.owens.rate_scale), lambda = Wi / Gamma, and the local Weissenberg number is lambda_0 r
// with lambda_0 = Wi / rate_scale (s). F = lambda (rate of the conformation equation) makes F
// dimensionless, and B = lambda I.
//
// A multi-mode law ([fluid.modes], LawKeys) has each mode's unknowns in turn (mode by mode, the
// first mode's first), each mode relaxing in its own time t_k lambda; the stress observables are
// the sum of the modes' (mode k's modulus w_k (1 - beta) Gamma / (t_k Wi)), the M_* observables
// the first mode's.
#pragma once

#include <memory>

#include "core/Problem.hpp"
#include "core/Scene.hpp"
#include "problems/kernels/FlowParameters.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/LawKeys.hpp"

namespace keller {

enum class HomogeneousFlow { Shear, PlanarExtension, UniaxialExtension };
const char* problem_type(HomogeneousFlow flow);  // "steady-shear", "planar-extension", "uniaxial-extension"

struct RheometryOptions {
  HomogeneousFlow flow = HomogeneousFlow::Shear;
  LawKeys law = [] {  // the law, its formulation, its constants: Owens by default
    LawKeys k;
    k.model = FluidModel::Owens;
    return k;
  }();
  double log10_rate = -3.0;
  double Wi = 26.3;  // lambda_0 = Wi / (U0 / W) = 0.263 s
  double Gamma = 4.95e-4;
  double beta = OwensParameters().beta();

  static void declare(SceneSchema& schema);  // the same keys for the three flows
  // Throws SceneError for keys the law does not use (LawKeys); fluid.model has no Newtonian choice.
  static RheometryOptions from_scene(const Scene& scene, HomogeneousFlow flow);
};

class RheometryProblem final : public Problem {
 public:
  explicit RheometryProblem(RheometryOptions options);

  std::string name() const override { return problem_type(o_.flow); }
  int size() const override { return components_; }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status mass_matrix(const Vector& u, SparseMatrix& B) override;
  // The state at rest (M = I, Psi = 0): the exact state as the rate goes to zero.
  Vector initial_guess() override;
  std::vector<Homotopy> homotopies() const override;
  // Shear: rate (1/s), Wi_local = lambda_0 r, eta = (eta_s + eta_p) / eta0, eta_p = eta_p / eta_p0
  // (the polymer's part), N1 = tau_xx - tau_yy (in G), M_xx, M_xy, M_yy, psi1_p = the polymer's
  // first normal stress coefficient N1_p / gdot^2 over 2 eta_p0 lambda (1 for Oldroyd-B),
  // N2 = tau_yy - tau_zz (in G).
  // Extension: rate, Wi_local, eta_e = (tau_xx - tau_yy) / (eta0 eps) with the solvent (the
  // Trouton ratio: 4 planar, 3 uniaxial at low rate), eta_e_p = the polymer's part over eta_p0,
  // N1 = tau_xx - tau_yy (in G), M_xx, M_yy, M_zz.
  std::vector<std::string> observable_names() const override;
  Status observables(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

 private:
  struct Kinematics {
    double rate = 0, lambda = 0;
    double L[2][2] = {{0, 0}, {0, 0}};
    double Lzz = 0;
  };
  Kinematics kinematics() const;  // at the current parameter values
  template <int NC>
  Status evaluate(const Vector& u, Vector& F, SparseMatrix* J) const;
  // The first mode's M and the polymer stress of a state (summed over the modes); false where
  // the law's factor is not positive.
  bool stress(const Vector& u, Conformation<double>& M, Conformation<double>& tau) const;

  RheometryOptions o_;
  int components_;  // nc_ per mode
  int nc_;
  std::vector<PolymerMode> modes_;
  ParameterSet params_;
  int i_rate_, i_Wi_, i_Gamma_, i_beta_;
  LawParameterIndices i_law_;
  SparseMatrix pattern_;
};

}  // namespace keller
