#include "core/UmfpackLU.hpp"

#include <fmt/format.h>
#include <umfpack.h>

#include <algorithm>
#include <cmath>
#include <mutex>
#include <vector>

namespace keller {

static_assert(UMFPACK_CONTROL == kUmfpackControlSize && UMFPACK_INFO == 90, "UMFPACK array sizes changed");

void umfpack_control(const SparseLUOptions& options, double* control) {
  umfpack_di_defaults(control);
  switch (options.ordering) {
    case SparseLUOptions::Ordering::Amd: control[UMFPACK_ORDERING] = UMFPACK_ORDERING_AMD; break;
    case SparseLUOptions::Ordering::Metis: control[UMFPACK_ORDERING] = UMFPACK_ORDERING_METIS; break;
    case SparseLUOptions::Ordering::Cholmod: control[UMFPACK_ORDERING] = UMFPACK_ORDERING_CHOLMOD; break;
    case SparseLUOptions::Ordering::Best: control[UMFPACK_ORDERING] = UMFPACK_ORDERING_BEST; break;
  }
  switch (options.scaling) {
    case SparseLUOptions::Scaling::None: control[UMFPACK_SCALE] = UMFPACK_SCALE_NONE; break;
    case SparseLUOptions::Scaling::Sum: control[UMFPACK_SCALE] = UMFPACK_SCALE_SUM; break;
    case SparseLUOptions::Scaling::Max: control[UMFPACK_SCALE] = UMFPACK_SCALE_MAX; break;
  }
  switch (options.strategy) {
    case SparseLUOptions::Strategy::Auto: control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_AUTO; break;
    case SparseLUOptions::Strategy::Unsymmetric: control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_UNSYMMETRIC; break;
    case SparseLUOptions::Strategy::Symmetric: control[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC; break;
  }
  control[UMFPACK_PIVOT_TOLERANCE] = options.pivot_tolerance;
  control[UMFPACK_IRSTEP] = options.refinement_steps;
}

Status umfpack_status(int status, const std::string& what) {
  switch (status) {
    case UMFPACK_OK:
    case UMFPACK_WARNING_determinant_underflow:
    case UMFPACK_WARNING_determinant_overflow: return {};
    case UMFPACK_WARNING_singular_matrix:
      return {StatusCode::SingularMatrix, fmt::format("{}: matrix is singular", what)};
    case UMFPACK_ERROR_out_of_memory: return {StatusCode::LinearSolverError, fmt::format("{}: out of memory", what)};
    default: return {StatusCode::LinearSolverError, fmt::format("{}: UMFPACK status {}", what, status)};
  }
}

namespace {

const char* ordering_name(double used) {
  switch (static_cast<int>(used)) {
    case UMFPACK_ORDERING_AMD: return "amd/colamd";
    case UMFPACK_ORDERING_METIS: return "metis";
    case UMFPACK_ORDERING_CHOLMOD: return "cholmod";
    case UMFPACK_ORDERING_GIVEN: return "given";
    case UMFPACK_ORDERING_NONE: return "none";
    default: return "other";
  }
}

std::shared_ptr<void> own_symbolic(void* s) {
  return std::shared_ptr<void>(s, [](void* p) {
    if (p) umfpack_di_free_symbolic(&p);
  });
}

// The last symbolic analysis with its pattern and controls (one entry: a run factorises one
// pattern, J's, again and again from several places).
struct SymbolicCache {
  std::mutex mutex;
  std::vector<int> outer, inner;
  std::vector<double> control;
  std::shared_ptr<void> symbolic;
  double ordering_used = 0;
};

SymbolicCache& symbolic_cache() {
  static SymbolicCache cache;
  return cache;
}

class UmfpackLU final : public LUBackend {
 public:
  explicit UmfpackLU(const SparseLUOptions& options) { umfpack_control(options, control_); }
  ~UmfpackLU() override { free_numeric(); }
  UmfpackLU(const UmfpackLU&) = delete;
  UmfpackLU& operator=(const UmfpackLU&) = delete;

  Status analyze(const CscView& A, bool& reused) override {
    free_numeric();
    symbolic_.reset();
    SymbolicCache& cache = symbolic_cache();
    std::lock_guard<std::mutex> lock(cache.mutex);
    const std::vector<double> control(control_, control_ + UMFPACK_CONTROL);
    reused = cache.symbolic && cache.control == control && std::ssize(cache.outer) == A.n + 1 &&
             std::equal(cache.outer.begin(), cache.outer.end(), A.outer) && std::ssize(cache.inner) == A.nnz() &&
             std::equal(cache.inner.begin(), cache.inner.end(), A.inner);
    if (reused) {
      symbolic_ = cache.symbolic;
      ordering_used_ = cache.ordering_used;
      return {};
    }
    void* symbolic = nullptr;
    const int st = umfpack_di_symbolic(A.n, A.n, A.outer, A.inner, A.values, &symbolic, control_, info_);
    if (st != UMFPACK_OK) {
      if (symbolic) umfpack_di_free_symbolic(&symbolic);
      return umfpack_status(st, "symbolic analysis");
    }
    symbolic_ = own_symbolic(symbolic);
    ordering_used_ = info_[UMFPACK_ORDERING_USED];
    cache.outer.assign(A.outer, A.outer + A.n + 1);
    cache.inner.assign(A.inner, A.inner + A.nnz());
    cache.control = control;
    cache.symbolic = symbolic_;
    cache.ordering_used = ordering_used_;
    return {};
  }

  Status factorize(const CscView& A) override {
    free_numeric();
    const int st = umfpack_di_numeric(A.outer, A.inner, A.values, symbolic_.get(), &numeric_, control_, info_);
    Status status = umfpack_status(st, "numeric factorisation");
    if (st < 0) {
      numeric_ = nullptr;
      return status;
    }
    double mantissa = 0, exponent = 0;
    umfpack_di_get_determinant(&mantissa, &exponent, numeric_, nullptr);
    det_sign_ = mantissa > 0 ? 1 : (mantissa < 0 ? -1 : 0);
    log_abs_det_ = (mantissa != 0) ? std::log(std::abs(mantissa)) + exponent * std::log(10.0) : -INFINITY;
    if (!status.is_ok()) free_numeric();
    return status;
  }

  Status solve(const CscView& A, const double* b, double* x, bool transpose, int refinement_steps) override {
    double control[UMFPACK_CONTROL];
    std::copy(control_, control_ + UMFPACK_CONTROL, control);
    control[UMFPACK_IRSTEP] = refinement_steps;
    const int st = umfpack_di_solve(transpose ? UMFPACK_At : UMFPACK_A, A.outer, A.inner, A.values, x, b, numeric_,
                                    control, info_);
    return umfpack_status(st, "solve");
  }

  bool factorized() const override { return numeric_ != nullptr; }

  void determinant(int& sign, double& log_abs) const override {
    sign = det_sign_;
    log_abs = log_abs_det_;
  }

  void report(SparseLU::Statistics& s) const override {
    s.backend = "umfpack";
    s.ordering_used = ordering_name(ordering_used_);
    s.nnz_lu = info_[UMFPACK_LNZ] + info_[UMFPACK_UNZ] - info_[UMFPACK_NROW];
    s.flops = info_[UMFPACK_FLOPS];
    s.peak_memory_bytes = info_[UMFPACK_PEAK_MEMORY] * info_[UMFPACK_SIZE_OF_UNIT];
    s.numeric_bytes = info_[UMFPACK_NUMERIC_SIZE] * info_[UMFPACK_SIZE_OF_UNIT];
    s.rcond = info_[UMFPACK_RCOND];
  }

 private:
  void free_numeric() {
    if (numeric_) umfpack_di_free_numeric(&numeric_);
    numeric_ = nullptr;
  }

  double control_[UMFPACK_CONTROL];
  double info_[UMFPACK_INFO] = {};  // of the last call
  // shared: the last symbolic analysis is kept process-wide and reused by any SparseLU that
  // analyses the same pattern with the same controls (the first steady state's Newton solver,
  // the continuation's and the eigen-solver's factorisations of J: one analysis per run)
  std::shared_ptr<void> symbolic_;
  void* numeric_ = nullptr;
  double ordering_used_ = 0;
  int det_sign_ = 0;
  double log_abs_det_ = 0.0;
};

}  // namespace

std::unique_ptr<LUBackend> make_umfpack_lu(const SparseLUOptions& options) {
  return std::make_unique<UmfpackLU>(options);
}

}  // namespace keller
