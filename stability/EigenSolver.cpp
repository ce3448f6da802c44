#include "stability/EigenSolver.hpp"

#include "stability/ComplexSparseLU.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <functional>
#include <limits>
#include <random>

// ARPACK (arpack-ng, Fortran, 32-bit integers and LOGICAL): the nonsymmetric real and complex
// drivers of the reverse-communication interface. Hidden CHARACTER lengths come last.
extern "C" {
void dnaupd_(int* ido, const char* bmat, const int* n, const char* which, const int* nev, const double* tol,
             double* resid, const int* ncv, double* v, const int* ldv, int* iparam, int* ipntr, double* workd,
             double* workl, const int* lworkl, int* info, std::size_t bmat_len, std::size_t which_len);
void dneupd_(const int* rvec, const char* howmny, int* select, double* dr, double* di, double* z, const int* ldz,
             const double* sigmar, const double* sigmai, double* workev, const char* bmat, const int* n,
             const char* which, const int* nev, const double* tol, double* resid, const int* ncv, double* v,
             const int* ldv, int* iparam, int* ipntr, double* workd, double* workl, const int* lworkl, int* info,
             std::size_t howmny_len, std::size_t bmat_len, std::size_t which_len);
void znaupd_(int* ido, const char* bmat, const int* n, const char* which, const int* nev, const double* tol,
             std::complex<double>* resid, const int* ncv, std::complex<double>* v, const int* ldv, int* iparam,
             int* ipntr, std::complex<double>* workd, std::complex<double>* workl, const int* lworkl, double* rwork,
             int* info, std::size_t bmat_len, std::size_t which_len);
void zneupd_(const int* rvec, const char* howmny, int* select, std::complex<double>* d, std::complex<double>* z,
             const int* ldz, const std::complex<double>* sigma, std::complex<double>* workev, const char* bmat,
             const int* n, const char* which, const int* nev, const double* tol, std::complex<double>* resid,
             const int* ncv, std::complex<double>* v, const int* ldv, int* iparam, int* ipntr,
             std::complex<double>* workd, std::complex<double>* workl, const int* lworkl, double* rwork, int* info,
             std::size_t howmny_len, std::size_t bmat_len, std::size_t which_len);
}

