#include "core/MumpsLU.hpp"

#include "core/FillOrdering.hpp"

#include <dmumps_c.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <mutex>
#include <new>
#include <vector>

namespace keller {

namespace {

// MUMPS's parameters, named after its user's guide (5.5): JOB values, ICNTL(7) orderings.
// The componentwise backward error at which a refined solve has reached rounding.
constexpr double kRoundingBackwardError = 4 * std::numeric_limits<double>::epsilon();
constexpr int kJobInit = -1, kJobEnd = -2, kJobAnalyse = 1, kJobFactorise = 2, kJobSolve = 3;
constexpr int kUseCommWorld = -987654;  // the Fortran MPI_COMM_WORLD of MUMPS's sequential MPI stub
constexpr int kHostWorks = 1;           // PAR = 1: the (only) process takes part in the work
constexpr int kUnsymmetric = 0;         // SYM = 0: general matrix, LU with threshold pivoting
constexpr int kAmd = 0, kGiven = 1, kAmf = 2, kScotch = 3, kPord = 4, kMetis = 5, kQamd = 6;
// INFO(1) < 0 codes
constexpr int kStructurallySingular = -6, kNumericallySingular = -10;
constexpr int kAllocationFailed = -13;
// INFO(1) codes of a workspace MUMPS sized from its analysis and found too small during the
// factorisation (delayed pivots grow the fronts): -8, -9, -14, -15, -17, -20. The answer the guide
// gives is a larger ICNTL(14), the percentage added to the estimate; it is doubled up to
// kWorkspaceRetries times (20% -> 640%), beyond which the matrix is hopeless for a direct solve.
constexpr int kWorkspaceErrors[] = {-8, -9, -14, -15, -17, -20};
constexpr int kWorkspaceRetries = 5;
// `best`: MUMPS's candidates, after METIS's nested dissection given by keller where it is built
// with METIS (core/FillOrdering). Each must earn its analysis: SCOTCH (the other nested
// dissection MUMPS has, and its fallback for METIS) and AMF were never the fewest flops on the
// matrices measured (M2, M4, W3, square and strip grids; docs/orderings.md), SCOTCH at 1.2 to 6
// times the winner's flops with the slowest analysis, AMF at 1.02 to 1.3 times.
constexpr int kBestCandidates[] = {kPord, kAmd};
// The estimated flops of a candidate whose analysis failed (fewest_flops skips it).
constexpr double kNoFlops = std::numeric_limits<double>::quiet_NaN();
// MUMPS's memory statistics are in millions of bytes.
constexpr double kBytesPerMumpsMb = 1e6;

const char* ordering_name(int used) {
  switch (used) {
    case kAmd: return "amd";
    case kGiven: return "metis";  // keller gives only METIS's nested dissection
    case kAmf: return "amf";
    case kScotch: return "scotch";
    case kPord: return "pord";
    case kMetis: return "metis";
    case kQamd: return "qamd";
    default: return "other";
  }
}

// INFOG entries that count beyond the range of an int are negative, in millions.
double count(int v) { return v >= 0 ? static_cast<double>(v) : -1e6 * static_cast<double>(v); }

int scaling_control(SparseLUOptions::Scaling s) {
  switch (s) {
    case SparseLUOptions::Scaling::None: return 0;
    case SparseLUOptions::Scaling::Sum: return 77;  // MUMPS chooses (row and column, iterative)
    case SparseLUOptions::Scaling::Max: return 4;   // rows and columns by their largest entries
  }
  return 77;
}

// The ordering the last analysis of a pattern chose, for the next instance that analyses the
// same pattern with the same options (MUMPS cannot share an analysis between instances: the next
// one repeats the symbolic phase with this ordering and skips the search of `best`).
struct OrderingCache {
  std::mutex mutex;
  std::vector<int> outer, inner;
  SparseLUOptions::Ordering ordering{};
  SparseLUOptions::Scaling scaling{};
  int chosen = -1;
  std::vector<int> given;  // the order where chosen is kGiven
};

OrderingCache& ordering_cache() {
  static OrderingCache cache;
  return cache;
}

// One MUMPS instance with keller's controls (JOB = -1 on construction, -2 on destruction).
class Instance {
 public:
  explicit Instance(const SparseLUOptions& options) : id_(std::make_unique<DMUMPS_STRUC_C>()) {
    *id_ = DMUMPS_STRUC_C{};
    id_->job = kJobInit;
    id_->par = kHostWorks;
    id_->sym = kUnsymmetric;
    id_->comm_fortran = kUseCommWorld;
    dmumps_c(id_.get());
    if (info(1) < 0) throw std::runtime_error(fmt::format("MUMPS initialisation failed: INFO(1) = {}", info(1)));
    icntl(1) = icntl(2) = icntl(3) = -1;  // no output: failures come back as a Status
    icntl(4) = 0;
    icntl(5) = 0;   // assembled matrix
    icntl(18) = 0;  // centralised on the host
    icntl(8) = scaling_control(options.scaling);
    icntl(33) = 1;  // the determinant with every factorisation (the continuation's branch points and folds)
    cntl(1) = options.pivot_tolerance;
    // refine until the componentwise backward error reaches rounding (MUMPS's default stops at
    // its square root); on the flow matrices one step takes it from 1e-13..1e-11 to 2-3 eps and a
    // second changes nothing, but with eps itself as the goal every refined solve made them all
    cntl(2) = kRoundingBackwardError;
  }
  ~Instance() {
    id_->job = kJobEnd;
    dmumps_c(id_.get());
  }
  Instance(const Instance&) = delete;
  Instance& operator=(const Instance&) = delete;

