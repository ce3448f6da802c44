#include "core/SparseLU.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>

#include "core/BlasThreads.hpp"
#include "core/LUBackend.hpp"
#include "core/UmfpackLU.hpp"
#ifdef KELLER_MUMPS
#include "core/MumpsLU.hpp"
#endif

namespace keller {

const char* to_string(SparseLUOptions::Backend b) {
  switch (b) {
    case SparseLUOptions::Backend::Auto: return "auto";
    case SparseLUOptions::Backend::Umfpack: return "umfpack";
    case SparseLUOptions::Backend::Mumps: return "mumps";
  }
  return "?";
}

const char* to_string(SparseLUOptions::Ordering o) {
  switch (o) {
    case SparseLUOptions::Ordering::Amd: return "amd";
    case SparseLUOptions::Ordering::Metis: return "metis";
    case SparseLUOptions::Ordering::Cholmod: return "cholmod";
    case SparseLUOptions::Ordering::Best: return "best";
  }
  return "?";
}

SparseLUOptions::Backend backend_from_string(const std::string& s) {
  for (auto b : {SparseLUOptions::Backend::Auto, SparseLUOptions::Backend::Umfpack, SparseLUOptions::Backend::Mumps})
    if (s == to_string(b)) return b;
  throw std::invalid_argument("unknown linear solver backend '" + s + "' (auto, umfpack, mumps)");
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

bool mumps_available() {
#ifdef KELLER_MUMPS
  return true;
#else
  return false;
#endif
}

namespace {

const char* to_string(SparseLUOptions::Strategy s) {
  switch (s) {
    case SparseLUOptions::Strategy::Auto: return "auto";
    case SparseLUOptions::Strategy::Unsymmetric: return "unsymmetric";
    case SparseLUOptions::Strategy::Symmetric: return "symmetric";
  }
  return "?";
}

// The option set that only UMFPACK has, as its key and value ("" where there is none).
std::string umfpack_only_option(const SparseLUOptions& o) {
  if (o.strategy != SparseLUOptions::Strategy::Auto)
    return fmt::format("linear_solver.strategy = \"{}\"", to_string(o.strategy));
  if (o.ordering == SparseLUOptions::Ordering::Cholmod) return "linear_solver.ordering = \"cholmod\"";
  return "";
}

}  // namespace

SparseLUOptions::Backend resolved_backend(const SparseLUOptions& o) {
  using Backend = SparseLUOptions::Backend;
  const std::string umfpack_only = umfpack_only_option(o);
  switch (o.backend) {
    case Backend::Umfpack: return Backend::Umfpack;
    case Backend::Auto: return mumps_available() && umfpack_only.empty() ? Backend::Mumps : Backend::Umfpack;
    case Backend::Mumps:
      if (!mumps_available())
        throw std::invalid_argument(
            "linear_solver.backend = \"mumps\": this keller is built without MUMPS (Debian: libmumps-seq-dev; "
            "then run cmake again)");
      if (!umfpack_only.empty())
        throw std::invalid_argument(fmt::format(
            "linear_solver.backend = \"mumps\" with {}, an option only UMFPACK has: set linear_solver.backend = "
            "\"umfpack\" (or \"auto\") with it, or drop it",
            umfpack_only));
      return Backend::Mumps;
  }
  return Backend::Umfpack;
}

void declare_linear_solver_keys(SceneSchema& s) {
  s.section("linear_solver", "sparse LU: UMFPACK or MUMPS");
  // "mumps" is a choice in every build, so that a scene that asks for it in a build without MUMPS
  // learns why it cannot have it (sparse_lu_options_from) rather than that the value is unknown
  s.string("linear_solver.backend", "auto",
           "sparse direct solver: umfpack, mumps (only in builds with MUMPS, Debian's libmumps-seq-dev), auto (MUMPS "
           "where built with it, 2.5-4x faster factorisations of the flow problems; UMFPACK with an option only it "
           "has: strategy other than auto, ordering cholmod)",
           {"auto", "umfpack", "mumps"});
  s.string("linear_solver.ordering", "amd",
           "fill-reducing ordering: amd, metis (nested dissection; with MUMPS keller gives it METIS's, and in a build "
           "without METIS MUMPS falls back to SCOTCH, which the run's LU line names), cholmod (UMFPACK only), best "
           "(UMFPACK: the least fill of AMD/COLAMD, METIS, NESDIS; MUMPS: the fewest flops of METIS where built with "
           "it, PORD, AMD)",
           {"amd", "metis", "cholmod", "best"});
  s.string("linear_solver.scaling", "sum",
           "scaling before factorisation: none, sum (UMFPACK: rows by their sums; MUMPS: its automatic row and "
           "column scaling), max (by the largest entries: UMFPACK rows, MUMPS rows and columns)",
           {"none", "sum", "max"});
  s.string("linear_solver.strategy", "auto",
           "UMFPACK's strategy: unsymmetric (column ordering, row pivoting), symmetric (ordering of A + A^T, "
           "diagonal pivots preferred), auto (UMFPACK chooses from the pattern); MUMPS has only auto",
           {"auto", "unsymmetric", "symmetric"});
  s.real("linear_solver.pivot_tolerance", 0.1, "threshold partial pivoting tolerance", Range::between(0.0, 1.0));
  s.integer("linear_solver.refinement_steps", 2,
            "iterative refinement steps per solve at most (each costs about two solves)", Range::at_least(0));
}

SparseLUOptions sparse_lu_options_from(const Scene& scene) {
  SparseLUOptions o;
  o.backend = backend_from_string(scene.string("linear_solver.backend"));
  o.ordering = ordering_from_string(scene.string("linear_solver.ordering"));
  const std::string sc = scene.string("linear_solver.scaling");
  o.scaling = sc == "none" ? SparseLUOptions::Scaling::None
                           : (sc == "max" ? SparseLUOptions::Scaling::Max : SparseLUOptions::Scaling::Sum);
  o.strategy = strategy_from_string(scene.string("linear_solver.strategy"));
  o.pivot_tolerance = scene.real("linear_solver.pivot_tolerance");
  o.refinement_steps = static_cast<int>(scene.integer("linear_solver.refinement_steps"));
  try {
    resolved_backend(o);
  } catch (const std::invalid_argument& e) {
    throw scene.error("linear_solver.backend", e.what());
  }
  return o;
}

namespace {

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::unique_ptr<LUBackend> make_backend(const SparseLUOptions& options) {
#ifdef KELLER_MUMPS
  if (resolved_backend(options) == SparseLUOptions::Backend::Mumps) return make_mumps_lu(options);
#else
  resolved_backend(options);  // throws where MUMPS is asked for
#endif
  return make_umfpack_lu(options);
}

}  // namespace

SparseLU::SparseLU(SparseLUOptions options) : options_(options), backend_(make_backend(options_)) {
  backend_->report(stats_);
}

SparseLU::~SparseLU() = default;

bool SparseLU::factorized() const { return backend_->factorized(); }

bool SparseLU::same_pattern(const SparseMatrix& A) const {
  if (!analysed_ || A.cols() + 1 != static_cast<long>(outer_.size()) ||
      A.nonZeros() != static_cast<long>(inner_.size()))
    return false;
  return std::equal(outer_.begin(), outer_.end(), A.outerIndexPtr()) &&
         std::equal(inner_.begin(), inner_.end(), A.innerIndexPtr());
}

Status SparseLU::analyze(const SparseMatrix& A) {
  if (!A.isCompressed()) throw std::invalid_argument("SparseLU: matrix must be compressed");
  if (A.rows() != A.cols()) throw std::invalid_argument("SparseLU: matrix must be square");
  analysed_ = false;
  const double t0 = now_seconds();
  const int n = static_cast<int>(A.rows());
  outer_.assign(A.outerIndexPtr(), A.outerIndexPtr() + n + 1);
  inner_.assign(A.innerIndexPtr(), A.innerIndexPtr() + A.nonZeros());
  stats_.n = n;
  stats_.nnz_matrix = A.nonZeros();
  bool reused = false;
  const Status st = backend_->analyze({n, outer_.data(), inner_.data(), A.valuePtr()}, reused);
  stats_.analyze_seconds += now_seconds() - t0;
  ++(reused ? stats_.analyses_reused : stats_.analyses);
  if (!st.is_ok()) {
    outer_.clear();
    inner_.clear();
    return st;
  }
  analysed_ = true;
  backend_->report(stats_);
  return {};
}

Status SparseLU::factorize(const SparseMatrix& A) {
  if (!same_pattern(A)) {
    Status st = analyze(A);
    if (!st.is_ok()) return st;
  }
  values_.assign(A.valuePtr(), A.valuePtr() + A.nonZeros());
  // one BLAS thread for a small matrix (core/BlasThreads.hpp), at every factorisation: another
  // SparseLU of another size may have set it since
  if (blas_thread_policy()) use_blas_threads_for(stats_.n);
  const double t0 = now_seconds();
  const Status status = backend_->factorize({stats_.n, outer_.data(), inner_.data(), values_.data()});
  stats_.factor_seconds += now_seconds() - t0;
  ++stats_.factorisations;
  backend_->report(stats_);
  backend_->determinant(det_sign_, log_abs_det_);
  return status;
}

Status SparseLU::solve(const Vector& b, Vector& x, bool transpose, int refinement_steps) {
  if (!factorized()) throw std::logic_error("SparseLU::solve before a successful factorize");
  if (b.size() != stats_.n) throw std::invalid_argument("SparseLU::solve: size mismatch");
  x.resize(b.size());
  const double t0 = now_seconds();
  const Status status =
      backend_->solve({stats_.n, outer_.data(), inner_.data(), values_.data()}, b.data(), x.data(), transpose,
                      refinement_steps >= 0 ? refinement_steps : options_.refinement_steps);
  stats_.solve_seconds += now_seconds() - t0;
  ++stats_.solves;
  if (status.is_ok() && !x.allFinite()) return {StatusCode::NotFinite, "solve: solution is not finite"};
  return status;
}

Status SparseLU::solve_columns(const Eigen::MatrixXd& b, Eigen::MatrixXd& x, bool transpose) {
  if (!factorized()) throw std::logic_error("SparseLU::solve_columns before a successful factorize");
  if (b.rows() != stats_.n) throw std::invalid_argument("SparseLU::solve_columns: size mismatch");
  x.resize(b.rows(), b.cols());
  if (b.cols() == 0) return {};
  const double t0 = now_seconds();
  const Status status = backend_->solve_several({stats_.n, outer_.data(), inner_.data(), values_.data()}, b.data(),
                                                x.data(), static_cast<int>(b.cols()), transpose);
  stats_.solve_seconds += now_seconds() - t0;
  stats_.solves += b.cols();
  if (status.is_ok() && !x.allFinite()) return {StatusCode::NotFinite, "solve: solution is not finite"};
  return status;
}

}  // namespace keller
