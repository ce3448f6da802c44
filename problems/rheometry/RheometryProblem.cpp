#include "problems/rheometry/RheometryProblem.hpp"

#include <fmt/format.h>

#include <cmath>
#include <stdexcept>
#include <utility>

#include "core/AutoDiff.hpp"
#include "problems/kernels/ConformationTransport.hpp"
#include "problems/laws/LogConformation.hpp"

namespace keller {

const char* problem_type(HomogeneousFlow flow) {
  switch (flow) {
    case HomogeneousFlow::Shear: return "steady-shear";
    case HomogeneousFlow::PlanarExtension: return "planar-extension";
    case HomogeneousFlow::UniaxialExtension: return "uniaxial-extension";
  }
  return "?";
}

void RheometryOptions::declare(SceneSchema& s) {
  s.section("fluid", "the viscoelastic law and its formulation");
  LawKeys::declare(s, {"oldroyd-b", "fene-p", "owens", "giesekus", "ptt-linear", "ptt-exponential", "fene-cr"},
                   "owens");
  s.section("parameters", "initial values of the named continuation parameters");
  s.real("parameters.log10_rate", -3.0, "log10 of the dimensional shear or extension rate in 1/s",
         Range::between(-30.0, 30.0));
  s.real("parameters.Wi", 26.3,
         "Weissenberg number of the channel: lambda_0 = Wi W / U0 = Wi / rate_scale (0.263 s by default)",
         Range::positive());
  s.real("parameters.Gamma", 4.95e-4, "velocity scale of the channel (sets the model rate of a rate in 1/s)",
         Range::positive());
  s.real("parameters.beta", OwensParameters().beta(), "viscosity ratio eta_s / eta0", Range{0.0, 1.0, false, true});
  LawKeys::declare_constants(s);
}

RheometryOptions RheometryOptions::from_scene(const Scene& sc, HomogeneousFlow flow) {
  RheometryOptions o;
  o.flow = flow;
  o.law = LawKeys::from_scene(sc);
  if (flow != HomogeneousFlow::Shear && sc.differs_from_default("fluid.fene_p_dynamic_zz"))
    throw sc.error("fluid.fene_p_dynamic_zz", "has no meaning in extension, which always carries M_zz as an unknown");
  o.log10_rate = sc.real("parameters.log10_rate");
  o.Wi = sc.real("parameters.Wi");
  o.Gamma = sc.real("parameters.Gamma");
  o.beta = sc.real("parameters.beta");
  return o;
}

RheometryProblem::RheometryProblem(RheometryOptions options) : o_(std::move(options)) {
  if (o_.law.model == FluidModel::Newtonian)
    throw std::invalid_argument(std::string(problem_type(o_.flow)) +
                                ": a Newtonian fluid has no conformation (its viscosity is eta0)");
  const bool shear = o_.flow == HomogeneousFlow::Shear;
  nc_ = !shear || (o_.law.model == FluidModel::FeneP && o_.law.dynamic_zz) ? 4 : 3;
  i_rate_ = params_.add("log10_rate", o_.log10_rate, "log10 of the dimensional rate in 1/s", -30.0, 30.0);
  i_Wi_ = params_.add("Wi", o_.Wi, "Weissenberg number of the channel (lambda_0 = Wi W / U0)", Range::positive());
  i_Gamma_ = params_.add("Gamma", o_.Gamma, "velocity scale of the channel", Range::positive());
  i_beta_ = params_.add("beta", o_.beta, "viscosity ratio eta_s / eta0", Range{0.0, 1.0, false, true});
  i_law_ = add_law_parameters(params_, o_.law.model, o_.law.log_conformation, o_.law.constants);
  const std::vector<int> times = add_mode_parameters(params_, o_.law.modes);
  modes_.resize(std::max<size_t>(1, times.size()));
  for (size_t k = 0; k < times.size(); ++k) modes_[k] = {o_.law.modes[k].name, times[k], o_.law.modes[k].viscosity};
  components_ = nc_ * static_cast<int>(modes_.size());
  // the modes are coupled only through the given velocity gradient: one block each
  std::vector<Eigen::Triplet<double, int>> t;
  for (int b = 0; b < components_; b += nc_)
    for (int i = 0; i < nc_; ++i)
      for (int j = 0; j < nc_; ++j) t.emplace_back(b + i, b + j, 0.0);
  pattern_.resize(components_, components_);
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();
}

RheometryProblem::Kinematics RheometryProblem::kinematics() const {
  const double Gamma = params_.value(i_Gamma_);
  Kinematics k;
  k.rate = std::pow(10.0, params_.value(i_rate_)) * Gamma / o_.law.owens.rate_scale;
  k.lambda = params_.value(i_Wi_) / Gamma;
  switch (o_.flow) {
    case HomogeneousFlow::Shear: k.L[0][1] = k.rate; break;
    case HomogeneousFlow::PlanarExtension:
      k.L[0][0] = k.rate;
      k.L[1][1] = -k.rate;
      break;
    case HomogeneousFlow::UniaxialExtension:
      k.L[0][0] = k.rate;
      k.L[1][1] = k.Lzz = -0.5 * k.rate;
      break;
  }
  return k;
}

template <int NC>
Status RheometryProblem::evaluate(const Vector& u, Vector& F, SparseMatrix* J) const {
  using D = Dual<NC>;
  const Kinematics k = kinematics();
  const LawConstants<double> law = law_constants(i_law_, params_.values());
  const double* xi = i_law_.xi >= 0 ? &law.xi : nullptr;
  F.resize(components_);
  if (J) *J = pattern_;
  for (size_t mode = 0; mode < modes_.size(); ++mode) {
    const int at = static_cast<int>(mode) * NC;
    const double lambda = mode_relaxation_time(k.lambda, modes_[mode], params_.values());
    const double inv_lambda =
        inverse_relaxation_time(o_.law.model, lambda, k.L, params_.value(i_Gamma_), o_.law.owens, k.Lzz);
    D m[NC], r[NC];
    for (int i = 0; i < NC; ++i) m[i] = make_variable<NC>(u[at + i], i);
    const Conformation<D> M = conformation_of<NC>(m, o_.law.log_conformation);
    // the steady state of a law is positive definite; the conformation equations have other roots
    // too (Newton reaches them from a long step in fast extension): refused, so a shorter step is taken
    if (!o_.law.log_conformation && !(value_of(M.xx) > 0 && value_of(M.zz) > 0 &&
                                      value_of(M.xx) * value_of(M.yy) > value_of(M.xy) * value_of(M.xy)))
      return {StatusCode::InvalidState, "the conformation is not positive definite: not a state of the law"};
    const Relaxation<D> rel = relaxation(o_.law.model, NC == 4, M, law);
    if (const char* why = inadmissible_state(o_.law.model); why && !(value_of(rel.factor) > 0.0))
      return {StatusCode::InvalidState, why};
    if (o_.law.log_conformation) {
      const Sym2<D> rate =
          log_conformation_rate(Sym2<D>{m[0], m[1], m[2]}, k.L, rel, Sym2<D>{M.xx, M.xy, M.yy}, inv_lambda);
      r[0] = rate.xx;
      r[1] = rate.xy;
      r[2] = rate.yy;
      if constexpr (NC == 4) r[3] = log_conformation_rate_zz(m[3], rel, M.zz, inv_lambda, k.Lzz);
    } else {
      const Conformation<D> rate = conformation_rate(M, k.L, rel, inv_lambda, xi, k.Lzz);
      r[0] = rate.xx;
      r[1] = rate.xy;
      r[2] = rate.yy;
      if constexpr (NC == 4) r[3] = rate.zz;
    }
    for (int i = 0; i < NC; ++i) {
      F[at + i] = k.lambda * value_of(r[i]);
      if (J)
        for (int j = 0; j < NC; ++j) J->coeffRef(at + i, at + j) = k.lambda * r[i].derivatives()[j];
    }
  }
  if (!F.allFinite()) return {StatusCode::NotFinite, std::string(problem_type(o_.flow)) + " residual is not finite"};
  return {};
}

Status RheometryProblem::residual(const Vector& u, Vector& F) {
  return nc_ == 4 ? evaluate<4>(u, F, nullptr) : evaluate<3>(u, F, nullptr);
}

Status RheometryProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  return nc_ == 4 ? evaluate<4>(u, F, &J) : evaluate<3>(u, F, &J);
}