namespace keller {

namespace {

using Complex = std::complex<double>;
using ComplexVector = Eigen::VectorXcd;
// y = OP x for a complex x (the real operator acts on real and imaginary parts separately).
using ComplexOperator = std::function<Status(const ComplexVector&, ComplexVector&)>;

// A converged Ritz pair of OP: nu and its (unpurified) vector.
struct RitzPair {
  Complex nu;
  ComplexVector x;
};

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// J - s B on the union of the two patterns, which is J's own pattern when B's is a subset of it
// (so the LU's symbolic analysis is shared with J's); entries that cancel are kept.
template <class Scalar>
Eigen::SparseMatrix<Scalar, Eigen::ColMajor, int> shifted(const SparseMatrix& J, const SparseMatrix& B, Scalar s) {
  Eigen::SparseMatrix<Scalar, Eigen::ColMajor, int> A(J.rows(), J.cols());
  A.reserve(J.nonZeros() + B.nonZeros());
  for (int j = 0; j < J.outerSize(); ++j) {
    A.startVec(j);
    SparseMatrix::InnerIterator a(J, j), b(B, j);
    while (a || b) {
      if (a && (!b || a.index() < b.index())) {
        A.insertBack(a.index(), j) = Scalar(a.value());
        ++a;
      } else if (!a || b.index() < a.index()) {
        A.insertBack(b.index(), j) = -s * b.value();
        ++b;
      } else {
        A.insertBack(a.index(), j) = Scalar(a.value()) - s * b.value();
        ++a;
        ++b;
      }
    }
  }
  A.finalize();
  return A;
}

ComplexVector times(const SparseMatrix& A, const ComplexVector& x) {
  ComplexVector y(A.rows());
  y.real() = A * x.real();
  y.imag() = A * x.imag();
  return y;
}

// sqrt(||A||_1 ||A||_inf) >= ||A||_2, cheap for a sparse matrix.
double norm_bound(const SparseMatrix& A) {
  Eigen::VectorXd row_sums = Eigen::VectorXd::Zero(A.rows());
  double max_column = 0;
  for (int j = 0; j < A.outerSize(); ++j) {
    double column = 0;
    for (SparseMatrix::InnerIterator it(A, j); it; ++it) {
      column += std::abs(it.value());
      row_sums[it.index()] += std::abs(it.value());
    }
    max_column = std::max(max_column, column);
  }
  return std::sqrt(max_column * (A.rows() > 0 ? row_sums.maxCoeff() : 0.0));
}

bool all_finite(const SparseMatrix& A) {
  for (int j = 0; j < A.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(A, j); it; ++it)
      if (!std::isfinite(it.value())) return false;
  return true;
}

Vector random_start(int n) {
  std::mt19937_64 rng(20240607);
  std::uniform_real_distribution<double> U(-1.0, 1.0);
  Vector r(n);
  for (int i = 0; i < n; ++i) r[i] = U(rng);
  return r;
}

// The vector OP is first applied to: the random one, or the options' start vectors (each scaled
// to unit norm) with the random one at its weight of their sum's norm. For a real operator each
// vector's real and imaginary parts are added (both lie in the real invariant subspace; a
// conjugate pair's vectors would otherwise cancel their imaginary parts).
ComplexVector start_vector(int n, const EigenOptions& o, bool real) {
  const Vector random = random_start(n);
  ComplexVector sum = ComplexVector::Zero(n);
  for (const auto& v : o.start) {
    if (v.size() != n || !(v.norm() > 0) || !v.allFinite()) continue;
    if (real)
      sum.real() += (v.real() + v.imag()) / v.norm();
    else
      sum += v / v.norm();
  }
  if (!(sum.norm() > 0)) return random.cast<Complex>();
  return sum + (o.start_random_weight * sum.norm() / random.norm()) * random.cast<Complex>();
}

std::string arpack_reason(int info) {
  switch (info) {
    case 1: return "the restart limit was reached";
    case 3: return "no shifts could be applied in an implicit restart (increase ncv)";
    case -7: return "the work array is too short";
    case -8: return "LAPACK failed in the eigenvalues of the Hessenberg matrix";
    case -9: return "the start vector is zero";
    case -14: return "no Ritz value converged";
    case -15: return "the converged count differs between the iteration and the extraction";
    case -9999: return "no Arnoldi factorisation could be built";
    default: return info < 0 ? "invalid arguments" : "unknown condition";
  }
}

Status arpack_status(const char* routine, int info, const EigenOptions& o, int converged) {
  return {StatusCode::NotConverged,
          fmt::format("eigen solver: ARPACK {} info {} ({}); {} of {} eigenvalues converged (tolerance {:g}, "
                      "max_restarts {})",
                      routine, info, arpack_reason(info), converged, o.count, o.tolerance, o.max_restarts)};
}

// dnaupd/dneupd on the real operator `op`; fills the converged Ritz pairs, unpacking the
// complex-conjugate pairs stored as (real part, imaginary part) columns.
Status real_arnoldi(int n, int nev, int ncv, const EigenOptions& o, const Vector& start,
                    const std::function<Status(const Vector&, Vector&)>& op, std::vector<RitzPair>& ritz,
                    EigenResult& out) {
  const char bmat = 'I', howmny = 'A';
  const char which[] = "LM";
  const int ldv = n, lworkl = 3 * ncv * ncv + 6 * ncv;
  const double tol = o.tolerance;
  int ido = 0, info = 1;  // info = 1: resid holds the start vector
  int iparam[11] = {}, ipntr[14] = {};
  iparam[0] = 1;  // exact shifts
  iparam[2] = o.max_restarts;
  iparam[6] = 1;  // regular mode on OP
  Vector resid = start;
  std::vector<double> v(static_cast<std::size_t>(n) * ncv), workd(3 * static_cast<std::size_t>(n)), workl(lworkl);
  Vector x(n), y(n);
  for (;;) {
    dnaupd_(&ido, &bmat, &n, which, &nev, &tol, resid.data(), &ncv, v.data(), &ldv, iparam, ipntr, workd.data(),
            workl.data(), &lworkl, &info, 1, 2);
    if (ido != -1 && ido != 1) break;
    x = Eigen::Map<const Vector>(&workd[ipntr[0] - 1], n);
    Status st = op(x, y);
    if (!st.is_ok()) return st;
    Eigen::Map<Vector>(&workd[ipntr[1] - 1], n) = y;
  }
  out.restarts = iparam[2];
  if (ido != 99)
    return {StatusCode::NotConverged, fmt::format("eigen solver: unexpected ARPACK dnaupd request {}", ido)};
  const Status iteration = info == 0 ? Status{} : arpack_status("dnaupd", info, o, iparam[4]);
  if (info < 0 || iparam[4] <= 0) return iteration;

  const int rvec = 1, ldz = n;
  const double sigmar = 0, sigmai = 0;
  std::vector<int> select(ncv);
  std::vector<double> dr(ncv), di(ncv), z(static_cast<std::size_t>(n) * ncv), workev(3 * ncv);
  int extract_info = 0;
  dneupd_(&rvec, &howmny, select.data(), dr.data(), di.data(), z.data(), &ldz, &sigmar, &sigmai, workev.data(), &bmat,
          &n, which, &nev, &tol, resid.data(), &ncv, v.data(), &ldv, iparam, ipntr, workd.data(), workl.data(), &lworkl,
          &extract_info, 1, 1, 2);
  if (extract_info != 0) return arpack_status("dneupd", extract_info, o, 0);
  const int nconv = iparam[4];
  out.converged = nconv;
  auto column = [&](int j) { return Eigen::Map<const Vector>(&z[static_cast<std::size_t>(j) * n], n); };
  for (int j = 0; j < nconv;) {
    if (di[j] == 0.0) {
      ritz.push_back({Complex(dr[j], 0.0), column(j).cast<Complex>()});
      ++j;
      continue;
    }
    if (j + 1 >= nconv) break;  // half a pair at the end: its vector is not available
    // columns j, j+1: real and imaginary parts of the vector of the value with positive imaginary part
    ComplexVector xp(n);
    xp.real() = column(j);
    xp.imag() = column(j + 1);
    const Complex nu_p(dr[j], std::abs(di[j]));
    ritz.push_back({nu_p, xp});
    ritz.push_back({std::conj(nu_p), xp.conjugate()});
    j += 2;
  }
  return iteration;
}

// znaupd/zneupd on the complex operator `op`.
Status complex_arnoldi(int n, int nev, int ncv, const EigenOptions& o, const ComplexVector& start,
                       const ComplexOperator& op, std::vector<RitzPair>& ritz, EigenResult& out) {
  const char bmat = 'I', howmny = 'A';
  const char which[] = "LM";
  const int ldv = n, lworkl = 3 * ncv * ncv + 5 * ncv;
  const double tol = o.tolerance;
  int ido = 0, info = 1;
  int iparam[11] = {}, ipntr[14] = {};
  iparam[0] = 1;
  iparam[2] = o.max_restarts;
  iparam[6] = 1;
  ComplexVector resid = start;
  std::vector<Complex> v(static_cast<std::size_t>(n) * ncv), workd(3 * static_cast<std::size_t>(n)), workl(lworkl);
  std::vector<double> rwork(ncv);
  ComplexVector x(n), y(n);
  for (;;) {
    znaupd_(&ido, &bmat, &n, which, &nev, &tol, resid.data(), &ncv, v.data(), &ldv, iparam, ipntr, workd.data(),
            workl.data(), &lworkl, rwork.data(), &info, 1, 2);
    if (ido != -1 && ido != 1) break;
    x = Eigen::Map<const ComplexVector>(&workd[ipntr[0] - 1], n);
    Status st = op(x, y);
    if (!st.is_ok()) return st;
    Eigen::Map<ComplexVector>(&workd[ipntr[1] - 1], n) = y;
  }
  out.restarts = iparam[2];
  if (ido != 99)
    return {StatusCode::NotConverged, fmt::format("eigen solver: unexpected ARPACK znaupd request {}", ido)};
  const Status iteration = info == 0 ? Status{} : arpack_status("znaupd", info, o, iparam[4]);
  if (info < 0 || iparam[4] <= 0) return iteration;

  const int rvec = 1, ldz = n;
  const Complex sigma = 0.0;
  std::vector<int> select(ncv);
  std::vector<Complex> d(ncv), z(static_cast<std::size_t>(n) * ncv), workev(2 * ncv);
  int extract_info = 0;
  zneupd_(&rvec, &howmny, select.data(), d.data(), z.data(), &ldz, &sigma, workev.data(), &bmat, &n, which, &nev, &tol,
          resid.data(), &ncv, v.data(), &ldv, iparam, ipntr, workd.data(), workl.data(), &lworkl, rwork.data(),
          &extract_info, 1, 1, 2);
  if (extract_info != 0) return arpack_status("zneupd", extract_info, o, 0);
  const int nconv = iparam[4];
  out.converged = nconv;
  for (int j = 0; j < nconv; ++j)
    ritz.push_back({d[j], Eigen::Map<const ComplexVector>(&z[static_cast<std::size_t>(j) * n], n)});
  return {};
}

// Ritz pairs of OP -> eigenpairs of the pencil: drops the infinite eigenvalues, purifies the
// vectors (phi <- OP phi / nu), computes residuals with J and B, sorts.
Status finish(const std::vector<RitzPair>& ritz, Complex s, const ComplexOperator& op, const SparseMatrix& J,
              const SparseMatrix& B, const EigenOptions& o, EigenResult& out) {
  double max_nu = 0;
  for (const auto& r : ritz) max_nu = std::max(max_nu, std::abs(r.nu));
  const double infinite_below = 1e3 * std::numeric_limits<double>::epsilon() * max_nu;
  const double norm_j = norm_bound(J), norm_b = norm_bound(B);
  Status status;
  for (const auto& r : ritz) {
    if (!(std::abs(r.nu) > infinite_below)) {
      ++out.infinite_discarded;
      continue;
    }
    EigenPair pair;
    pair.value = s + 1.0 / r.nu;
    ComplexVector phi;
    Status st = op(r.x, phi);
    if (!st.is_ok()) return st;
    phi /= r.nu;
    const double norm = phi.norm();
    if (!(norm > 0) || !phi.allFinite())
      return {StatusCode::NotFinite,
              fmt::format("eigen solver: eigenvector of sigma = {} is not finite or zero", pair.value.real())};
    Eigen::Index k = 0;
    phi.cwiseAbs().maxCoeff(&k);
    phi *= std::conj(phi[k]) / (std::abs(phi[k]) * norm);
    const ComplexVector residual = times(J, phi) - pair.value * times(B, phi);
    pair.residual = residual.norm() / (norm_j + std::abs(pair.value) * norm_b);
    pair.accurate = pair.residual <= o.residual_tolerance;
    if (!pair.accurate && status.is_ok())
      status = {StatusCode::NotConverged,
                fmt::format("eigen solver: sigma = {:.10g}{:+.10g}i has relative residual {:.3g} > {:.3g}",
                            pair.value.real(), pair.value.imag(), pair.residual, o.residual_tolerance)};
    if (o.vectors) pair.vector = std::move(phi);
    out.pairs.push_back(std::move(pair));
  }
  order_spectrum(out.pairs);
  return status;
}

}  // namespace

void order_spectrum(std::vector<EigenPair>& pairs) {
  std::sort(pairs.begin(), pairs.end(),
            [](const EigenPair& a, const EigenPair& b) { return a.value.real() < b.value.real(); });
  // runs of real parts equal to rounding (relative to the values' size), each by imaginary part
  constexpr double kSameRealPart = 1e-12;
  auto same = [](const EigenPair& a, const EigenPair& b) {
    return std::abs(a.value.real() - b.value.real()) <=
           kSameRealPart * std::max({1.0, std::abs(a.value), std::abs(b.value)});
  };
  for (std::size_t i = 0; i < pairs.size();) {
    std::size_t j = i + 1;
    while (j < pairs.size() && same(pairs[j - 1], pairs[j])) ++j;
    std::sort(pairs.begin() + static_cast<std::ptrdiff_t>(i), pairs.begin() + static_cast<std::ptrdiff_t>(j),
              [](const EigenPair& a, const EigenPair& b) { return a.value.imag() < b.value.imag(); });
    i = j;
  }
}

namespace {

Status invalid(const std::string& what) { return {StatusCode::InvalidState, "eigen solver: " + what}; }

}  // namespace

EigenSolver::EigenSolver(SparseLUOptions lu) : lu_options_(lu), real_lu_(lu) {}

EigenSolver::~EigenSolver() = default;

Status EigenSolver::solve(const SparseMatrix& J, const SparseMatrix& B, const EigenOptions& o, EigenResult& out,
                          SparseLU* factorised_j) {
  const double t0 = now_seconds();
  out = EigenResult{};
  out.requested = o.count;
  const long n_long = J.rows();
  if (J.cols() != n_long || B.rows() != n_long || B.cols() != n_long)
    return invalid(
        fmt::format("J is {} x {} and B is {} x {}; both must be n x n", J.rows(), J.cols(), B.rows(), B.cols()));
  if (n_long > std::numeric_limits<int>::max() / 4) return invalid(fmt::format("n = {} is too large", n_long));
  const int n = static_cast<int>(n_long);
  if (o.count < 1 || o.count > n - 2)
    return invalid(fmt::format("count = {} is outside [1, n - 2] = [1, {}]", o.count, n - 2));
  const int ncv = o.ncv > 0 ? o.ncv : std::min(std::max(2 * o.count + 1, 20), n);
  if (ncv < o.count + 2 || ncv > n)
    return invalid(fmt::format("ncv = {} is outside [count + 2, n] = [{}, {}]", ncv, o.count + 2, n));
  if (!(o.tolerance >= 0) || o.max_restarts < 1 || !(o.residual_tolerance > 0))
    return invalid(fmt::format("tolerance = {:g} (>= 0), max_restarts = {} (>= 1), residual_tolerance = {:g} (> 0)",
                               o.tolerance, o.max_restarts, o.residual_tolerance));
  if (!std::isfinite(o.shift.real()) || !std::isfinite(o.shift.imag())) return invalid("the shift is not finite");
  if (!all_finite(J) || !all_finite(B)) return {StatusCode::NotFinite, "eigen solver: J or B has a NaN or Inf entry"};

  const Complex s = o.shift;
  std::vector<RitzPair> ritz;
  ComplexOperator op;
  Status iteration;
  if (s.imag() == 0.0) {
    SparseLU* lu = &real_lu_;
    if (factorised_j && s.real() == 0.0) {
      if (!factorised_j->factorized() || factorised_j->statistics().n != n)
        return invalid(fmt::format("the given factorisation of J is missing or of size {}, not {}",
                                   factorised_j->statistics().n, n));
      lu = factorised_j;
    } else {
      ++out.factorisations;
      const Status st = real_lu_.factorize(shifted(J, B, s.real()));
      if (!st.is_ok())
        return {st.code(), fmt::format("eigen solver: factorising J - s B at s = {:g}: {}", s.real(), st.message())};
    }
    auto real_op = [&out, lu, &B](const Vector& x, Vector& y) {
      ++out.solves;
      // plain solves: the eigenpairs are checked by their residuals with the original J and B
      return lu->solve(B * x, y, false, 0);
    };
    op = [real_op](const ComplexVector& x, ComplexVector& y) {
      Vector yr, yi;
      Status st = real_op(x.real(), yr);
      if (!st.is_ok()) return st;
      if (x.imag().isZero(0.0))
        yi.setZero(yr.size());
      else if (!(st = real_op(x.imag(), yi)).is_ok())
        return st;
      y.resize(yr.size());
      y.real() = yr;
      y.imag() = yi;
      return Status{};
    };
    Vector start;
    const Status st = real_op(start_vector(n, o, true).real(), start);
    if (!st.is_ok()) return st;
    if (start.norm() == 0) return invalid("B is zero: the pencil has no finite eigenvalue");
    iteration = real_arnoldi(n, o.count, ncv, o, start, real_op, ritz, out);
  } else {
    if (!complex_lu_) complex_lu_ = std::make_unique<ComplexSparseLU>(lu_options_);
    ++out.factorisations;
    const Status st = complex_lu_->factorize(shifted(J, B, s));
    if (!st.is_ok())
      return {st.code(),
              fmt::format("eigen solver: factorising J - s B at s = {:g}{:+g}i: {}", s.real(), s.imag(), st.message())};
    op = [this, &out, &B](const ComplexVector& x, ComplexVector& y) {
      ++out.solves;
      return complex_lu_->solve(times(B, x), y);
    };
    ComplexVector start;
    const Status sst = op(start_vector(n, o, false), start);
    if (!sst.is_ok()) return sst;
    if (start.norm() == 0) return invalid("B is zero: the pencil has no finite eigenvalue");
    iteration = complex_arnoldi(n, o.count, ncv, o, start, op, ritz, out);
  }
  if (!iteration.is_ok() && ritz.empty()) {
    out.seconds = now_seconds() - t0;
    return iteration;
  }
  const Status finished = finish(ritz, s, op, J, B, o, out);
  out.seconds = now_seconds() - t0;
  return iteration.is_ok() ? finished : iteration;
}

}  // namespace keller
