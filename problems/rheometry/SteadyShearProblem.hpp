// Steady homogeneous simple shear of a viscoelastic law (Oldroyd-B, FENE-P, Owens), in either
// formulation: the state the flow kernels reach where v . grad M = 0 and L = [[0, gdot], [0, 0]],
// from the kernels' own pointwise constitutive residual (conformation_rate, or
// log_conformation_rate with M = exp(Psi)). Traced in log10 of the shear rate, it gives the
// law's steady-shear viscosity over decades of rates (the reference study's first figure).
//
// Units (model.md): the channel's, so that a state here is the state at a point of the channel
// flow with the same local shear rate. The parameter log10_rate is log10 of the dimensional shear
// rate r (1/s); the model shear rate is gdot = r Gamma / (U0 / W), lambda = Wi / Gamma, and the
// local Weissenberg number is lambda gdot = lambda_0 r with lambda_0 = Wi W / U0 (s).
// F = lambda (rate of the conformation equation) makes F dimensionless, and B = lambda I.
#pragma once

#include <memory>

#include "core/Problem.hpp"
#include "core/Scene.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/LawKeys.hpp"

namespace keller {

struct SteadyShearOptions {
  LawKeys law{FluidModel::Owens};  // the law, its formulation, FENE-P's b
  double log10_rate = -3.0;
  double Wi = 26.3;  // lambda_0 = Wi / (U0 / W) = 0.263 s
  double Gamma = 4.95e-4;
  double beta = OwensParameters().beta();
  OwensParameters owens;

  static void declare(SceneSchema& schema);
  // Throws SceneError for keys the law does not use (LawKeys); fluid.model has no Newtonian choice.
  static SteadyShearOptions from_scene(const Scene& scene);
};

class SteadyShearProblem final : public Problem {
 public:
  explicit SteadyShearProblem(SteadyShearOptions options);

  std::string name() const override { return "steady-shear"; }
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
  // rate (1/s), Wi_local = lambda_0 r, eta = (eta_s + eta_p) / eta0, eta_p = eta_p / eta_p0 (the
  // polymer contribution), N1 = tau_xx - tau_yy (in G), M_xx, M_xy, M_yy.
  std::vector<std::string> observable_names() const override;
  Status observables(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  static std::unique_ptr<Problem> from_scene(const Scene& scene);

 private:
  struct Shear {
    double gdot = 0, lambda = 0, inv_lambda_eff = 0;
  };
  Shear shear() const;  // at the current parameter values
  template <int NC>
  Status evaluate(const Vector& u, Vector& F, SparseMatrix* J) const;
  // M and the polymer stress of a state; false where FENE-P's tr M has reached 3b.
  bool stress(const Vector& u, Conformation<double>& M, Conformation<double>& tau) const;

  SteadyShearOptions o_;
  int components_;
  ParameterSet params_;
  int i_rate_, i_Wi_, i_Gamma_, i_beta_, i_b_ = -1;
  SparseMatrix pattern_;
};

}  // namespace keller
