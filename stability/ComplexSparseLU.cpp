#include "stability/ComplexSparseLU.hpp"

#include <umfpack.h>

#include <algorithm>
#include <stdexcept>

#include "core/UmfpackLU.hpp"

namespace keller {

using ComplexVector = ComplexSparseLU::ComplexVector;
using ComplexSparseMatrix = ComplexSparseLU::ComplexSparseMatrix;

ComplexSparseLU::ComplexSparseLU(SparseLUOptions options) { umfpack_control(options, control_); }

ComplexSparseLU::~ComplexSparseLU() {
  free_numeric();
  free_symbolic();
}

void ComplexSparseLU::free_numeric() {
  if (numeric_) umfpack_zi_free_numeric(&numeric_);
  numeric_ = nullptr;
}

void ComplexSparseLU::free_symbolic() {
  if (symbolic_) umfpack_zi_free_symbolic(&symbolic_);
  symbolic_ = nullptr;
}

bool ComplexSparseLU::same_pattern(const ComplexSparseMatrix& A) const {
  if (!symbolic_ || A.cols() + 1 != static_cast<long>(outer_.size()) ||
      A.nonZeros() != static_cast<long>(inner_.size()))
    return false;
  return std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
         std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
}

Status ComplexSparseLU::analyze(const ComplexSparseMatrix& A) {
  free_numeric();
  free_symbolic();
  n_ = static_cast<int>(A.rows());
  outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + n_ + 1);
  inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  real_.resize(A.nonZeros());
  imag_.resize(A.nonZeros());
  for (long k = 0; k < A.nonZeros(); ++k) {
    real_[k] = A.valuePtr()[k].real();
    imag_[k] = A.valuePtr()[k].imag();
  }
  ++analyses_;
  const int st = umfpack_zi_symbolic(n_, n_, outer_.data(), inner_.data(), real_.data(), imag_.data(), &symbolic_,
                                     control_, info_);
  if (st != UMFPACK_OK) {
    symbolic_ = nullptr;
    outer_.clear();
    inner_.clear();
    return umfpack_status(st, "complex symbolic analysis");
  }
  return {};
}

Status ComplexSparseLU::factorize(const ComplexSparseMatrix& A) {
  if (!A.isCompressed()) throw std::invalid_argument("ComplexSparseLU: matrix must be compressed");
  if (A.rows() != A.cols()) throw std::invalid_argument("ComplexSparseLU: matrix must be square");
  if (!same_pattern(A)) {
    Status st = analyze(A);
    if (!st.is_ok()) return st;
  }
  free_numeric();
  for (long k = 0; k < A.nonZeros(); ++k) {
    real_[k] = A.valuePtr()[k].real();
    imag_[k] = A.valuePtr()[k].imag();
  }
  ++factorisations_;
  const int st = umfpack_zi_numeric(outer_.data(), inner_.data(), real_.data(), imag_.data(), symbolic_, &numeric_,
                                    control_, info_);
  Status status = umfpack_status(st, "complex numeric factorisation");
  if (st < 0) numeric_ = nullptr;
  if (!status.is_ok()) free_numeric();
  return status;
}

Status ComplexSparseLU::solve(const ComplexVector& b, ComplexVector& x) {
  if (!numeric_) throw std::logic_error("ComplexSparseLU::solve before a successful factorize");
  if (b.size() != n_) throw std::invalid_argument("ComplexSparseLU::solve: size mismatch");
  const Eigen::VectorXd br = b.real(), bi = b.imag();
  Eigen::VectorXd xr(n_), xi(n_);
  const int st = umfpack_zi_solve(UMFPACK_A, outer_.data(), inner_.data(), real_.data(), imag_.data(), xr.data(),
                                  xi.data(), br.data(), bi.data(), numeric_, control_, info_);
  Status status = umfpack_status(st, "complex solve");
  if (!status.is_ok()) return status;
  x.resize(n_);
  x.real() = xr;
  x.imag() = xi;
  if (!x.allFinite()) return {StatusCode::NotFinite, "complex solve: solution is not finite"};
  return {};
}

}  // namespace keller