  DMUMPS_STRUC_C* operator->() { return id_.get(); }
  // Fortran's 1-based names of MUMPS's arrays
  int& icntl(int k) { return id_->icntl[k - 1]; }
  double& cntl(int k) { return id_->cntl[k - 1]; }
  int info(int k) const { return id_->info[k - 1]; }
  int infog(int k) const { return id_->infog[k - 1]; }
  double rinfog(int k) const { return id_->rinfog[k - 1]; }

  Status call(int job, const char* what) {
    id_->job = job;
    dmumps_c(id_.get());
    if (info(1) >= 0) return {};  // > 0: warnings (e.g. refinement stopped by its criterion)
    const std::string codes = fmt::format("MUMPS INFO(1) = {}, INFO(2) = {}", info(1), info(2));
    if (info(1) == kNumericallySingular || info(1) == kStructurallySingular)
      return {StatusCode::SingularMatrix, fmt::format("{}: matrix is singular ({})", what, codes)};
    if (info(1) == kAllocationFailed)
      return {StatusCode::LinearSolverError, fmt::format("{}: out of memory ({})", what, codes)};
    return {StatusCode::LinearSolverError, fmt::format("{}: {}", what, codes)};
  }

 private:
  std::unique_ptr<DMUMPS_STRUC_C> id_;
};

class MumpsLU final : public LUBackend {
 public:
  explicit MumpsLU(const SparseLUOptions& options) : options_(options), id_(std::make_unique<Instance>(options)) {}

  Status analyze(const CscView& A, bool& reused) override {
    factorized_ = false;
    analysed_ = false;
    trials_.clear();
    irn_.resize(static_cast<size_t>(A.nnz()));
    jcn_.resize(static_cast<size_t>(A.nnz()));
    for (int j = 0; j < A.n; ++j)
      for (int k = A.outer[j]; k < A.outer[j + 1]; ++k) {
        irn_[static_cast<size_t>(k)] = A.inner[k] + 1;
        jcn_[static_cast<size_t>(k)] = j + 1;
      }
    // (held through the search of `best`, about 1.6 s on W3: another object analysing the same
    // pattern meanwhile waits and then takes the ordering chosen instead of searching again)
    OrderingCache& cache = ordering_cache();
    std::lock_guard<std::mutex> lock(cache.mutex);
    reused = cache.chosen >= 0 && cache.ordering == options_.ordering && cache.scaling == options_.scaling &&
             std::ssize(cache.outer) == A.n + 1 && std::equal(cache.outer.begin(), cache.outer.end(), A.outer) &&
             std::ssize(cache.inner) == A.nnz() && std::equal(cache.inner.begin(), cache.inner.end(), A.inner);
    Status st;
    if (reused) {
      given_ = cache.given;
      st = analyse_with(*id_, A, cache.chosen);
    } else if (options_.ordering == SparseLUOptions::Ordering::Best) {
      st = analyse_best(A);
    } else if (options_.ordering == SparseLUOptions::Ordering::Metis && nested_dissection_available()) {
      st = order_by_nested_dissection(A);
      if (st.is_ok()) st = analyse_with(*id_, A, kGiven);
    } else {
      // MUMPS's own METIS, where this MUMPS has it; Debian's falls back to SCOTCH (INFOG(7) says)
      st = analyse_with(*id_, A, options_.ordering == SparseLUOptions::Ordering::Metis ? kMetis : kAmd);
    }
    if (!st.is_ok()) return st;
    analysed_ = true;
    cache.outer.assign(A.outer, A.outer + A.n + 1);
    cache.inner.assign(A.inner, A.inner + A.nnz());
    cache.ordering = options_.ordering;
    cache.scaling = options_.scaling;
    cache.chosen = id_->infog(7);
    cache.given = cache.chosen == kGiven ? given_ : std::vector<int>{};
    return {};
  }

