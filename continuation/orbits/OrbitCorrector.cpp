#include "continuation/orbits/OrbitCorrector.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "core/Gmres.hpp"

namespace keller {

namespace {
// Eisenstat-Walker choice 2: eta_k = gamma (|R_k| / |R_(k-1)|)^2, within [kEtaMin, kEtaMax]
constexpr double kEtaMax = 1e-2, kEtaMin = 1e-12, kEtaGamma = 0.9;
// a Newton step that raises the residual above this multiple of the first one: diverged
constexpr double kDivergence = 1e4;
constexpr double kMaxPeriodChange = 0.5;
}  // namespace

double OrbitCorrector::pass_tolerance(double eta) { return std::max(kPassShare * eta, ShootingMap::kTightPass); }

bool OrbitCorrector::converged(double residual, double last_update, double contraction, double tolerance) {
  if (!(residual <= tolerance)) return false;
  if (last_update <= tolerance) return true;
  return contraction <= kTrustedContraction && contraction * last_update <= tolerance;
}

OrbitCorrection OrbitCorrector::correct(Vector& u0, double& T, double& lambda, bool free_lambda, const OrbitGrid& grid,
                                        const Vector& u_ref, const Vector& n, const OrbitRow& row) {
  Problem& problem = map_.problem();
  const int p = map_.parameter();
  if (free_lambda && p < 0) throw std::logic_error("orbit corrector: lambda is free but the map has no parameter");
  const long N = u0.size();
  if (n.size() != N || u_ref.size() != N) throw std::invalid_argument("orbit corrector: phase vectors of wrong size");
  OrbitCorrection out;
  if (!free_lambda && p >= 0) lambda = problem.parameters().value(p);
  const double nn = n.norm();
  if (!(nn > 0.0)) throw std::invalid_argument("orbit corrector: the phase normal is zero");
  const Vector normal = n / nn;
  const int extra = free_lambda ? 2 : 1;  // T (scaled by T: relative change) [and lambda]
  auto row_value = [&](const Vector& u, double t, double l) {
    double v = row.a_T * (t - row.z_T) + row.a_lambda * (l - row.z_lambda);
    if (row.a_u.size() == N) v += row.a_u.dot(row.z_u.size() == N ? Vector(u - row.z_u) : u);
    return v;
  };
  // dPhi/dlambda for the preconditioner's border, at the first iterate (a preconditioner need not
  // follow it; without it the border is singular where the branch turns in lambda)
  Vector phi_lambda;
  double eta = kEtaMax, previous = 0.0, first = 0.0;
  double last_update = 0.0;  // the last Newton update: max(|du|_inf / scale, |dT| / T)
  for (int it = 0;; ++it) {
    if (free_lambda) problem.parameters().set(p, lambda);
    Status st = map_.integrate(u0, T, grid);
    if (!st.is_ok()) {
      out.status = st;
      return out;
    }
    Vector R(N + extra);
    R.head(N) = map_.end() - u0;
    R[N] = normal.dot(u0 - u_ref);
    if (free_lambda) R[N + 1] = row_value(u0, T, lambda);
    const double scale = std::max(u0.lpNorm<Eigen::Infinity>(), 1.0);
    out.residual = R.head(N).lpNorm<Eigen::Infinity>();
    const double norm = R.norm();
    if (options_.progress) options_.progress(it, out.residual, out.krylov_iterations);
    if (it > 0 && converged(out.residual / scale, last_update, norm / previous, options_.tolerance)) return out;
    if (it == 0) first = norm;
    if (it > 0) {
      if (norm > kDivergence * std::max(first, 1e-300)) {
        out.status = {StatusCode::NotConverged,
                      fmt::format("orbit corrector: diverged (|R| {:.3e} from {:.3e})", norm, first)};
        return out;
      }
      eta = std::clamp(kEtaGamma * (norm / previous) * (norm / previous), kEtaMin, kEtaMax);
    }
    previous = norm;
    if (it >= options_.max_iterations) {
      out.status = {StatusCode::NotConverged,
                    fmt::format("orbit corrector: {} iterations, |Phi - u0| = {:.3e}", it, out.residual)};
      return out;
    }
    // the border's rows and corner (the phase row; the closing row), the same in the product and
    // in the preconditioner
    Eigen::MatrixXd B = Eigen::MatrixXd::Zero(N, extra), D = Eigen::MatrixXd::Zero(extra, extra);
    B.col(0) = normal;
    if (free_lambda) {
      if (row.a_u.size() == N) B.col(1) = row.a_u;
      D(1, 0) = row.a_T * T;
      D(1, 1) = row.a_lambda;
    }
    // one pass per product: the T and lambda columns go into the pass with the state's (a pass is
    // linear in all three), not as two passes of their own per iteration
    const double pass = pass_tolerance(eta);
    Status failed;
    auto A = [&](const Vector& z) {
      Vector y(N + extra), Mv;
      Status s = map_.linearised(z.head(N), T * z[N], free_lambda ? z[N + 1] : 0.0, Mv, pass);
      if (!s.is_ok()) {
        if (failed.is_ok()) failed = s;
        Mv = Vector::Zero(N);
      }
      y.head(N) = Mv - z.head(N);
      y.tail(extra) = B.transpose() * z.head(N) + D * z.tail(extra);
      return y;
    };
    // the preconditioner (BorderedDeflation): the deflation with the border; its columns are the
    // period's, T dPhi/dT ~ T f(Phi) (ShootingMap.TheEndRate...), and lambda's, by one pass a
    // correction where the closing row couples lambda to the rest (a fixed lambda's row does not:
    // its component of every Krylov vector stays 0, and the column would never be used)
    if (free_lambda && phi_lambda.size() == 0) {
      if (row.a_u.size() == N || row.a_T != 0.0) {
        Status s = map_.linearised(Vector::Zero(N), 0.0, 1.0, phi_lambda, pass);
        if (!s.is_ok()) {
          out.status = s;
          return out;
        }
      } else {
        phi_lambda = Vector::Zero(N);
      }
    }
    Eigen::MatrixXd C = Eigen::MatrixXd::Zero(N, extra);
    C.col(0) = T * map_.end_rate();
    if (free_lambda) C.col(1) = phi_lambda;
    const BorderedDeflation border(deflation_, C, B, D);
    auto precondition = [&](const Vector& z) { return border.apply(z); };
    Vector dz;
    const GmresResult g = gmres(A, precondition, Vector(-R), dz, eta, options_.krylov_iterations);
    out.krylov_iterations += g.iterations;
    if (!failed.is_ok()) {
      out.status = failed;
      return out;
    }
    if (!g.converged && !(g.residual <= 0.5 * norm)) {
      out.status = {StatusCode::NotConverged,
                    fmt::format("orbit corrector: GMRES did not converge in {} iterations", g.iterations)};
      return out;
    }
    // a step that would change the period by more than kMaxPeriodChange of itself is cut back to
    // that, whole (Newton's first steps from a rough guess can throw T past zero)
    if (std::abs(dz[N]) > kMaxPeriodChange) dz *= kMaxPeriodChange / std::abs(dz[N]);
    u0 += dz.head(N);
    const double dT = T * dz[N];
    T += dT;
    if (free_lambda) lambda += dz[N + 1];
    out.iterations = it + 1;
    last_update = std::max(dz.head(N).lpNorm<Eigen::Infinity>() / scale, std::abs(dT) / T);
  }
}

}  // namespace keller
