#include "continuation/orbits/ShootingMap.hpp"

#include <fmt/format.h>

#include <Eigen/LU>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include "continuation/time/TimeIntegrator.hpp"
#include "continuation/time/TimeStepControl.hpp"
#include "core/Gmres.hpp"

namespace keller {

namespace {
using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Preconditioned: A x by central differences of the solve's residual at a step 1e-5 of the state's
// size over |x|, and GMRES to the pass's tolerance (kTightPass: 1e-12 of the right-hand side). The
// step balances the differences' truncation (step^2) against the rounding of residuals whose terms
// cancel (rounding / step): passes on the Brusselator erred by 1.4e-8 at worst against 1.2e-7 at
// 1e-6 (ShootingMapTest), and on docs/periodic_orbits.md's FSI problem the rounding at 1e-6 made
// the multipliers near 1 depend on Arnoldi's start by up to 3e-4, against 1.5e-5 at 1e-5.
constexpr double kJacobianDifferenceStep = 1e-5;
constexpr int kInnerIterations = 40;

bool same_values(const SparseMatrix& a, const SparseMatrix& b) {
  if (a.nonZeros() != b.nonZeros() || a.rows() != b.rows() || a.cols() != b.cols()) return false;
  return std::equal(a.valuePtr(), a.valuePtr() + a.nonZeros(), b.valuePtr()) &&
         std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), b.innerIndexPtr());
}
}  // namespace

// One implicit solve of the period (a BDF2 step or an SDIRK4 stage): B(U) R + F(U) = 0 with
// R = coefficient U + (the rest); its matrix A = coefficient B(U) + J(U) and, where kept, A's
// factorisation.
struct ShootingMap::Solve {
  int step = 0;               // 0-based index of its step
  int stage = 0;              // SDIRK4: 0-based stage; BDF2: 0
  double coefficient = 0.0;   // dR/dU: c0 / h (BDF2), 1 / (h gamma) (SDIRK4)
  std::array<double, 3> c{};  // BDF2's coefficients
  Vector U;                   // the state solved for
  Vector rate;                // R at U
  Vector dF_lambda;           // F_lambda(U), once asked for (empty: not yet, or not kept)
  SparseMatrix B;             // B(U) (only where B varies)
  SparseMatrix A;
  std::optional<Eigen::PartialPivLU<Eigen::MatrixXd>> dense;
  std::unique_ptr<SparseLU> sparse;
  int anchor = -1;  // Preconditioned: the anchor whose factorisation preconditions it
};

// Preconditioned: a solve whose matrix is factorised, kept where the memory budget allows.
struct ShootingMap::Anchor {
  int solve = 0;
  std::unique_ptr<SparseLU> lu;
};

namespace {
class StageRecorder final : public TimeObserver {
 public:
  StageRecorder(std::vector<Vector>& states, std::vector<std::vector<Vector>>& stages)
      : states_(states), stages_(stages) {}
  void on_step(const TimePoint& p) override {
    states_.push_back(p.u);
    if (p.step > 0) stages_.push_back(p.stages);
  }

 private:
  std::vector<Vector>& states_;
  std::vector<std::vector<Vector>>& stages_;
};
}  // namespace

ShootingMap::ShootingMap(Problem& problem, int parameter, ShootingOptions options)
    : problem_(problem), parameter_(parameter), options_(std::move(options)) {
  options_.lu.backend = ShootingOptions::backend_for(options_.lu.backend, problem_.size());
  SparseMatrix B;
  (void)problem_.mass_matrix(problem_.initial_guess(), B);  // throws NoTimeForm for a problem without one
}

ShootingMap::~ShootingMap() = default;

const SparseMatrix& ShootingMap::mass(const Solve& s) const { return mass_varies_ ? s.B : mass_; }

Status ShootingMap::assemble(Solve& s) {
  Vector F;
  SparseMatrix J;
  Status st = problem_.jacobian(s.U, F, J);
  if (st.is_ok() && mass_varies_) st = problem_.mass_matrix(s.U, s.B);
  if (!st.is_ok()) return st;
  s.A = J + s.coefficient * mass(s);
  return {};
}