  Status factorize(const CscView& A) override {
    factorized_ = false;
    if (!analysed_) return {StatusCode::LinearSolverError, "numeric factorisation: the symbolic analysis failed"};
    Instance& m = *id_;
    m->a = const_cast<double*>(A.values);
    const int workspace = m.icntl(14);
    Status st;
    for (int attempt = 0; attempt <= kWorkspaceRetries; ++attempt) {
      st = provide_workspace(m);
      if (!st.is_ok()) break;
      st = m.call(kJobFactorise, "numeric factorisation");
      if (st.is_ok() ||
          std::find(std::begin(kWorkspaceErrors), std::end(kWorkspaceErrors), m.info(1)) == std::end(kWorkspaceErrors))
        break;
      m.icntl(14) *= 2;
    }
    m.icntl(14) = workspace;
    if (!st.is_ok()) {
      det_sign_ = 0;
      log_abs_det_ = -INFINITY;
      return st;
    }
    factorized_ = true;
    const double mantissa = m.rinfog(12);
    det_sign_ = mantissa > 0 ? 1 : (mantissa < 0 ? -1 : 0);
    log_abs_det_ = mantissa != 0 ? std::log(std::abs(mantissa)) + m.infog(34) * std::log(2.0) : -INFINITY;
    return {};
  }

  Status solve(const CscView& A, const double* b, double* x, bool transpose, int refinement_steps) override {
    std::copy(b, b + A.n, x);
    return solve_in_place(A, x, 1, transpose, refinement_steps);
  }

  Status solve_several(const CscView& A, const double* b, double* x, int count, bool transpose) override {
    std::copy(b, b + static_cast<long>(count) * A.n, x);
    return solve_in_place(A, x, count, transpose, 0);
  }

  bool factorized() const override { return factorized_; }

  void determinant(int& sign, double& log_abs) const override {
    sign = det_sign_;
    log_abs = log_abs_det_;
  }

  void report(SparseLU::Statistics& s) const override {
    s.backend = "mumps";
    if (!analysed_) return;
    const Instance& m = *id_;
    s.ordering_used = ordering_name(m.infog(7));
    s.ordering_trials = trials_;
    s.nnz_lu = count(m.infog(29));
    s.flops = m.rinfog(3);
    s.numeric_bytes = count(m.infog(9)) * sizeof(double) + count(m.infog(10)) * sizeof(int);
    // MUMPS counts its peak in whole MB (0 for a small matrix); it holds the factors at least
    s.peak_memory_bytes = std::max(count(m.infog(22)) * kBytesPerMumpsMb, s.numeric_bytes);
    s.rcond = std::numeric_limits<double>::quiet_NaN();
  }

 private:
  static std::vector<int> one_based(std::vector<int> position) {
    for (int& p : position) ++p;
    return position;
  }

  Status solve_in_place(const CscView& A, double* x, int count, bool transpose, int refinement_steps) {
    Instance& m = *id_;
    m->a = const_cast<double*>(A.values);  // refinement computes residuals with A
    m->rhs = x;
    m->nrhs = count;
    m->lrhs = A.n;
    m.icntl(9) = transpose ? 2 : 1;  // 1: A x = b, otherwise A^T x = b
    m.icntl(10) = refinement_steps;  // > 0: at most this many steps, stopping at cntl(2)
    m.icntl(20) = 0;                 // dense right-hand side
    m.icntl(21) = 0;                 // the solution overwrites it
    Status st = m.call(kJobSolve, "solve");
    m->nrhs = 1;
    return st;
  }

  // MUMPS's main workspace (its fronts and the factors in them) as keller's own buffer (WK_USER),
  // kept from one factorisation to the next: MUMPS otherwise allocates it anew at each one and
  // the kernel hands out (and zeroes) fresh pages for it (bench_cylinder W3: 1.57 s a factorisation
  // with the kept buffer, 1.63-1.66 s without). Sized
  // like MUMPS's own: the analysis's estimate INFO(8) plus ICNTL(14) percent; grown, never
  // shrunk, where a new analysis or a retry wants more.
  Status provide_workspace(Instance& m) {
    const double estimate = count(m.info(8));
    const double wanted = std::ceil(estimate * (1.0 + std::max(m.icntl(14), 0) / 100.0));
    if (!(wanted > 0)) return {};  // (no estimate: MUMPS allocates its own)
    // (in whole millions beyond what LWK_USER, an int, counts in entries)
    const double entries = wanted > std::numeric_limits<int>::max() ? std::ceil(wanted / 1e6) * 1e6 : wanted;
    if (entries > static_cast<double>(workspace_size_)) {
      try {
        workspace_.reset();
        workspace_size_ = 0;
        workspace_ = std::make_unique_for_overwrite<double[]>(static_cast<size_t>(entries));
        workspace_size_ = static_cast<long>(entries);
      } catch (const std::bad_alloc&) {
        return {StatusCode::LinearSolverError,
                fmt::format("numeric factorisation: out of memory for its workspace ({:.0f} MB)", entries * 8e-6)};
      }
    }
    m->wk_user = workspace_.get();
    // LWK_USER: the entries, or minus the millions of them where they do not fit an int
    m->lwk_user = workspace_size_ > std::numeric_limits<int>::max() ? -static_cast<int>(workspace_size_ / 1000000)
                                                                    : static_cast<int>(workspace_size_);
    return {};
  }

