#include "runs/NormalFormObserver.hpp"

#include <algorithm>
#include <cmath>
#include <complex>

#include <fmt/format.h>

#include "continuation/output/BranchFile.hpp"

namespace keller {

std::vector<double> normal_form_row(const NormalForm& nf) {
  const auto& types = normal_form_types();
  const auto it = std::find(types.begin(), types.end(), nf.type);
  const double type = it == types.end() ? NAN : static_cast<double>(it - types.begin());
  const bool hopf = nf.kind == NormalForm::Kind::Hopf, fold = nf.kind == NormalForm::Kind::Fold;
  const bool pitchfork = nf.type.rfind("pitchfork", 0) == 0;
  std::vector<double> row = {type,
          nf.exact_derivatives ? 1.0 : 0.0,
          hopf ? NAN : nf.a,
          hopf ? NAN : nf.b,
          hopf || fold ? NAN : nf.c,
          fold ? nf.curvature : NAN,
          pitchfork ? nf.cubic : NAN,
          fold ? NAN : nf.growth_rate_derivative,
          hopf ? nf.omega : NAN,
          hopf ? nf.period : NAN,
          hopf ? nf.l1 : NAN,
          hopf ? nf.c1.real() : NAN,
          hopf ? nf.c1.imag() : NAN,
          hopf ? nf.amplitude_coefficient : NAN,
          hopf ? static_cast<double>(nf.amplitude_entry) : NAN,
          hopf || pitchfork ? static_cast<double>(nf.side) : NAN,
          nf.seconds};
  for (double a : nf.observable_amplitudes) row.push_back(hopf ? a : NAN);
  return row;
}

NormalFormObserver::NormalFormObserver(BranchObserver& inner, Problem& problem, int parameter, SparseLUOptions lu)
    : inner_(inner), problem_(problem), parameter_(parameter), forms_(lu), has_time_form_(has_time_form(problem)) {}

void NormalFormObserver::on_point(const BranchPoint& p) {
  const bool wanted =
      p.kind == PointKind::Fold || p.kind == PointKind::BranchPoint || (p.kind == PointKind::Hopf && has_time_form_);
  if (!wanted) {
    inner_.on_point(p);
    return;
  }
  ParameterSet& params = problem_.parameters();
  const double before = params.value(parameter_);
  NormalForm nf;
  Status st;
  try {
    params.set(parameter_, p.lambda);
    if (p.kind == PointKind::Fold) {
      st = forms_.fold(problem_, parameter_, p.u, &p.tu, nf);
    } else if (p.kind == PointKind::BranchPoint) {
      st = forms_.branch_point(problem_, parameter_, p.u, nullptr, nf);
    } else {
      Eigen::VectorXcd guess;
      if (p.critical_re.size() == p.u.size()) {
        guess = p.critical_re.cast<std::complex<double>>();
        if (p.critical_im.size() == p.u.size()) guess += std::complex<double>(0.0, 1.0) * p.critical_im;
      }
      st = forms_.hopf(problem_, parameter_, p.u, p.critical_imag, guess.size() ? &guess : nullptr, nf);
    }
  } catch (const std::exception& e) {
    st = Status(StatusCode::InvalidState, e.what());
  }
  params.set(parameter_, before);
  if (!st.is_ok()) {
    inner_.on_point(p);
    inner_.on_note(fmt::format("the normal form at row {} was not computed: {}", p.index, st.message()));
    return;
  }
  BranchPoint with = p;
  with.normal_form = normal_form_row(nf);
  with.normal_form.resize(with.normal_form.size() + problem_.observable_names().size() - nf.observable_amplitudes.size(),
                          NAN);
  inner_.on_point(with);
  inner_.on_note(fmt::format("{} ({} derivatives, {:.2f} s)", nf.summary(),
                             nf.exact_derivatives ? "exact" : "difference", nf.seconds));
}

}  // namespace keller