Status ShootingMap::measure_factorisation() {
  if (factorisation_bytes_ >= 0.0) return {};  // once, on the first solve's matrix
  Solve& s = solves_.front();
  Status st = assemble(s);
  if (!st.is_ok()) return st;
  SparseLU lu(options_.lu);
  st = lu.factorize(s.A);
  ++counts_.factorisations;
  if (!st.is_ok()) return st;
  factorisation_bytes_ = lu.statistics().numeric_bytes;
  return {};
}

Status ShootingMap::integrate(const Vector& u0, double period, const OrbitGrid& grid) {
  const bool sdirk = grid.method == TimeOptions::Method::Sdirk4;
  if (grid.steps() < (sdirk ? 1 : 3)) throw std::invalid_argument("shooting: the grid has too few steps");
  if (!(period > 0.0)) throw std::invalid_argument("shooting: the period must be > 0");
  const auto t0 = Clock::now();
  period_ = period;
  method_ = grid.method;
  states_.clear();
  solves_.clear();
  steps_.clear();
  stored_bytes_ = 0.0;
  std::vector<double> times(grid.fractions.size());
  for (size_t k = 0; k < times.size(); ++k) times[k] = grid.fractions[k] * period;
  TimeOptions time;
  time.method = grid.method;
  time.t_end = period;
  TimeIntegrator integrator(problem_, time, options_.newton, ShootingOptions::chord_lu(options_.lu));
  std::vector<std::vector<Vector>> stages;
  StageRecorder recorder(states_, stages);
  const TimeResult r = integrator.run_on_grid(u0, 0.0, times, recorder, {}, sdirk);
  counts_.steps += r.steps;
  counts_.newton_iterations += r.newton_iterations;
  counts_.factorisations += r.factorisations;
  if (r.code != TimeStop::End) {
    counts_.forward_seconds += since(t0);
    return {StatusCode::NotConverged, "shooting: " + r.reason};
  }

  const int m = grid.steps();
  Status st = problem_.mass_matrix(states_[0], mass_);
  if (!st.is_ok()) return st;
  {
    SparseMatrix Bmid;
    st = problem_.mass_matrix(states_[static_cast<size_t>(m / 2 + 1)], Bmid);
    if (!st.is_ok()) return st;
    mass_varies_ = !same_values(mass_, Bmid);
  }
  const SdirkTableau& t = sdirk4();
  double h_prev = 0.0;
  for (int k = 0; k < m; ++k) {
    const double h = times[static_cast<size_t>(k)] - (k > 0 ? times[static_cast<size_t>(k - 1)] : 0.0);
    steps_.push_back(h);
    const auto K = static_cast<size_t>(k);
    if (!sdirk) {
      Solve s;
      s.step = k;
      s.c = bdf_coefficients(k < 2 ? 1 : 2, h, k > 0 ? h_prev : h);
      s.coefficient = s.c[0] / h;
      s.U = states_[K + 1];
      s.rate = (s.c[0] * states_[K + 1] + s.c[1] * states_[K]) / h;
      if (s.c[2] != 0.0) s.rate += (s.c[2] / h) * states_[K - 1];
      solves_.push_back(std::move(s));
    } else {
      std::array<Vector, SdirkTableau::kStages> rates;
      for (int i = 0; i < SdirkTableau::kStages; ++i) {
        Solve s;
        s.step = k;
        s.stage = i;
        s.coefficient = 1.0 / (h * t.gamma);
        s.U = stages[K][static_cast<size_t>(i)];
        Vector sum = states_[K];
        for (int j = 0; j < i; ++j) sum += (h * t.a[i][j]) * rates[static_cast<size_t>(j)];
        s.rate = (s.U - sum) * s.coefficient;
        rates[static_cast<size_t>(i)] = s.rate;
        solves_.push_back(std::move(s));
      }
    }
    h_prev = h;
  }
  using L = ShootingOptions::Linearisation;
  const int n = problem_.size();
  const long count = static_cast<long>(solves_.size());
  L how =
      ShootingOptions::linearisation_for(options_.linearisation, n, mass_varies_, -1.0, count, options_.memory_budget);
  if (how == L::Factorised && n > kDenseSize && options_.linearisation == L::Auto) {
    if (!(st = measure_factorisation()).is_ok()) return st;
    how = ShootingOptions::linearisation_for(L::Auto, n, mass_varies_, factorisation_bytes_, count,
                                             options_.memory_budget);
  }
  preconditioned_ = how == L::Preconditioned;
  std::vector<Anchor> kept = reusable_anchors(u0, period, grid);
  auto next_kept = kept.begin();
  shared_anchor_ = -1;
  for (size_t k = 0; k < solves_.size(); ++k) {
    Solve& s = solves_[k];
    if (!preconditioned_) {
      st = assemble(s);
      if (!st.is_ok()) return st;
      continue;
    }
    const bool renew =
        anchors_.empty() ||
        !keeps_factorisation(s.coefficient, solves_[static_cast<size_t>(anchors_.back().solve)].coefficient) ||
        static_cast<int>(k) - anchors_.back().solve >= ShootingOptions::kAnchorSpan;
    if (renew) {
      anchors_.push_back({static_cast<int>(k), nullptr});
      while (next_kept != kept.end() && next_kept->solve < static_cast<int>(k)) ++next_kept;
      if (next_kept != kept.end() && next_kept->solve == static_cast<int>(k) && next_kept->lu) {
        stored_bytes_ += next_kept->lu->statistics().numeric_bytes;
        anchors_.back().lu = std::move(next_kept->lu);
      }
    }
    s.anchor = static_cast<int>(anchors_.size()) - 1;
  }
  counts_.forward_seconds += since(t0);
  return {};
}

