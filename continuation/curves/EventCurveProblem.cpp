#include "continuation/curves/EventCurveProblem.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace keller {

namespace {

// A state this close to a switch's (relative, max norm) is the next piece's start: the run's
// correction of the start moves it by about 1e-11 of |U| (M2), the piece's steps by far more than
// 1e-8.
constexpr double kSwitchNeighbourhood = 1e-8;

int index_of(const std::vector<std::string>& names, const std::string& name, const std::string& what) {
  const auto it = std::find(names.begin(), names.end(), name);
  if (it == names.end()) {
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
    throw std::invalid_argument("event curve: unknown " + what + " '" + name + "' (" +
                                (known.empty() ? "none" : known) + ")");
  }
  return static_cast<int>(it - names.begin());
}

}  // namespace

EventCurveProblem::EventCurveProblem(Problem& inner, const std::string& event_parameter, const std::string& monitor)
    : CurveProblem(inner, event_parameter, 1, "event curve"),
      monitor_(index_of(inner.monitor_names(), monitor, "monitor")) {}

Status EventCurveProblem::place_values(const Vector& U, std::vector<double>& values) {
  Status st = set_p1(U);
  if (!st.is_ok()) return st;
  st = places_of(inner_, monitor_, U.head(n_), values);
  if (!st.is_ok()) return st;
  if (place_ >= static_cast<int>(values.size()))
    throw std::logic_error("event curve: the monitor's places changed in number");
  return {};
}

Status EventCurveProblem::argmin(const Vector& U, int& place) {
  std::vector<double> v;
  Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  place = static_cast<int>(std::min_element(v.begin(), v.end()) - v.begin());
  return {};
}

Status EventCurveProblem::residual(const Vector& U, Vector& F) {
  std::vector<double> v;
  Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  Vector f;
  st = inner_.residual(U.head(n_), f);
  if (!st.is_ok()) return st;
  F.resize(n_ + 1);
  F.head(n_) = f;
  F[n_] = v[static_cast<size_t>(place_)];
  return {};
}

Status EventCurveProblem::place_parameter_derivative(int p, int place, const Vector& u, double& derivative) {
  Vector d;
  const Status st = parameter_difference(
      p,
      [&](Vector& value) {
        std::vector<double> v;
        const Status s = places_of(inner_, monitor_, u, v);
        if (s.is_ok()) value = Vector::Constant(1, v[static_cast<size_t>(place)]);
        return s;
      },
      d);
  if (st.is_ok()) derivative = d[0];
  return st;
}

Status EventCurveProblem::equations_parameter_derivative(int p, const Vector& U, Vector& d) {
  double mp = 0.0;
  Status st = set_p1(U);
  if (st.is_ok()) st = place_parameter_derivative(p, place_, U.head(n_), mp);
  d = Vector::Constant(1, mp);
  return st;
}

Status EventCurveProblem::bordered_jacobian(const Vector& U, Vector& F, BorderedJacobian& J) {
  if (J.border_size() != 1 || J.inner_size() != n_) J = blocks();
  Vector f;
  Status st = set_p1(U);
  if (st.is_ok()) st = inner_.jacobian(U.head(n_), f, J.K);
  if (!st.is_ok()) return st;
  return fill_border(U, f, F, J);
}

Status EventCurveProblem::border(const Vector& U, Vector& F, BorderedJacobian& J) {
  if (J.border_size() != 1 || J.inner_size() != n_) return bordered_jacobian(U, F, J);
  Vector f;
  Status st = set_p1(U);
  if (st.is_ok()) st = inner_.residual(U.head(n_), f);
  if (!st.is_ok()) return st;
  return fill_border(U, f, F, J);
}

Status EventCurveProblem::fill_border(const Vector& U, const Vector& f, Vector& F, BorderedJacobian& J) {
  std::vector<double> v;
  Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  F.resize(n_ + 1);
  F.head(n_) = f;
  F[n_] = v[static_cast<size_t>(place_)];
  Vector Fp1, gu;
  st = inner_.parameter_derivative(p1(), u, Fp1);
  if (st.is_ok()) st = place_gradient_of(inner_, monitor_, place_, u, gu);
  double gp1 = 0.0;
  if (st.is_ok()) st = place_parameter_derivative(p1(), place_, u, gp1);
  if (!st.is_ok()) return st;
  J.B.col(0) = Fp1;
  J.C.col(0) = gu;
  J.D(0, 0) = gp1;
  return {};
}

Status EventCurveProblem::observables(const Vector& U, std::vector<double>& values) {
  std::vector<double> v;
  Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  st = inner_.observables(U.head(n_), values);
  if (!st.is_ok()) return st;
  const int j = other_place(U, v);
  const double margin = j >= 0 ? v[static_cast<size_t>(j)] - v[static_cast<size_t>(place_)] : 1.0;
  values.push_back(U[n_]);
  values.push_back(place_);
  values.push_back(margin);
  return {};
}

