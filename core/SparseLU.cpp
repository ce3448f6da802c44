#include "core/SparseLU.hpp"

#include <fmt/format.h>
#include <umfpack.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <mutex>
#include <stdexcept>

namespace keller {

static_assert(UMFPACK_CONTROL == 20 && UMFPACK_INFO == 90, "UMFPACK array sizes changed");

const char* to_string(SparseLUOptions::Ordering o) {
  switch (o) {
    case SparseLUOptions::Ordering::Amd: return "amd";
    case SparseLUOptions::Ordering::Metis: return "metis";
    case SparseLUOptions::Ordering::Cholmod: return "cholmod";
    case SparseLUOptions::Ordering::Best: return "best";
  }
  return "?";
}

SparseLUOptions::Ordering ordering_from_string(const std::string& s) {
  for (auto o : {SparseLUOptions::Ordering::Amd, SparseLUOptions::Ordering::Metis, SparseLUOptions::Ordering::Cholmod,
                 SparseLUOptions::Ordering::Best})
    if (s == to_string(o)) return o;
  throw std::invalid_argument("unknown ordering '" + s + "' (amd, metis, cholmod, best)");
}

SparseLUOptions::Strategy strategy_from_string(const std::string& s) {
  if (s == "auto") return SparseLUOptions::Strategy::Auto;
  if (s == "unsymmetric") return SparseLUOptions::Strategy::Unsymmetric;
  if (s == "symmetric") return SparseLUOptions::Strategy::Symmetric;
  throw std::invalid_argument("unknown strategy '" + s + "' (auto, unsymmetric, symmetric)");
}

void declare_linear_solver_keys(SceneSchema& s) {
  s.section("linear_solver", "UMFPACK sparse LU");
  s.string("linear_solver.ordering", "amd", "fill-reducing ordering", {"amd", "metis", "cholmod", "best"});
  s.string("linear_solver.scaling", "sum", "row scaling before factorisation", {"none", "sum", "max"});
  s.string("linear_solver.strategy", "auto",
           "UMFPACK's strategy: unsymmetric (column ordering, row pivoting), symmetric (ordering of A + A^T, "
           "diagonal pivots preferred), auto (UMFPACK chooses from the pattern)",
           {"auto", "unsymmetric", "symmetric"});
  s.real("linear_solver.pivot_tolerance", 0.1, "threshold partial pivoting tolerance", Range::between(0.0, 1.0));
  s.integer("linear_solver.refinement_steps", 2, "iterative refinement steps per solve (each costs about two solves)",
            Range::at_least(0));
}

SparseLUOptions sparse_lu_options_from(const Scene& scene) {
  SparseLUOptions o;
  o.ordering = ordering_from_string(scene.string("linear_solver.ordering"));
  const std::string sc = scene.string("linear_solver.scaling");
  o.scaling = sc == "none" ? SparseLUOptions::Scaling::None
                           : (sc == "max" ? SparseLUOptions::Scaling::Max : SparseLUOptions::Scaling::Sum);
  o.strategy = strategy_from_string(scene.string("linear_solver.strategy"));
  o.pivot_tolerance = scene.real("linear_solver.pivot_tolerance");
  o.refinement_steps = static_cast<int>(scene.integer("linear_solver.refinement_steps"));
  return o;
}

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

Status umfpack_status(int status, const char* what) {
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

}  // namespace

SparseLU::SparseLU(SparseLUOptions options) : options_(options) { set_control(); }

SparseLU::~SparseLU() {
  free_numeric();
  free_symbolic();
}

void SparseLU::set_control() {
  umfpack_di_defaults(control_);
  switch (options_.ordering) {
    case SparseLUOptions::Ordering::Amd: control_[UMFPACK_ORDERING] = UMFPACK_ORDERING_AMD; break;
    case SparseLUOptions::Ordering::Metis: control_[UMFPACK_ORDERING] = UMFPACK_ORDERING_METIS; break;
    case SparseLUOptions::Ordering::Cholmod: control_[UMFPACK_ORDERING] = UMFPACK_ORDERING_CHOLMOD; break;
    case SparseLUOptions::Ordering::Best: control_[UMFPACK_ORDERING] = UMFPACK_ORDERING_BEST; break;
  }
  switch (options_.scaling) {
    case SparseLUOptions::Scaling::None: control_[UMFPACK_SCALE] = UMFPACK_SCALE_NONE; break;
    case SparseLUOptions::Scaling::Sum: control_[UMFPACK_SCALE] = UMFPACK_SCALE_SUM; break;
    case SparseLUOptions::Scaling::Max: control_[UMFPACK_SCALE] = UMFPACK_SCALE_MAX; break;
  }
  switch (options_.strategy) {
    case SparseLUOptions::Strategy::Auto: control_[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_AUTO; break;
    case SparseLUOptions::Strategy::Unsymmetric: control_[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_UNSYMMETRIC; break;
    case SparseLUOptions::Strategy::Symmetric: control_[UMFPACK_STRATEGY] = UMFPACK_STRATEGY_SYMMETRIC; break;
  }
  control_[UMFPACK_PIVOT_TOLERANCE] = options_.pivot_tolerance;
  control_[UMFPACK_IRSTEP] = options_.refinement_steps;
}

void SparseLU::free_numeric() {
  if (numeric_) umfpack_di_free_numeric(&numeric_);
  numeric_ = nullptr;
}

void SparseLU::free_symbolic() { symbolic_.reset(); }

namespace {

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

std::shared_ptr<void> own_symbolic(void* s) {
  return std::shared_ptr<void>(s, [](void* p) {
    if (p) umfpack_di_free_symbolic(&p);
  });
}

}  // namespace

bool SparseLU::same_pattern(const SparseMatrix& A) const {
  if (!symbolic_ || A.cols() + 1 != static_cast<long>(outer_.size()) ||
      A.nonZeros() != static_cast<long>(inner_.size()))
    return false;
  return std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
         std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
}

Status SparseLU::analyze(const SparseMatrix& A) {
  if (!A.isCompressed()) throw std::invalid_argument("SparseLU: matrix must be compressed");
  if (A.rows() != A.cols()) throw std::invalid_argument("SparseLU: matrix must be square");
  free_numeric();
  free_symbolic();
  const double t0 = now_seconds();
  const int n = static_cast<int>(A.rows());
  outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + n + 1);
  inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  stats_.n = n;
  stats_.nnz_matrix = A.nonZeros();
  SymbolicCache& cache = symbolic_cache();
  std::lock_guard<std::mutex> lock(cache.mutex);
  const std::vector<double> control(control_, control_ + UMFPACK_CONTROL);
  if (cache.symbolic && cache.outer == outer_ && cache.inner == inner_ && cache.control == control) {
    symbolic_ = cache.symbolic;
    stats_.ordering_used = ordering_name(cache.ordering_used);
    stats_.analyze_seconds += now_seconds() - t0;
    ++stats_.analyses_reused;
    return {};
  }
  void* symbolic = nullptr;
  const int st =
      umfpack_di_symbolic(n, n, A.outerIndexPtr(), A.innerIndexPtr(), A.valuePtr(), &symbolic, control_, info_);
  stats_.analyze_seconds += now_seconds() - t0;
  ++stats_.analyses;
  if (st != UMFPACK_OK) {
    if (symbolic) umfpack_di_free_symbolic(&symbolic);
    outer_.clear();
    inner_.clear();
    return umfpack_status(st, "symbolic analysis");
  }
  symbolic_ = own_symbolic(symbolic);
  stats_.ordering_used = ordering_name(info_[UMFPACK_ORDERING_USED]);
  cache.outer = outer_;
  cache.inner = inner_;
  cache.control = control;
  cache.symbolic = symbolic_;
  cache.ordering_used = info_[UMFPACK_ORDERING_USED];
  return {};
}

Status SparseLU::factorize(const SparseMatrix& A) {
  if (!same_pattern(A)) {
    Status st = analyze(A);
    if (!st.is_ok()) return st;
  }
  free_numeric();
  values_.assign(A.valuePtr(), A.valuePtr() + A.nonZeros());
  const double t0 = now_seconds();
  const int st =
      umfpack_di_numeric(outer_.data(), inner_.data(), values_.data(), symbolic_.get(), &numeric_, control_, info_);
  stats_.factor_seconds += now_seconds() - t0;
  ++stats_.factorisations;
  stats_.nnz_lu = info_[UMFPACK_LNZ] + info_[UMFPACK_UNZ] - info_[UMFPACK_NROW];
  stats_.flops = info_[UMFPACK_FLOPS];
  stats_.peak_memory_bytes = info_[UMFPACK_PEAK_MEMORY] * info_[UMFPACK_SIZE_OF_UNIT];
  stats_.numeric_bytes = info_[UMFPACK_NUMERIC_SIZE] * info_[UMFPACK_SIZE_OF_UNIT];
  stats_.rcond = info_[UMFPACK_RCOND];
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

Status SparseLU::solve(const Vector& b, Vector& x, bool transpose, int refinement_steps) {
  if (!numeric_) throw std::logic_error("SparseLU::solve before a successful factorize");
  if (b.size() != stats_.n) throw std::invalid_argument("SparseLU::solve: size mismatch");
  x.resize(b.size());
  const double t0 = now_seconds();
  double control[UMFPACK_CONTROL];
  std::copy(control_, control_ + UMFPACK_CONTROL, control);
  if (refinement_steps >= 0) control[UMFPACK_IRSTEP] = refinement_steps;
  const int st = umfpack_di_solve(transpose ? UMFPACK_At : UMFPACK_A, outer_.data(), inner_.data(), values_.data(),
                                  x.data(), b.data(), numeric_, control, info_);
  stats_.solve_seconds += now_seconds() - t0;
  ++stats_.solves;
  Status status = umfpack_status(st, "solve");
  if (status.is_ok() && !x.allFinite()) return {StatusCode::NotFinite, "solve: solution is not finite"};
  return status;
}

}  // namespace keller