std::vector<ShootingMap::Anchor> ShootingMap::reusable_anchors(const Vector& u0, double period, const OrbitGrid& grid) {
  std::vector<Anchor> old = std::move(anchors_);
  anchors_.clear();
  std::vector<double> scalars{period};
  const ParameterSet& p = problem_.parameters();
  for (int i = 0; i < p.size(); ++i) scalars.push_back(p.value(i));
  AnchorOrigin& o = anchor_origin_;
  if (preconditioned_ && !old.empty() && o.method == grid.method && o.fractions == grid.fractions &&
      ShootingOptions::keeps_anchors(ShootingOptions::anchor_drift(o.u0, u0, o.scalars, scalars)))
    return old;
  o = {u0, std::move(scalars), grid.fractions, grid.method};
  return {};
}

Status ShootingMap::solve_residual(const Solve& s, const Vector& U, Vector& G) {
  // R(U) = rate + coefficient (U - U_s): the rate is affine in U with slope coefficient
  return time_dependent_residual(problem_, U, s.rate + s.coefficient * (U - s.U), G);
}

Status ShootingMap::apply_mass(const Solve& s, const Vector& x, Vector& out) {
  if (!preconditioned_) {
    out = mass(s) * x;
    return {};
  }
  return problem_.time_residual(s.U, x, out);
}

Status ShootingMap::anchor_lu(int a, SparseLU*& lu) {
  Anchor& anchor = anchors_[static_cast<size_t>(a)];
  if (anchor.lu) {
    lu = anchor.lu.get();
    return {};
  }
  if (shared_anchor_ == a) {
    lu = shared_lu_.get();
    return {};
  }
  Solve& s = solves_[static_cast<size_t>(anchor.solve)];
  Status st = assemble(s);
  if (!st.is_ok()) return st;
  const bool keep = stored_bytes_ < options_.memory_budget;
  std::unique_ptr<SparseLU>& target = keep ? anchor.lu : shared_lu_;
  if (!target) target = std::make_unique<SparseLU>(options_.lu);
  st = target->factorize(s.A);
  ++counts_.factorisations;
  s.A = SparseMatrix();
  s.B = SparseMatrix();
  if (!st.is_ok()) {
    if (keep) anchor.lu.reset();
    shared_anchor_ = -1;
    return st;
  }
  if (keep)
    stored_bytes_ += target->statistics().numeric_bytes;
  else
    shared_anchor_ = a;
  lu = target.get();
  return {};
}

double ShootingMap::step_error(double rtol, double atol) const {
  if (solves_.empty()) throw std::logic_error("shooting: step_error before integrate");
  if (method_ != TimeOptions::Method::Sdirk4) return std::numeric_limits<double>::infinity();
  const std::vector<char> counted = TimeIntegrator::differential_unknowns(mass_);
  const SdirkTableau& t = sdirk4();
  double worst = 0.0;
  for (size_t k = 0; k < steps_.size(); ++k) {
    std::array<const Vector*, SdirkTableau::kStages> K;
    for (size_t j = 0; j < K.size(); ++j) K[j] = &solves_[k * SdirkTableau::kStages + j].rate;
    const Vector e = t.embedded_error(steps_[k], K);
    worst = std::max(worst, TimeIntegrator::error_norm(e, states_[k], states_[k + 1], rtol, atol, counted));
  }
  return worst;
}

