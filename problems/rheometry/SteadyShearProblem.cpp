#include "problems/rheometry/SteadyShearProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/AutoDiff.hpp"
#include "problems/kernels/ConformationTransport.hpp"
#include "problems/laws/LogConformation.hpp"

namespace keller {

void SteadyShearOptions::declare(SceneSchema& s) {
  s.section("fluid", "the viscoelastic law and its formulation");
  LawKeys::declare(s, {"oldroyd-b", "fene-p", "owens"}, "owens");
  s.section("parameters", "initial values of the named continuation parameters");
  s.real("parameters.log10_rate", -3.0, "log10 of the dimensional shear rate in 1/s", Range::between(-30.0, 30.0));
  s.real("parameters.Wi", 26.3, "Weissenberg number of the channel: lambda_0 = Wi W / U0 = Wi / 100 s",
         Range::positive());
  s.real("parameters.Gamma", 4.95e-4, "velocity scale of the channel (sets the model shear rate of a rate in 1/s)",
         Range::positive());
  s.real("parameters.beta", OwensParameters().beta(), "viscosity ratio eta_s / eta0", Range{0.0, 1.0, false, true});
  s.real("parameters.b", 100.0, "FENE-P extensibility (tr M < 3b)", Range::above(1.0));
}

SteadyShearOptions SteadyShearOptions::from_scene(const Scene& sc) {
  SteadyShearOptions o;
  o.law = LawKeys::from_scene(sc);
  o.log10_rate = sc.real("parameters.log10_rate");
  o.Wi = sc.real("parameters.Wi");
  o.Gamma = sc.real("parameters.Gamma");
  o.beta = sc.real("parameters.beta");
  return o;
}

SteadyShearProblem::SteadyShearProblem(SteadyShearOptions options)
    : o_(std::move(options)), components_(o_.law.model == FluidModel::FeneP && o_.law.dynamic_zz ? 4 : 3) {
  if (o_.law.model == FluidModel::Newtonian)
    throw std::invalid_argument("steady-shear: a Newtonian fluid has no conformation (its viscosity is eta0)");
  i_rate_ = params_.add("log10_rate", o_.log10_rate, "log10 of the dimensional shear rate in 1/s", -30.0, 30.0);
  i_Wi_ = params_.add("Wi", o_.Wi, "Weissenberg number of the channel (lambda_0 = Wi W / U0)", Range::positive());
  i_Gamma_ = params_.add("Gamma", o_.Gamma, "velocity scale of the channel", Range::positive());
  i_beta_ = params_.add("beta", o_.beta, "viscosity ratio eta_s / eta0", Range{0.0, 1.0, false, true});
  if (o_.law.model == FluidModel::FeneP) i_b_ = params_.add("b", o_.law.b, "FENE-P extensibility", Range::above(1.0));
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i < components_; ++i)
    for (int j = 0; j < components_; ++j) t.emplace_back(i, j, 0.0);
  pattern_.resize(components_, components_);
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();
}

SteadyShearProblem::Shear SteadyShearProblem::shear() const {
  const double Gamma = params_.value(i_Gamma_);
  Shear s;
  s.gdot = std::pow(10.0, params_.value(i_rate_)) * Gamma / o_.owens.rate_scale;
  s.lambda = params_.value(i_Wi_) / Gamma;
  const double L[2][2] = {{0.0, s.gdot}, {0.0, 0.0}};
  s.inv_lambda_eff = inverse_relaxation_time(o_.law.model, s.lambda, L, Gamma, o_.owens);
  return s;
}

template <int NC>
Status SteadyShearProblem::evaluate(const Vector& u, Vector& F, SparseMatrix* J) const {
  using D = Dual<NC>;
  const Shear s = shear();
  const double L[2][2] = {{0.0, s.gdot}, {0.0, 0.0}};
  D m[NC], r[NC];
  for (int i = 0; i < NC; ++i) m[i] = make_variable<NC>(u[i], i);
  const Conformation<D> M = conformation_of<NC>(m, o_.law.log_conformation);
  const D f = i_b_ >= 0 ? peterlin(o_.law.model, NC == 4, M, params_.value(i_b_)) : D(1.0);
  if (!(value_of(f) > 0.0)) return {StatusCode::InvalidState, "FENE-P: tr M reached 3b"};
  if (o_.law.log_conformation) {
    using std::exp;
    const Sym2<D> rate = log_conformation_rate(Sym2<D>{m[0], m[1], m[2]}, L, f, s.inv_lambda_eff);
    r[0] = rate.xx;
    r[1] = rate.xy;
    r[2] = rate.yy;
    if constexpr (NC == 4) r[3] = -s.inv_lambda_eff * (exp(-m[3]) - f);
  } else {
    const Conformation<D> rate = conformation_rate(M, L, f, s.inv_lambda_eff);
    r[0] = rate.xx;
    r[1] = rate.xy;
    r[2] = rate.yy;
    if constexpr (NC == 4) r[3] = rate.zz;
  }
  F.resize(NC);
  if (J) *J = pattern_;
  for (int i = 0; i < NC; ++i) {
    F[i] = s.lambda * value_of(r[i]);
    if (J)
      for (int j = 0; j < NC; ++j) J->coeffRef(i, j) = s.lambda * r[i].derivatives()[j];
  }
  if (!F.allFinite()) return {StatusCode::NotFinite, "steady-shear residual is not finite"};
  return {};
}

