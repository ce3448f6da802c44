// GMRES for A x = b, real or complex, with a fixed linear right preconditioner P (x = P y), from
// x = 0, matrix-free: A and P are callables on vectors. The preconditioned basis vectors P v_k are
// kept, so that x is their combination and P is applied once per iteration, not once more at the end
// (where P is a sparse LU's solve and the system converges in a few iterations, that last solve was
// a fifth of the solves; the price is a second set of basis vectors in memory). Modified Gram-Schmidt applied twice
// (the Krylov basis stays orthogonal to rounding where the space nearly closes), the small least-squares problem solved
// by QR at each step; no restarts (the callers' systems converge in tens of iterations or are given a better
// preconditioner).
#pragma once

#include <Eigen/Core>
#include <Eigen/QR>
#include <complex>
#include <vector>

namespace keller {

struct GmresResult {
  int iterations = 0;      // matrix-vector products taken
  bool converged = false;  // the residual estimate reached tol |b|
  double residual = 0.0;   // the least-squares residual estimate |b - A x| at the end
};

// Stops once the residual estimate is at most tol |b| (converged), or after max_iterations with the
// best x of the space built (not converged). A breakdown (the space closes) ends with the exact
// solution of that space.
template <class Vec, class Apply, class Precondition>
GmresResult gmres(const Apply& A, const Precondition& P, const Vec& b, Vec& x, double tol, int max_iterations) {
  using Scalar = typename Vec::Scalar;
  using Dense = Eigen::Matrix<Scalar, Eigen::Dynamic, Eigen::Dynamic>;
  GmresResult r;
  const double beta = b.norm();
  x = Vec::Zero(b.size());
  if (beta == 0.0) {
    r.converged = true;
    return r;
  }
  std::vector<Vec> V{b / beta}, Z;  // Z[k] = P V[k]
  Dense H = Dense::Zero(max_iterations + 1, max_iterations);
  Vec y;
  auto solution = [&](int k) {  // x = P (V y) = Z y
    x = Vec::Zero(b.size());
    for (int i = 0; i <= k; ++i) x += y[i] * Z[static_cast<size_t>(i)];
  };
  for (int k = 0; k < max_iterations; ++k) {
    Z.push_back(P(V[static_cast<size_t>(k)]));
    Vec w = A(Z.back());
    for (int pass = 0; pass < 2; ++pass)
      for (int i = 0; i <= k; ++i) {
        const Scalar c = V[static_cast<size_t>(i)].dot(w);
        H(i, k) += c;
        w -= c * V[static_cast<size_t>(i)];
      }
    H(k + 1, k) = w.norm();
    Vec e = Vec::Zero(k + 2);
    e[0] = beta;
    const Dense Hk = H.topLeftCorner(k + 2, k + 1);
    y = Hk.householderQr().solve(e);
    r.iterations = k + 1;
    r.residual = (e - Hk * y).norm();
    const double next = std::real(H(k + 1, k));
    if (r.residual <= tol * beta || next == 0.0 || k + 1 == max_iterations) {
      r.converged = r.residual <= tol * beta || next == 0.0;
      solution(k);
      return r;
    }
    V.push_back(w / next);
  }
  return r;
}

}  // namespace keller