Vector ShootingMap::end_rate() const {
  if (solves_.empty()) throw std::logic_error("shooting: end_rate before integrate");
  return solves_.back().rate;
}

Status ShootingMap::factorise(Solve& s) {
  const int n = problem_.size();
  if (n <= kDenseSize) {
    s.dense.emplace(Eigen::MatrixXd(s.A));
    ++counts_.factorisations;
    return {};
  }
  const bool keep = stored_bytes_ < options_.memory_budget;
  SparseLU* lu = nullptr;
  if (keep) {
    s.sparse = std::make_unique<SparseLU>(options_.lu);
    lu = s.sparse.get();
  } else {
    if (!shared_lu_) shared_lu_ = std::make_unique<SparseLU>(options_.lu);
    lu = shared_lu_.get();
  }
  Status st = lu->factorize(s.A);
  ++counts_.factorisations;
  if (!st.is_ok()) {
    s.sparse.reset();
    return st;
  }
  if (keep) stored_bytes_ += lu->statistics().numeric_bytes;
  return {};
}

Status ShootingMap::solve_linearised(Solve& s, const Vector& rhs, Vector& v, double tolerance, const Vector& guess) {
  // the preconditioner: an anchor's factorisation (Preconditioned), else the solve's own matrix
  // without the B' term, factorised now where it is not kept
  SparseLU* lu = nullptr;
  if (preconditioned_) {
    Status st = anchor_lu(s.anchor, lu);
    if (!st.is_ok()) return st;
  } else {
    if (!s.dense && !s.sparse) {
      Status st = factorise(s);
      if (!st.is_ok()) return st;
    }
    lu = s.sparse ? s.sparse.get() : shared_lu_.get();
  }
  Status failed;
  auto P = [&](const Vector& x) -> Vector {
    Vector y;
    if (s.dense) return s.dense->solve(x);
    Status e = lu->solve(x, y, false, preconditioned_ ? 0 : -1);
    if (!e.is_ok()) {
      failed = e;
      return Vector::Zero(x.size());
    }
    return y;
  };
  if (!preconditioned_ && !mass_varies_) {  // the factorisation is A's: one solve
    v = P(rhs);
    return failed;
  }
  // GMRES with A x by central differences of the solve's residual (the B'[x] R term with it)
  Vector Gp, Gm;
  const double scale = std::max(s.U.lpNorm<Eigen::Infinity>(), 1.0);
  auto A = [&](const Vector& x) -> Vector {
    const double xn = x.lpNorm<Eigen::Infinity>();
    if (xn == 0.0) return Vector::Zero(x.size());
    const double eps = kJacobianDifferenceStep * scale / xn;
    Status e = solve_residual(s, s.U + eps * x, Gp);
    if (e.is_ok()) e = solve_residual(s, s.U - eps * x, Gm);
    if (!e.is_ok()) {
      failed = e;
      return Vector::Zero(x.size());
    }
    return (Gp - Gm) / (2.0 * eps);
  };
  // from the guess where it leaves less to solve for: GMRES on the rest, to the same residual
  const double target = tolerance * rhs.norm();
  Vector rest;
  bool guessed = false;
  if (guess.size() == rhs.size()) {
    rest = rhs - A(guess);
    ++counts_.inner_iterations;
    if (!failed.is_ok()) return failed;
    guessed = rest.norm() < rhs.norm();
    if (guessed && rest.norm() <= target) {
      v = guess;
      return {};
    }
  }
  const Vector& b = guessed ? rest : rhs;
  const GmresResult g = gmres(A, P, b, v, target / b.norm(), kInnerIterations);
  if (guessed) v += guess;
  counts_.inner_iterations += g.iterations;
  if (!failed.is_ok()) return failed;
  if (!g.converged)
    return {StatusCode::NotConverged,
            fmt::format("shooting: a linearised solve took more than {} GMRES iterations", kInnerIterations)};
  return {};
}