  // given_ = METIS's nested dissection of A's pattern.
  Status order_by_nested_dissection(const CscView& A) {
    try {
      given_ = one_based(nested_dissection_order(A.n, A.outer, A.inner));
    } catch (const std::exception& e) {  // METIS's failure, or memory for its graph
      return {StatusCode::LinearSolverError, fmt::format("symbolic analysis: {}", e.what())};
    }
    return {};
  }

  // The symbolic analysis of A by `m` with ICNTL(7) = ordering (kGiven: the order in given_).
  Status analyse_with(Instance& m, const CscView& A, int ordering) {
    m->n = A.n;
    m->nnz = A.nnz();
    m->irn = irn_.data();
    m->jcn = jcn_.data();
    m->a = const_cast<double*>(A.values);  // MUMPS reads it (its interface is not const)
    m->perm_in = ordering == kGiven ? given_.data() : nullptr;
    m.icntl(7) = ordering;
    return m.call(kJobAnalyse, "symbolic analysis");
  }

  // Analyses with each candidate ordering, each in an instance of its own, and keeps the instance
  // of the fewest estimated flops of the factorisation (RINFOG(1), fewest_flops), so the winner
  // needs no second analysis.
  Status analyse_best(const CscView& A) {
    std::vector<int> orderings;
    if (nested_dissection_available()) orderings.push_back(kGiven);
    orderings.insert(orderings.end(), std::begin(kBestCandidates), std::end(kBestCandidates));
    std::unique_ptr<Instance> best;
    std::vector<int> best_given, used;
    Status failure;
    for (int ordering : orderings) {
      std::unique_ptr<Instance> candidate;
      try {
        candidate = std::make_unique<Instance>(options_);
      } catch (const std::exception& e) {
        return {StatusCode::LinearSolverError, fmt::format("symbolic analysis: {}", e.what())};
      }
      Status st = ordering == kGiven ? order_by_nested_dissection(A) : Status{};
      if (st.is_ok()) st = analyse_with(*candidate, A, ordering);
      // (named by the ordering MUMPS used, which a build without one substitutes; one it has
      // tried already is not counted again)
      const int got = st.is_ok() ? candidate->infog(7) : ordering;
      if (std::find(used.begin(), used.end(), got) != used.end()) continue;
      used.push_back(got);
      trials_.push_back({ordering_name(got), st.is_ok() ? candidate->rinfog(1) : kNoFlops});
      if (!st.is_ok()) {
        // a singular matrix says so whichever candidate found it (callers fall back on it)
        if (failure.is_ok() || st.code() == StatusCode::SingularMatrix) failure = st;
        continue;
      }
      if (fewest_flops(trials_) == std::ssize(trials_) - 1) {
        best = std::move(candidate);
        best_given = ordering == kGiven ? given_ : std::vector<int>{};
      }
    }
    if (!best) return failure;  // every candidate failed
    id_ = std::move(best);
    given_ = std::move(best_given);
    (*id_)->perm_in = given_.empty() ? nullptr : given_.data();
    return {};
  }

  SparseLUOptions options_;
  // MUMPS's main workspace (WK_USER), holding the factors; before id_, which is ended (JOB = -2)
  // while it is still there
  std::unique_ptr<double[]> workspace_;
  long workspace_size_ = 0;  // its entries
  std::unique_ptr<Instance> id_;
  std::vector<int> irn_, jcn_;  // 1-based triplets of the analysed pattern
  std::vector<int> given_;      // the given ordering's pivot positions (1-based, MUMPS's PERM_IN)
  std::vector<OrderingTrial> trials_;
  bool analysed_ = false, factorized_ = false;
  int det_sign_ = 0;
  double log_abs_det_ = 0.0;
};

}  // namespace

std::unique_ptr<LUBackend> make_mumps_lu(const SparseLUOptions& options) { return std::make_unique<MumpsLU>(options); }

}  // namespace keller
