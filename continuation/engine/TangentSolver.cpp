#include "continuation/engine/TangentSolver.hpp"

#include <algorithm>
#include <cmath>

#include "core/Anderson.hpp"

namespace keller {

namespace {
int sign_of(double x) { return x > 0 ? 1 : (x < 0 ? -1 : 0); }
// The tangent system is solved to this residual relative to its scale: far below what its uses
// (the predictor, the sign of the parameter part at folds) can see.
constexpr double kTangentTolerance = 1e-9;
// The iteration may make at least this many solves (or the corrector's limit, if larger): a
// factorisation costs tens of them.
constexpr int kMinTangentIterations = 12;
// Accelerated, the residual need not fall at every iteration: stalled when no new least residual
// came for this many iterations, or one rose this far above the least.
constexpr int kStallIterations = 3;
constexpr double kRiseAboveLeast = 10.0;
// Plain Richardson must at least halve the residual at every iteration.
constexpr double kPlainFall = 0.5;
// Converged also needs the error left after the last correction (its length times the factor by
// which the corrections fall) below this fraction of the tangent (arclength norm): the correction
// estimates the error the residual test cannot see where the system is stiff
// (|J| of 1e9 on a fine 1D mesh: a residual of 1e-9 |J| |z| then leaves the tangent 20 degrees off
// near a fold, and the finite-difference J v is not exact enough to go further). 1e-4 rad is far
// below what the tangent's uses see: the predictor's error from it is 1e-4 ds against ds^2 / 2 of
// the branch's curvature, the row needs only to be transversal, and folds and events found with
// it are located by Newton on their own functions.
constexpr double kTangentCorrection = 1e-4;
// ... and the sign of its parameter part certain (folds are found from it): that part's error
// below kSignMargin of its size, or, where the part is itself that small (at a fold), the error
// below kTangentSignCorrection of the tangent.
constexpr double kSignMargin = 0.5;
constexpr double kTangentSignCorrection = 1e-6;
}  // namespace

TangentSolver::TangentSolver(Evaluator& ev, KeptFactorisation& kept, const ArclengthNorm& norm,
                             const ContinuationOptions& options)
    : ev_(ev), kept_(kept), norm_(norm), options_(options) {}

bool TangentSolver::accurate(double error, double size, double mu_error, double mu) {
  if (!(error <= kTangentCorrection * size)) return false;
  return mu_error < kSignMargin * std::abs(mu) || error <= kTangentSignCorrection * size;
}

double TangentSolver::error_left(double correction, double previous) {
  return correction < previous ? correction * (correction / previous) : correction;
}

Status TangentSolver::unit(Vector v, double mu, const Vector& tu_prev, double tl_prev, Tangent& t) const {
  // (v, mu) solves [J F_p; c^T d] (v, mu) = (0, 1). Cramer: mu = det(J) / det(bordered), so this
  // is the sign of det J
  t.det_sign = sign_of(mu) * kept_.determinant_sign();
  const double nrm = norm_.norm(v, mu);
  if (!(nrm > 0) || !std::isfinite(nrm)) return {StatusCode::NotFinite, "tangent is zero or not finite"};
  const double sign = tu_prev.size() && norm_.dot(v, mu, tu_prev, tl_prev) < 0 ? -1.0 : 1.0;
  t.tu = (sign / nrm) * v;
  t.tl = sign * mu / nrm;
  return {};
}

Status TangentSolver::from_factorisation(const Vector& tu_prev, double tl_prev, Tangent& t) {
  Vector v;
  double mu = 0;
  const Status st = kept_.solve(Vector::Zero(ev_.size()), 1.0, v, mu);
  if (!st.is_ok()) return st;
  return unit(std::move(v), mu, tu_prev, tl_prev, t);
}

Status TangentSolver::initial(const Vector& u, double lambda, Tangent& t) {
  Status st = ev_.set_parameter(lambda);
  if (st.is_ok()) st = ev_.jacobian(u);
  if (st.is_ok()) st = ev_.parameter_derivative(u);
  if (!st.is_ok()) return st;
  // [J F_p; 0 1] gives (-J^-1 F_p, 1) where J is regular; at a fold J is singular and a generic
  // border row (0 on the parameter) is used instead.
  st = kept_.factorise_assembled(ev_, u, lambda, Constraint::parameter(0.0));
  if (st.code() == StatusCode::SingularMatrix) {
    Constraint generic;
    generic.cu.resize(ev_.size());
    for (int i = 0; i < generic.cu.size(); ++i) generic.cu[i] = std::sin(1.0 + 0.7 * i);  // deterministic, generic
    st = kept_.factorise_assembled(ev_, u, lambda, generic);
  }
  if (!st.is_ok()) return st;
  t.factorised = true;
  st = from_factorisation(Vector(), 0.0, t);
  if (!st.is_ok()) return st;
  if (t.tl * options_.direction < 0) {
    t.tu = -t.tu;
    t.tl = -t.tl;
  }
  return {};
}

Status TangentSolver::at_point(const BranchPoint& p, const Constraint& c, const Vector& tu_prev, double tl_prev,
                               bool refresh, Tangent& t, const BranchPoint* near) {
  t = Tangent{};
  if (!options_.corrector.kept()) {
    if (refresh) {
      const Status st = kept_.factorise_at(ev_, p.u, p.lambda, c);
      if (!st.is_ok()) return st;
      t.factorised = true;
    }
    return from_factorisation(tu_prev, tl_prev, t);
  }
  if (!refresh && kept_.block()) {
    Status st;
    if (by_iteration(p, c, tu_prev, tl_prev, t, st, near)) return st;
    if (!st.is_ok()) return st;
  }
  // a kept factorisation that has grown too old for the iteration (or refresh): one at p
  Status st = kept_.factorise_at(ev_, p.u, p.lambda, c);
  if (!st.is_ok()) return st;
  t.factorised = true;
  return from_factorisation(tu_prev, tl_prev, t);
}

bool TangentSolver::by_iteration(const BranchPoint& p, const Constraint& c, const Vector& tu_prev, double tl_prev,
                                 Tangent& t, Status& st, const BranchPoint* near) {
  // Richardson iteration on [J F_p; c^T d] z = (0, 1) at p, preconditioned by the kept
  // factorisation (possibly of an earlier point): converges while that is close to this one.
  st = ev_.set_parameter(p.lambda);
  if (st.is_ok()) st = ev_.parameter_derivative(p.u);
  if (!st.is_ok()) return false;
  const Vector& Fp = ev_.parameter_derivative_vector();
  const int n = ev_.size();
  const Vector cu = c.cu.size() ? c.cu : Vector::Zero(n);
  const double scale_j = kept_.system().matrix().coeffs().cwiseAbs().maxCoeff();  // of the kept bordered matrix
  const double scale_a = scale_j + Fp.cwiseAbs().maxCoeff() + cu.cwiseAbs().maxCoeff() + std::abs(c.cl);
  Vector v = Vector::Zero(n), rf = Vector::Zero(n), dv, jv;
  double mu = 0.0, rg = 1.0, dmu = 0.0, previous = INFINITY, before_previous = INFINITY;
  if (near && near->tu.size() == n) {
    // the tangent of a point close by, scaled to the row, and its residual: the iteration starts
    // there (a trial point between two located ones: a few solves instead of a dozen)
    const double along = cu.dot(near->tu) + c.cl * near->tlambda;
    if (std::abs(along) > 0 && ev_.jacobian_times(p.u, near->tu / along, jv).is_ok()) {
      v = near->tu / along;
      mu = near->tlambda / along;
      rf = -(jv + Fp * mu);
      rg = 0.0;
    }
  }
  // as many iterations as the corrector may make, while each falls and the rate says the
  // tolerance is within reach
  const int limit = std::max(kMinTangentIterations, options_.max_iterations());
  // accelerated like the corrector's chord: on this linear system that is GMRES with the kept
  // factorisation as preconditioner
  const int depth =
      options_.corrector.method == CorrectorOptions::Method::Chord ? options_.corrector.anderson_depth : 0;
  AndersonMixer mixer(depth);
  double best = INFINITY, first = INFINITY, last_correction = 0.0;
  int it_best = -1;
  bool converged = false;
  for (int it = 0; it < limit; ++it) {
    st = kept_.solve(rf, rg, dv, dmu, false);
    ++iterations_;
    if (!st.is_ok()) break;
    mixer.mix(v, mu, dv, dmu);
    v += dv;
    mu += dmu;
    const double correction = norm_.norm(dv, dmu);
    const double error = error_left(correction, last_correction);
    // (the parameter part's error: its share of the correction, falling as the whole does)
    const double mu_error = correction > 0 ? error * std::abs(dmu) / correction : 0.0;
    const bool small_correction = accurate(error, norm_.norm(v, mu), mu_error, mu);
    last_correction = correction;
    st = ev_.jacobian_times(p.u, v, jv);
    if (!st.is_ok()) break;
    rf = -(jv + Fp * mu);
    rg = 1.0 - cu.dot(v) - c.cl * mu;
    const double res = rf.cwiseAbs().maxCoeff() + std::abs(rg);
    const double scale = 1.0 + scale_a * (v.cwiseAbs().maxCoeff() + std::abs(mu));
    if (res < best) {
      best = res;
      it_best = it;
    }
    const bool accelerated = mixer.depth() > 0;
    const bool stalled = accelerated ? it - it_best >= kStallIterations || !(res <= kRiseAboveLeast * best)
                                     : !(res <= kPlainFall * previous);
    if (it == 0) first = res;
    if (res <= kTangentTolerance * scale && small_correction) {
      converged = true;
      break;
    }
    if (stalled || !std::isfinite(res)) break;
    // (the rate over the last two iterations, one alone wanders; accelerated, the mean rate to
    // the least residual so far, as its residual need not fall at every iteration)
    const double rate =
        accelerated ? std::pow(best / first, 1.0 / std::max(it_best, 1)) : std::sqrt(res / before_previous);
    if (it > 1 && rate < 1.0 &&
        it + 1 + std::log(kTangentTolerance * scale / (accelerated ? best : res)) / std::log(rate) > limit)
      break;
    before_previous = previous;
    previous = res;
  }
  if (!converged) {
    st = {};  // (an iteration that failed numerically falls back to a factorisation, like one that stalled)
    return false;
  }
  // The tangent is this point's, but the sign of det J is not: convergence on another point's
  // factorisation does not show that no eigenvalue crossed zero in between (accelerated, the
  // iteration converges past such a crossing; where F_p = 0 it is exact from any matrix). So 0,
  // not determined here; branch points are found from the factorisations (BranchPointMonitor).
  st = unit(std::move(v), mu, tu_prev, tl_prev, t);
  t.det_sign = 0;
  return true;
}

}  // namespace keller