Status SteadyShearProblem::residual(const Vector& u, Vector& F) {
  return components_ == 4 ? evaluate<4>(u, F, nullptr) : evaluate<3>(u, F, nullptr);
}

Status SteadyShearProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  return components_ == 4 ? evaluate<4>(u, F, &J) : evaluate<3>(u, F, &J);
}

Status SteadyShearProblem::mass_matrix(const Vector&, SparseMatrix& B) {
  B = pattern_;
  for (int i = 0; i < components_; ++i) B.coeffRef(i, i) = shear().lambda;
  return {};
}

Vector SteadyShearProblem::initial_guess() {
  Vector u = Vector::Zero(components_);
  if (!o_.law.log_conformation) {
    u[0] = u[2] = 1.0;
    if (components_ == 4) u[3] = 1.0;
  }
  return u;
}

std::vector<Problem::Homotopy> SteadyShearProblem::homotopies() const {
  return {{"log10_rate", -6.0}};  // lambda_0 r ~ 1e-7: the rest state is the solution to rounding
}

std::vector<std::string> SteadyShearProblem::observable_names() const {
  return {"rate", "Wi_local", "eta", "eta_p", "N1", "M_xx", "M_xy", "M_yy"};
}

bool SteadyShearProblem::stress(const Vector& u, Conformation<double>& M, Conformation<double>& tau) const {
  M = components_ == 4 ? conformation_of<4>(u.data(), o_.law.log_conformation)
                       : conformation_of<3>(u.data(), o_.law.log_conformation);
  const double f = i_b_ >= 0 ? peterlin(o_.law.model, components_ == 4, M, params_.value(i_b_)) : 1.0;
  const double Gamma = params_.value(i_Gamma_), beta = params_.value(i_beta_);
  tau = polymer_stress(M, f, (1.0 - beta) * Gamma / params_.value(i_Wi_));
  return f > 0.0;
}

Status SteadyShearProblem::observables(const Vector& u, std::vector<double>& values) {
  Conformation<double> M, tau;
  if (!stress(u, M, tau)) return {StatusCode::InvalidState, "FENE-P: tr M reached 3b"};
  const Shear s = shear();
  const double beta = params_.value(i_beta_), rate = std::pow(10.0, params_.value(i_rate_));
  values = {
      rate, s.lambda * s.gdot, beta + tau.xy / s.gdot, tau.xy / (s.gdot * (1.0 - beta)), tau.xx - tau.yy, M.xx, M.xy,
      M.yy};
  return {};
}

SolutionFields SteadyShearProblem::fields(const Vector& u) const {
  Conformation<double> M, tau;
  stress(u, M, tau);
  SolutionFields f;
  NamedArray a{"state",
               "the homogeneous state: conformation M and polymer stress tau_p (in G)",
               Eigen::MatrixXd(1, 8),
               {"M_xx", "M_xy", "M_yy", "M_zz", "tau_xx", "tau_xy", "tau_yy", "tau_zz"}};
  a.values.row(0) << M.xx, M.xy, M.yy, M.zz, tau.xx, tau.xy, tau.yy, tau.zz;
  f.arrays.push_back(std::move(a));
  return f;
}

std::string SteadyShearProblem::summary() const {
  return fmt::format("steady simple shear of the {} law ({}), {} unknowns", to_string(o_.law.model),
                     o_.law.log_conformation ? "log-conformation" : "conformation", components_);
}

std::unique_ptr<Problem> SteadyShearProblem::from_scene(const Scene& scene) {
  return std::make_unique<SteadyShearProblem>(SteadyShearOptions::from_scene(scene));
}

}  // namespace keller
