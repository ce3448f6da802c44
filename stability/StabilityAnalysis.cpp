#include "stability/StabilityAnalysis.hpp"

#include "stability/SpectrumEdge.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>

namespace keller {

void StabilityOptions::declare(SceneSchema& s) {
  s.section("stability", "linear stability of every point of a branch (keller trace): J phi = sigma B phi");
  s.boolean("stability.enabled", false, "compute eigenvalues along the branch, detect and locate stability changes");
  // (at most 10^4: a column per eigenvalue, and an Arnoldi basis of twice as many vectors)
  s.integer("stability.count", 6, "eigenvalues wanted nearest each shift (at most n - 2 of a problem of n unknowns)",
            Range::between(1, 10'000));
  s.real_list("stability.shifts_re", {0.0}, "real parts of the shifts (eigenvalues nearest each are computed)");
  s.real_list("stability.shifts_im", {0.0},
              "imaginary parts of the shifts (same length as shifts_re; nonzero: complex arithmetic, for Hopf)");
  s.integer("stability.every", 1,
            "analyse every N-th accepted point and the last; a change in between is bracketed by bisection "
            "over the points in between and located",
            Range::at_least(1));
  s.integer("stability.ncv", 0,
            "Arnoldi basis size per shift (0: max(2 count + 1, 20)); larger helps clustered spectra",
            Range::non_negative());
  s.real("stability.arpack_tolerance", 1e-10, "ARPACK's relative accuracy of the Ritz values", Range::positive());
  s.boolean("stability.warm_start", true,
            "start each point's Arnoldi iteration from the eigenvectors of the last analysed point (false: "
            "from a fixed random vector)");
  s.real("stability.residual_tolerance", 1e-8, "largest accepted relative residual of an eigenpair", Range::positive());
  s.real("stability.neutral_tolerance", 1e-8,
         "eigenvalues with |Re sigma| <= this x max(1, |sigma|) are neutral, not counted as unstable",
         Range::non_negative());
}

StabilityOptions StabilityOptions::from_scene(const Scene& sc) {
  StabilityOptions o;
  o.enabled = sc.boolean("stability.enabled");
  o.count = static_cast<int>(sc.integer("stability.count"));
  o.every = static_cast<int>(sc.integer("stability.every"));
  o.residual_tolerance = sc.real("stability.residual_tolerance");
  o.ncv = static_cast<int>(sc.integer("stability.ncv"));
  o.arpack_tolerance = sc.real("stability.arpack_tolerance");
  o.neutral_tolerance = sc.real("stability.neutral_tolerance");
  o.warm_start = sc.boolean("stability.warm_start");
  const auto& re = sc.real_list("stability.shifts_re");
  const auto& im = sc.real_list("stability.shifts_im");
  if (re.empty()) throw sc.error("stability.shifts_re", "needs at least one shift");
  if (im.size() != re.size())
    throw sc.error("stability.shifts_im", fmt::format("has {} entries, shifts_re {}: give one imaginary part per shift",
                                                      im.size(), re.size()));
  o.shifts.clear();
  for (size_t i = 0; i < re.size(); ++i) o.shifts.emplace_back(re[i], im[i]);
  return o;
}

void StabilityOptions::check_problem(const Scene& sc, Problem& problem) const {
  if (const std::string why = time_form_refusal(problem); !why.empty())
    throw sc.error("stability.enabled", why + ", so it has no spectrum to analyse");
  const long n = problem.size();
  if (count > n - 2)
    throw sc.error("stability.count",
                   fmt::format("{} eigenvalues asked for, but a problem of {} unknowns has at most {} to give", count,
                               n, std::max(n - 2, 0L)));
}

StabilityAnalysis::StabilityAnalysis(StabilityOptions options, SparseLUOptions lu)
    : options_(std::move(options)), solver_(lu) {}

bool StabilityAnalysis::uses_j_factorisation() const {
  return std::any_of(options_.shifts.begin(), options_.shifts.end(),
                     [](const std::complex<double>& s) { return s == std::complex<double>(0.0); });
}

bool StabilityAnalysis::widen() {
  bool grew = false;
  for (int& c : counts_) {
    const int next = std::min(cap_, 2 * c);
    grew |= next > c;
    c = next;
  }
  return grew;
}

std::vector<std::string> StabilityAnalysis::column_names() const {
  std::vector<std::string> c;
  for (int i = 1; i <= options_.count; ++i) {
    c.push_back(fmt::format("sigma{}_re", i));
    c.push_back(fmt::format("sigma{}_im", i));
  }
  c.push_back("unstable");
  c.push_back("eig_residual");
  return c;
}

Status StabilityAnalysis::analyse(Problem& problem, const Vector& u, PointAnalysisResult& out, SparseLU* factorised_j) {
  const auto t0 = std::chrono::steady_clock::now();
  struct AddTime {
    double& to;
    std::chrono::steady_clock::time_point t0;
    ~AddTime() { to += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count(); }
  } add{seconds_, t0};
  const int k = options_.count;
  out.columns.assign(2 * k + 2, NAN);
  out.count = -1;
  out.locator = NAN;
  out.critical_imag = 0.0;
  out.critical_re.resize(0);
  out.critical_im.resize(0);
  out.note.clear();
  out.width = 0;
  spectrum_.clear();
  if (J_.size() == 0) J_ = problem.jacobian_pattern();
  Status st = problem.jacobian(u, F_, J_);
  if (st.is_ok()) st = problem.mass_matrix(u, B_);
  if (!st.is_ok()) return st;
  if (B_.nonZeros() == 0 || B_.coeffs().cwiseAbs().maxCoeff() == 0.0) {
    // no dynamics: no finite eigenvalue, nothing can become unstable
    out.count = 0;
    out.locator = INFINITY;
    out.columns[2 * k] = 0;
    return {};
  }
  std::vector<EigenPair> all;
  Status worst;
  previous_.resize(options_.shifts.size());
  const int n = static_cast<int>(u.size());
  counts_.resize(options_.shifts.size(), std::min(k, n - 2));
  const int cap = cap_ = std::min(n - 2, std::max(kGrowthCap * k, kGrowthFloor));
  // the whole set again, wider, where an unstable mode of the last analysis is not in it
  for (;;) {
    all.clear();
    worst = Status{};
    out.width = 0;
    for (size_t shift = 0; shift < options_.shifts.size(); ++shift) {
      const auto& s = options_.shifts[shift];
      EigenOptions eo;
      if (options_.warm_start) eo.start = previous_[shift];
      eo.shift = s;
      eo.vectors = true;
      eo.residual_tolerance = options_.residual_tolerance;
      eo.tolerance = options_.arpack_tolerance;
      EigenResult r;
      // the set grows (and stays grown along the branch) until its unstable eigenvalues lie inside it
      for (int& count = counts_[shift];;) {
        eo.count = count;
        // (a basis the scene sets is kept for the count it asked for, widened for a grown one)
        if (options_.ncv > 0)
          eo.ncv = std::min(count > std::min(k, n - 2) ? std::max(options_.ncv, 2 * count + 1) : options_.ncv, n);
        r = EigenResult{};
        st = solver_.solve(J_, B_, eo, r, factorised_j);  // used at s = 0 only
        factorisations_ += r.factorisations;
        solves_ += r.solves;
        std::vector<std::complex<double>> values;
        for (const EigenPair& p : r.pairs) values.push_back(p.value);
        const int next = st.is_ok() ? count_to_separate(values, s, count, cap) : count;
        if (next == count) {
          if (st.is_ok() && !spectrum_edge_separated(values, s, count))
            out.note = fmt::format(
                "the eigenvalue farthest from the shift {} of the {} computed is unstable: the count of unstable "
                "eigenvalues may miss some beyond it (the set is at its cap of 8 stability.count, 32 or n - 2)",
                fmt::format("{}{:+}i", s.real(), s.imag()), count);
          break;
        }
        count = next;
        if (options_.warm_start)
          for (const EigenPair& p : r.pairs)
            if (p.accurate && p.vector.size()) eo.start.push_back(p.vector);
      }
      // A shift almost at an eigenvalue (SpectrumEdge: needs_moved_shift): once more from a shift
      // moved left, kept where it is better (ok, or with pairs where J - sB was singular, or more pairs)
      const bool inaccurate =
          std::any_of(r.pairs.begin(), r.pairs.end(), [](const EigenPair& p) { return !p.accurate; });
      const int n_found = static_cast<int>(r.pairs.size());
      if (needs_moved_shift(st.is_ok(), inaccurate, st.code() == StatusCode::SingularMatrix, n_found, eo.count)) {
        std::vector<std::complex<double>> values;
        for (const auto& p : r.pairs) values.push_back(p.value);
        eo.shift = s - shift_move(values, s, last_spread_);
        EigenResult r2;
        const Status st2 = solver_.solve(J_, B_, eo, r2);
        factorisations_ += r2.factorisations;
        solves_ += r2.solves;
        const bool better = st.is_ok() ? st2.is_ok() && static_cast<int>(r2.pairs.size()) > n_found
                                       : st2.is_ok() || (!r2.pairs.empty() && st2.code() != StatusCode::SingularMatrix);
        if (better) {
          st = st2;
          r = std::move(r2);
        }
      }
      out.width += counts_[shift];
      if (!st.is_ok() && r.pairs.empty()) return st;
      if (!st.is_ok()) worst = st;
      previous_[shift].clear();
      for (const auto& p : r.pairs)
        if (p.accurate && p.vector.size()) previous_[shift].push_back(p.vector);
      // an eigenvalue found by two shifts once; a multiple one as often as one shift found it
      std::vector<std::complex<double>> merged, found;
      for (const EigenPair& p : all) merged.push_back(p.value);
      for (const EigenPair& p : r.pairs) found.push_back(p.value);
      for (size_t i : values_to_merge(merged, found)) all.push_back(std::move(r.pairs[i]));
    }
    std::vector<Eigen::VectorXcd> now;
    for (const EigenPair& p : all)
      if (p.vector.size()) now.push_back(p.vector);
    if (!unstable_mode_lost(previous_unstable_, now) || !widen()) break;
  }
  previous_unstable_.clear();
  for (const EigenPair& p : all)
    if (p.value.real() < 0 && p.vector.size()) previous_unstable_.push_back(p.vector);
  order_spectrum(all);
  // Two counts: the engine brackets a change by the strict sign of Re sigma (every trial point
  // falls on one side); the table reports eigenvalues on the axis to within neutral_tolerance as
  // neutral, so that the count at a located bifurcation point, whose critical eigenvalue is zero
  // to rounding, does not hang on the last bit of Re sigma.
  int unstable = 0, unstable_reported = 0;
  double max_residual = 0.0;
  for (const auto& p : all) {
    if (p.value.real() < 0) ++unstable;
    if (p.value.real() < -options_.neutral_tolerance * std::max(1.0, std::abs(p.value))) ++unstable_reported;
    max_residual = std::max(max_residual, p.residual);
  }
  for (int i = 0; i < k && i < static_cast<int>(all.size()); ++i) {
    out.columns[2 * i] = all[static_cast<size_t>(i)].value.real();
    out.columns[2 * i + 1] = all[static_cast<size_t>(i)].value.imag();
  }
  out.columns[2 * k] = unstable_reported;
  out.columns[2 * k + 1] = max_residual;
  if (!worst.is_ok() && max_residual > options_.residual_tolerance) return worst;
  out.count = unstable;
  if (!all.empty()) {
    auto critical = std::min_element(all.begin(), all.end(), [](const EigenPair& a, const EigenPair& b) {
      return std::abs(a.value.real()) < std::abs(b.value.real());
    });
    // of a complex pair, the member with Im sigma > 0 (not whichever rounding put nearer the axis)
    if (critical->value.imag() < 0) {
      const auto conjugate = std::find_if(all.begin(), all.end(), [&](const EigenPair& p) {
        return std::abs(p.value - std::conj(critical->value)) <= 1e-8 * (1.0 + std::abs(p.value));
      });
      if (conjugate != all.end()) critical = conjugate;
    }
    out.locator = critical->value.real();
    out.critical_imag = critical->value.imag();
    out.critical_multiplicity = static_cast<int>(std::count_if(all.begin(), all.end(), [&](const EigenPair& p) {
      return std::abs(p.value - critical->value) <= 1e-6 * (1.0 + std::abs(critical->value));
    }));
    if (critical->vector.size()) {
      out.critical_re = critical->vector.real();
      out.critical_im = critical->vector.imag();
    }
  } else {
    out.locator = INFINITY;
  }
  last_spread_ = 0.0;
  for (const EigenPair& p : all) last_spread_ = std::max(last_spread_, std::abs(p.value - options_.shifts.front()));
  spectrum_ = std::move(all);
  return {};
}

}  // namespace keller