namespace {
// A solve's first guess: the rate's change as the last solve's, dU = shift + dR / coefficient
// (empty where there was no last solve)
Vector rate_guess(const Vector& shift, const Vector& previous, double coefficient) {
  if (previous.size() != shift.size()) return {};
  return shift + previous / coefficient;
}
}  // namespace

Status ShootingMap::parameter_term(Solve& s, double dlambda, Vector& rhs) {
  if (dlambda == 0.0) return {};
  if (s.dF_lambda.size() == 0) {
    // kept for the passes to come while the memory budget allows: every product of a Newton step's
    // GMRES carries a lambda component
    Vector dF;
    Status st = problem_.parameter_derivative(parameter_, s.U, dF);
    if (!st.is_ok()) return st;
    const double bytes = static_cast<double>(dF.size()) * sizeof(double);
    if (stored_bytes_ + bytes > options_.memory_budget) {
      rhs -= dlambda * dF;
      return {};
    }
    stored_bytes_ += bytes;
    s.dF_lambda = std::move(dF);
  }
  rhs -= dlambda * s.dF_lambda;
  return {};
}

Status ShootingMap::linearised(const Vector& v0, double dT, double dlambda, Vector& out, double tolerance) {
  if (solves_.empty()) throw std::logic_error("shooting: linearised before integrate");
  if (dlambda != 0.0 && parameter_ < 0) throw std::logic_error("shooting: no parameter to differentiate in");
  tolerance = std::clamp(tolerance, kTightPass, 1e-2);
  const auto t0 = Clock::now();
  const double s_T = dT / period_;  // dh / h of every step
  Vector rhs, v;
  Status st;
  if (method_ == TimeOptions::Method::Bdf2) {
    Vector before = v0, last = v0;  // v_(k-2), v_(k-1)
    Vector dR;                      // the last step's dR (empty: none yet)
    for (Solve& s : solves_) {
      const double h = steps_[static_cast<size_t>(s.step)];
      Vector w = s.c[1] * last;
      if (s.c[2] != 0.0) w += s.c[2] * before;
      // dR = (c0 dU + w) / h - s_T R = coefficient (dU - shift); B dR + J dU + ... = 0
      const Vector shift = (s_T * s.rate - w / h) / s.coefficient;
      if (!(st = apply_mass(s, s.coefficient * shift, rhs)).is_ok() ||
          !(st = parameter_term(s, dlambda, rhs)).is_ok() ||
          !(st = solve_linearised(s, rhs, v, tolerance, rate_guess(shift, dR, s.coefficient))).is_ok())
        return st;
      dR = s.coefficient * (v - shift);
      before = std::move(last);
      last = v;
    }
    out = std::move(last);
  } else {
    const SdirkTableau& t = sdirk4();
    Vector un = v0;  // du_n
    std::array<Vector, SdirkTableau::kStages> dK;
    Vector dK_last;  // the last step's last stage's (empty: none yet)
    for (size_t first = 0; first < solves_.size(); first += SdirkTableau::kStages) {
      const double h = steps_[static_cast<size_t>(solves_[first].step)];
      const Vector& u_n = states_[static_cast<size_t>(solves_[first].step)];
      for (int i = 0; i < SdirkTableau::kStages; ++i) {
        Solve& s = solves_[first + static_cast<size_t>(i)];
        // h gamma dK_i = dU_i - w_i - s_T (U_i - u_n), w_i = du_n + h sum_(j<i) a_ij dK_j
        Vector w = un;
        for (int j = 0; j < i; ++j) w += (h * t.a[i][j]) * dK[static_cast<size_t>(j)];
        const Vector shift = w + s_T * (s.U - u_n);
        const Vector& previous = i > 0 ? dK[static_cast<size_t>(i - 1)] : dK_last;
        if (!(st = apply_mass(s, s.coefficient * shift, rhs)).is_ok() ||
            !(st = parameter_term(s, dlambda, rhs)).is_ok() ||
            !(st = solve_linearised(s, rhs, v, tolerance, rate_guess(shift, previous, s.coefficient))).is_ok())
          return st;
        dK[static_cast<size_t>(i)] = s.coefficient * (v - shift);
      }
      un = v;
      dK_last = dK[SdirkTableau::kStages - 1];
    }
    out = std::move(un);
  }
  ++counts_.passes;
  counts_.linearised_seconds += since(t0);
  return {};
}

}  // namespace keller
