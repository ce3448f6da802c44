#include "problems/analytic/Brusselator1DProblem.hpp"

#include "problems/analytic/Grid1D.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <stdexcept>

namespace keller {

namespace {
enum : int { kA = 0, kB = 1, kDu = 2, kDv = 3 };
}  // namespace

void Brusselator1DOptions::declare(SceneSchema& s) {
  const Brusselator1DOptions d;
  s.section("brusselator", "Brusselator reaction-diffusion system on (0, L) with no-flux boundaries");
  s.integer("brusselator.intervals", d.intervals, "grid intervals on (0, L) (n + 1 nodes, boundaries included)",
            Range::between(2, max_grid_intervals));
  s.real("brusselator.length", d.length, "L, length of the interval", Range::positive());
  s.section("parameters", "initial values of the named continuation parameters");
  s.real("parameters.a", d.a, "feed rate a; the uniform state is (a, b / a)", Range::positive());
  s.real("parameters.b", d.b, "conversion rate b; the uniform state has its Hopf at b = 1 + a^2",
         Range::non_negative());
  s.real("parameters.D_u", d.D_u, "diffusivity of u", Range::non_negative());
  s.real("parameters.D_v", d.D_v, "diffusivity of v (D_v = D_u: no Turing instability)", Range::non_negative());
}

Brusselator1DOptions Brusselator1DOptions::from_scene(const Scene& scene) {
  Brusselator1DOptions o;
  o.intervals = static_cast<int>(scene.integer("brusselator.intervals"));
  o.length = scene.real("brusselator.length");
  o.a = scene.real("parameters.a");
  o.b = scene.real("parameters.b");
  o.D_u = scene.real("parameters.D_u");
  o.D_v = scene.real("parameters.D_v");
  return o;
}

Brusselator1DProblem::Brusselator1DProblem(const Brusselator1DOptions& o) : n_(o.intervals), length_(o.length) {
  if (o.intervals < 2) throw std::invalid_argument("brusselator1d: need at least 2 intervals");
  if (!(o.length > 0.0)) throw std::invalid_argument("brusselator1d: the length must be > 0");
  if (!(o.a > 0.0)) throw std::invalid_argument("brusselator1d: a must be > 0 (the uniform state is (a, b / a))");
  params_.add("a", o.a, "feed rate; the uniform state is (a, b / a)", Range::positive());
  params_.add("b", o.b, "conversion rate; Hopf of the uniform state at b = 1 + a^2", 0.0);
  params_.add("D_u", o.D_u, "diffusivity of u", 0.0);
  params_.add("D_v", o.D_v, "diffusivity of v", 0.0);
  // row (i, c) = 2 i + c couples to both components at node i and to component c at i - 1, i + 1
  std::vector<Eigen::Triplet<double, int>> t;
  for (int i = 0; i <= n_; ++i)
    for (int c = 0; c < 2; ++c) {
      const int r = 2 * i + c;
      t.emplace_back(r, 2 * i, 0.0);
      t.emplace_back(r, 2 * i + 1, 0.0);
      if (i > 0) t.emplace_back(r, 2 * (i - 1) + c, 0.0);
      if (i < n_) t.emplace_back(r, 2 * (i + 1) + c, 0.0);
    }
  pattern_.resize(size(), size());
  pattern_.setFromTriplets(t.begin(), t.end());
  pattern_.makeCompressed();
}

double Brusselator1DProblem::laplacian(const Vector& w, int c, int i) const {
  const double l = w[2 * (i > 0 ? i - 1 : 1) + c], r = w[2 * (i < n_ ? i + 1 : n_ - 1) + c];
  return (l - 2.0 * w[2 * i + c] + r) / (h() * h());
}

Status Brusselator1DProblem::residual(const Vector& w, Vector& F) {
  const double a = params_.value(kA), b = params_.value(kB), Du = params_.value(kDu), Dv = params_.value(kDv);
  F.resize(size());
  for (int i = 0; i <= n_; ++i) {
    const double u = w[2 * i], v = w[2 * i + 1], uuv = u * u * v;
    F[2 * i] = -(Du * laplacian(w, 0, i) + a - (b + 1.0) * u + uuv);
    F[2 * i + 1] = -(Dv * laplacian(w, 1, i) + b * u - uuv);
  }
  if (!F.allFinite()) return {StatusCode::NotFinite, "brusselator1d residual overflow"};
  return {};
}

Status Brusselator1DProblem::jacobian(const Vector& w, Vector& F, SparseMatrix& J) {
  Status st = residual(w, F);
  if (!st.is_ok()) return st;
  J = pattern_;
  const double b = params_.value(kB), ih2 = 1.0 / (h() * h());
  const double D[2] = {params_.value(kDu), params_.value(kDv)};
  for (int col = 0; col < J.outerSize(); ++col)
    for (SparseMatrix::InnerIterator it(J, col); it; ++it) {
      const int i = it.row() / 2, c = it.row() % 2, j = col / 2, cc = col % 2;
      if (j != i) {
        // neighbour in the same component; a boundary node sees its only neighbour twice (ghost)
        it.valueRef() = -D[c] * ih2 * ((i == 0 || i == n_) ? 2.0 : 1.0);
        continue;
      }
      const double u = w[2 * i], v = w[2 * i + 1];
      double value = c == cc ? 2.0 * D[c] * ih2 : 0.0;
      if (c == 0)
        value += cc == 0 ? (b + 1.0) - 2.0 * u * v : -u * u;
      else
        value += cc == 0 ? -b + 2.0 * u * v : u * u;
      it.valueRef() = value;
    }
  return {};
}

Status Brusselator1DProblem::parameter_derivative(int p, const Vector& w, Vector& dF) {
  dF = Vector::Zero(size());
  for (int i = 0; i <= n_; ++i) {
    switch (p) {
      case kA: dF[2 * i] = -1.0; break;
      case kB:
        dF[2 * i] = w[2 * i];
        dF[2 * i + 1] = -w[2 * i];
        break;
      case kDu: dF[2 * i] = -laplacian(w, 0, i); break;
      case kDv: dF[2 * i + 1] = -laplacian(w, 1, i); break;
      default: throw std::out_of_range(fmt::format("brusselator1d: no parameter with index {}", p));
    }
  }
  return {};
}

Status Brusselator1DProblem::mass_matrix(const Vector&, SparseMatrix& B) {
  B = pattern_;
  for (int c = 0; c < B.outerSize(); ++c)
    for (SparseMatrix::InnerIterator it(B, c); it; ++it) it.valueRef() = it.row() == c ? 1.0 : 0.0;
  return {};
}

Vector Brusselator1DProblem::initial_guess() {
  const double a = params_.value(kA), b = params_.value(kB);
  Vector w(size());
  for (int i = 0; i <= n_; ++i) {
    w[2 * i] = a;
    w[2 * i + 1] = b / a;
  }
  return w;
}

Status Brusselator1DProblem::observables(const Vector& w, std::vector<double>& values) {
  double su = 0.0, sv = 0.0, umax = w[0], umin = w[0];
  for (int i = 0; i <= n_; ++i) {
    const double weight = (i == 0 || i == n_) ? 0.5 : 1.0;
    su += weight * w[2 * i];
    sv += weight * w[2 * i + 1];
    umax = std::max(umax, w[2 * i]);
    umin = std::min(umin, w[2 * i]);
  }
  values = {su / n_, sv / n_, umax, umin};
  return {};
}

SolutionFields Brusselator1DProblem::fields(const Vector& w) const {
  SolutionFields f;
  NamedArray arr{
      "profile", "u(x) and v(x) on the grid, boundary nodes included", Eigen::MatrixXd(n_ + 1, 3), {"x", "u", "v"}};
  for (int i = 0; i <= n_; ++i) {
    arr.values(i, 0) = i * h();
    arr.values(i, 1) = w[2 * i];
    arr.values(i, 2) = w[2 * i + 1];
  }
  f.arrays.push_back(std::move(arr));
  return f;
}

std::string Brusselator1DProblem::summary() const {
  const double a = params_.value(kA);
  return fmt::format(
      "1D Brusselator on (0, {}), no-flux ends, central differences on {} intervals, {} unknowns; "
      "Hopf of the uniform state at b = 1 + a^2 = {:.10g}, frequency {:.10g}",
      length_, n_, size(), 1.0 + a * a, a);
}

std::unique_ptr<Problem> Brusselator1DProblem::from_scene(const Scene& scene) {
  return std::make_unique<Brusselator1DProblem>(Brusselator1DOptions::from_scene(scene));
}

}  // namespace keller