Status RheometryProblem::mass_matrix(const Vector&, SparseMatrix& B) {
  B = pattern_;
  for (int i = 0; i < components_; ++i) B.coeffRef(i, i) = kinematics().lambda;
  return {};
}

Vector RheometryProblem::initial_guess() {
  Vector u = Vector::Zero(components_);
  if (!o_.law.log_conformation)
    for (int b = 0; b < components_; b += nc_) {
      u[b] = u[b + 2] = 1.0;
      if (nc_ == 4) u[b + 3] = 1.0;
    }
  return u;
}

std::vector<Problem::Homotopy> RheometryProblem::homotopies() const {
  return {{"log10_rate", -6.0}};  // lambda_0 r ~ 1e-7: the rest state is the solution to rounding
}

std::vector<std::string> RheometryProblem::observable_names() const {
  if (o_.flow == HomogeneousFlow::Shear)
    return {"rate", "Wi_local", "eta", "eta_p", "N1", "M_xx", "M_xy", "M_yy", "psi1_p", "N2"};
  return {"rate", "Wi_local", "eta_e", "eta_e_p", "N1", "M_xx", "M_yy", "M_zz"};
}

bool RheometryProblem::stress(const Vector& u, Conformation<double>& M, Conformation<double>& tau) const {
  const LawConstants<double> law = law_constants(i_law_, params_.values());
  const double Gamma = params_.value(i_Gamma_), beta = params_.value(i_beta_);
  const double modulus = (1.0 - beta) * Gamma / params_.value(i_Wi_);
  bool admissible = true;
  tau = {0.0, 0.0, 0.0, 0.0};
  for (size_t mode = 0; mode < modes_.size(); ++mode) {
    const double* m = u.data() + mode * static_cast<size_t>(nc_);
    const Conformation<double> Mk =
        nc_ == 4 ? conformation_of<4>(m, o_.law.log_conformation) : conformation_of<3>(m, o_.law.log_conformation);
    const Relaxation<double> rel = relaxation(o_.law.model, nc_ == 4, Mk, law);
    const Conformation<double> t = polymer_stress(Mk, rel, mode_modulus(modulus, modes_[mode], params_.values()));
    tau = {tau.xx + t.xx, tau.xy + t.xy, tau.yy + t.yy, tau.zz + t.zz};
    if (mode == 0) M = Mk;
    admissible = admissible && rel.factor > 0.0;
  }
  return admissible;
}