int EventCurveProblem::other_place(const Vector& U, const std::vector<double>& v) const {
  // At the switch a piece starts from, the place it left is level with the followed one (not a new
  // crossing): the margin there is that of the other places, so that a third one overtaking within
  // the piece's first step is still a crossing.
  // (the piece's start is the switch's state or that state corrected by its run: within
  // kSwitchNeighbourhood of it; a step of the piece moves far more)
  const bool at_switch = switched_at_.size() == U.size() &&
                         (U - switched_at_).lpNorm<Eigen::Infinity>() <=
                             kSwitchNeighbourhood * std::max(1.0, switched_at_.lpNorm<Eigen::Infinity>());
  int other = -1;
  for (size_t j = 0; j < v.size(); ++j)
    if (static_cast<int>(j) != place_ && !(at_switch && static_cast<int>(j) == switched_from_) &&
        (other < 0 || v[j] < v[static_cast<size_t>(other)]))
      other = static_cast<int>(j);
  return other;
}

Status EventCurveProblem::observable_gradient(int observable, const Vector& U, Vector& gradient) {
  if (observable != margin_index()) return MonitorGradients::observable_gradient(observable, U, gradient);
  std::vector<double> v;
  const Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  const int j = other_place(U, v);
  if (j >= 0) return piece_gradient(observable, j, U, gradient);
  gradient = Vector::Zero(U.size());  // one place: the margin is constant
  return {};
}

void EventCurveProblem::check_margin(int observable) const {
  if (observable != margin_index())
    throw std::logic_error("event curve: observable " + std::to_string(observable) + " has no pieces");
}

void EventCurveProblem::check_piece(int observable, int piece) const {
  check_margin(observable);
  if (piece < 0 || piece == place_)
    throw std::logic_error("event curve: the switch margin has no piece " + std::to_string(piece) +
                           " (its pieces are the places other than the followed one, " + std::to_string(place_) + ")");
}

Status EventCurveProblem::smallest_piece(int observable, const Vector& U, int& piece) {
  check_margin(observable);
  std::vector<double> v;
  const Status st = place_values(U, v);
  if (st.is_ok()) piece = other_place(U, v);
  return st;
}

Status EventCurveProblem::piece_value(int observable, int piece, const Vector& U, double& value) {
  check_piece(observable, piece);
  std::vector<double> v;
  const Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  if (piece >= static_cast<int>(v.size()))
    throw std::out_of_range("event curve: the switch margin has no piece " + std::to_string(piece) + " (" +
                            std::to_string(v.size()) + " places)");
  value = v[static_cast<size_t>(piece)] - v[static_cast<size_t>(place_)];
  return {};
}

Status EventCurveProblem::piece_gradient(int observable, int piece, const Vector& U, Vector& gradient) {
  check_piece(observable, piece);
  Status st = set_p1(U);
  if (!st.is_ok()) return st;
  const Vector u = U.head(n_);
  Vector gj, gk;
  double pj = 0.0, pk = 0.0;
  st = place_gradient_of(inner_, monitor_, piece, u, gj);
  if (st.is_ok()) st = place_gradient_of(inner_, monitor_, place_, u, gk);
  if (st.is_ok()) st = place_parameter_derivative(p1(), piece, u, pj);
  if (st.is_ok()) st = place_parameter_derivative(p1(), place_, u, pk);
  if (!st.is_ok()) return st;
  gradient = Vector::Zero(U.size());
  gradient.head(n_) = gj - gk;
  gradient[n_] = pj - pk;
  return {};
}

Status EventCurveProblem::next_place(const Vector& U, int& place) {
  std::vector<double> v;
  const Status st = place_values(U, v);
  if (!st.is_ok()) return st;
  place = place_;
  double best = std::numeric_limits<double>::infinity();
  for (size_t j = 0; j < v.size(); ++j)
    if (static_cast<int>(j) != place_ && v[j] < best) best = v[j], place = static_cast<int>(j);
  return {};
}

void EventCurveProblem::follow(int place) { place_ = place; }

void EventCurveProblem::start_piece_at(const Vector& U, int left) {
  switched_at_ = U;
  switched_from_ = left;
}

std::vector<std::string> EventCurveProblem::monitor_names() const {
  std::vector<std::string> names = inner_.monitor_names();
  names.erase(names.begin() + monitor_);
  return names;
}

Status EventCurveProblem::monitors(const Vector& U, std::vector<double>& values) {
  Status st = set_p1(U);
  if (!st.is_ok()) return st;
  st = inner_.monitors(U.head(n_), values);
  if (!st.is_ok()) return st;
  values.erase(values.begin() + monitor_);  // zero all along the curve: its sign is rounding
  return {};
}

std::string EventCurveProblem::summary() const {
  return fmt::format("event curve of {} = 0 (unknowns the state and {}) of {}", inner_.monitor_names()[monitor_],
                     p1_name(), inner_.summary());
}

}  // namespace keller
