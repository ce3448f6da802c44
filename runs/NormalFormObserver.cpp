#include "runs/NormalFormObserver.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <functional>

#include <fmt/format.h>

#include "continuation/output/BranchFile.hpp"

namespace keller {

std::vector<double> normal_form_row(const NormalForm& nf) {
  const auto& types = normal_form_types();
  const auto it = std::find(types.begin(), types.end(), nf.type);
  const double type = it == types.end() ? NAN : static_cast<double>(it - types.begin());
  const bool hopf = nf.kind == NormalForm::Kind::Hopf, fold = nf.kind == NormalForm::Kind::Fold;
  const bool cusp = nf.kind == NormalForm::Kind::Cusp, pitchfork = nf.type.rfind("pitchfork", 0) == 0;
  const bool bt = nf.kind == NormalForm::Kind::BogdanovTakens, zh = nf.kind == NormalForm::Kind::FoldHopf;
  std::vector<double> row = {type,
                             nf.exact_derivatives ? 1.0 : 0.0,
                             hopf ? NAN : nf.a,
                             hopf ? NAN : nf.b,
                             hopf || fold || bt ? NAN : nf.c,
                             fold || cusp ? nf.curvature : NAN,
                             pitchfork || cusp ? nf.cubic : NAN,
                             fold || cusp || bt || zh ? NAN : nf.growth_rate_derivative,
                             hopf || zh ? nf.omega : NAN,
                             hopf || zh ? nf.period : NAN,
                             hopf ? nf.l1 : NAN,
                             hopf || zh ? nf.c1.real() : NAN,
                             hopf || zh ? nf.c1.imag() : NAN,
                             hopf ? nf.amplitude_coefficient : NAN,
                             hopf ? static_cast<double>(nf.amplitude_entry) : NAN,
                             hopf || pitchfork ? static_cast<double>(nf.side) : NAN,
                             nf.seconds};
  for (double a : nf.observable_amplitudes) row.push_back(hopf ? a : NAN);
  return row;
}

namespace {

// compute() with the parameter at `value` (restored after); an exception becomes a failed status
Status at_parameter(Problem& problem, int parameter, double value, const std::function<Status()>& compute) {
  ParameterSet& params = problem.parameters();
  const double before = params.value(parameter);
  Status st;
  try {
    params.set(parameter, value);
    st = compute();
  } catch (const std::exception& e) {
    st = Status(StatusCode::InvalidState, e.what());
  }
  params.set(parameter, before);
  return st;
}

}  // namespace

std::optional<Continuation::SwitchPrediction> switch_prediction(Problem& problem, int parameter, const BranchPoint& bp,
                                                                SparseLUOptions lu, std::string& note) {
  NormalForm nf;
  const Status st = at_parameter(problem, parameter, bp.lambda,
                                 [&] { return NormalForms(lu).branch_point(problem, parameter, bp.u, nullptr, nf); });
  if (!st.is_ok()) {
    note = "no normal form at the branch point (" + st.message() + "): the switch takes J's null vector";
    return std::nullopt;
  }
  if (nf.tangent_u[0].size() != bp.u.size()) {
    note = "the normal form at the branch point is an " + nf.type + ": the switch takes J's null vector";
    return std::nullopt;
  }
  // the branch least parallel to the old tangent (plain inner product of unit vectors)
  const double old = std::sqrt(bp.tu.squaredNorm() + bp.tlambda * bp.tlambda);
  auto overlap = [&](int k) {
    const double n = std::sqrt(nf.tangent_u[k].squaredNorm() + nf.tangent_lambda[k] * nf.tangent_lambda[k]);
    return std::abs(nf.tangent_u[k].dot(bp.tu) + nf.tangent_lambda[k] * bp.tlambda) / (n * old);
  };
  const int k = overlap(0) <= overlap(1) ? 0 : 1;
  Continuation::SwitchPrediction p;
  p.tu = nf.tangent_u[k];
  p.tl = nf.tangent_lambda[k];
  // a fixed sign, as J's null vector's: the entry of largest magnitude positive (the parameter part
  // where the state part vanishes)
  Eigen::Index imax = 0;
  const double largest = p.tu.size() ? p.tu.cwiseAbs().maxCoeff(&imax) : 0.0;
  const double lead = largest > 1e-12 * std::abs(p.tl) ? p.tu[imax] : p.tl;
  if (lead < 0) {
    p.tu = -p.tu;
    p.tl = -p.tl;
  }
  if (k == 0 && nf.second_u.size() == bp.u.size()) {  // the parabola is even in eps: no sign change
    p.second_u = nf.second_u;
    p.second_l = nf.second_lambda;
  }
  note = fmt::format("switching along the {} of the normal form ({})",
                     k == 0 && p.second_u.size() ? "parabola" : "tangent", nf.summary());
  return p;
}

HopfCurveProblem::LyapunovCoefficient unit_mode_lyapunov_coefficient(SparseLUOptions lu) {
  return [lu](Problem& inner, int p1, const Vector& u, double omega, const ComplexVector& mode, double& l1) {
    NormalForm nf;
    // (an exception of the problem at a difference step fails the value, as at_parameter does)
    const Status st = at_parameter(inner, p1, inner.parameters().value(p1),
                                   [&] { return NormalForms(lu).hopf(inner, p1, u, omega, &mode, nf); });
    if (st.is_ok()) l1 = nf.l1 / nf.q.squaredNorm();
    return st;
  };
}

NormalFormObserver::NormalFormObserver(BranchObserver& inner, Problem& problem, int parameter, SparseLUOptions lu)
    : inner_(inner), problem_(problem), parameter_(parameter), forms_(lu) {}

NormalFormObserver NormalFormObserver::for_curve(BranchObserver& inner, Problem& problem, int p1, int p2,
                                                 size_t observables, SparseLUOptions lu) {
  NormalFormObserver o(inner, problem, p1, lu);
  o.curve_p2_ = p2;
  o.curve_observables_ = observables;
  return o;
}

void NormalFormObserver::pass_on(const BranchPoint& p, const Status& st, const NormalForm& nf, size_t observables) {
  if (!st.is_ok()) {
    inner_.on_point(p);
    inner_.on_note(fmt::format("the normal form at row {} was not computed: {}", p.index, st.message()));
    return;
  }
  BranchPoint with = p;
  with.normal_form = normal_form_row(nf);
  with.normal_form.resize(with.normal_form.size() + observables - nf.observable_amplitudes.size(), NAN);
  inner_.on_point(with);
  inner_.on_note(fmt::format("{} ({} derivatives, {:.2f} s)", nf.summary(),
                             nf.exact_derivatives ? "exact" : "difference", nf.seconds));
}

void NormalFormObserver::on_point(const BranchPoint& p) {
  NormalForm nf;
  if (curve_p2_ >= 0) {  // a curve: its cusps, Bogdanov-Takens and fold-Hopf points
    const long n = problem_.size();
    const bool cusp = p.label == "cusp", bt = p.label == "bogdanov-takens", zh = p.label == "fold-hopf";
    if (p.kind != PointKind::Event || !(cusp || bt || zh) || p.u.size() <= n + (zh ? 1 : 0)) {
      inner_.on_point(p);
      return;
    }
    const Vector u = p.u.head(n);
    const Status st = at_parameter(problem_, curve_p2_, p.lambda, [&] {
      return at_parameter(problem_, parameter_, p.u[n], [&] {
        if (cusp) return forms_.cusp(problem_, parameter_, u, nullptr, nf);
        if (bt) return forms_.bogdanov_takens(problem_, parameter_, u, nf);
        return forms_.fold_hopf(problem_, parameter_, u, p.u[n + 1], nf);  // U = (u, p1, omega)
      });
    });
    pass_on(p, st, nf, curve_observables_);
    return;
  }
  if (p.kind == PointKind::Hopf && !has_time_form_) has_time_form_ = has_time_form(problem_, p.u);
  const bool wanted =
      p.kind == PointKind::Fold || p.kind == PointKind::BranchPoint || (p.kind == PointKind::Hopf && *has_time_form_);
  if (!wanted) {
    inner_.on_point(p);
    return;
  }
  const Status st = at_parameter(problem_, parameter_, p.lambda, [&]() -> Status {
    if (p.kind == PointKind::Fold) return forms_.fold(problem_, parameter_, p.u, &p.tu, nf);
    if (p.kind == PointKind::BranchPoint) return forms_.branch_point(problem_, parameter_, p.u, nullptr, nf);
    Eigen::VectorXcd guess;
    if (p.critical_re.size() == p.u.size()) {
      guess = p.critical_re.cast<std::complex<double>>();
      if (p.critical_im.size() == p.u.size()) guess += std::complex<double>(0.0, 1.0) * p.critical_im;
    }
    return forms_.hopf(problem_, parameter_, p.u, p.critical_imag, guess.size() ? &guess : nullptr, nf);
  });
  pass_on(p, st, nf, problem_.observable_names().size());
}

}  // namespace keller