Status RheometryProblem::observables(const Vector& u, std::vector<double>& values) {
  Conformation<double> M, tau;
  if (!stress(u, M, tau)) return {StatusCode::InvalidState, inadmissible_state(o_.law.model)};
  const Kinematics k = kinematics();
  const double beta = params_.value(i_beta_), r = std::pow(10.0, params_.value(i_rate_)), e = k.rate;
  const double W = k.lambda * e, N1 = tau.xx - tau.yy;
  if (o_.flow == HomogeneousFlow::Shear) {
    // polymer N1 / gdot^2 over 2 eta_p0 lambda, eta_p0 = 1 - beta in model units
    const double psi1 = N1 / (e * e * 2.0 * (1.0 - beta) * k.lambda);
    values = {r, W, beta + tau.xy / e, tau.xy / (e * (1.0 - beta)), N1, M.xx, M.xy, M.yy, psi1, tau.yy - tau.zz};
  } else {
    // the solvent's tau_xx - tau_yy = 2 beta (L_xx - L_yy): 4 beta eps planar, 3 beta eps uniaxial
    const double solvent = 2.0 * beta * (k.L[0][0] - k.L[1][1]);
    values = {r, W, (solvent + N1) / e, N1 / (e * (1.0 - beta)), N1, M.xx, M.yy, M.zz};
  }
  return {};
}

SolutionFields RheometryProblem::fields(const Vector& u) const {
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

std::string RheometryProblem::summary() const {
  return fmt::format("{} of the {} law ({}), {} mode{}, {} unknowns", problem_type(o_.flow), to_string(o_.law.model),
                     o_.law.log_conformation ? "log-conformation" : "conformation", modes_.size(),
                     modes_.size() == 1 ? "" : "s", components_);
}

}  // namespace keller
