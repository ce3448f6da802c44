#include "support/TestProblems.hpp"

namespace keller::test {

CubicProblem::CubicProblem(double lambda) : pattern_(1, 1) {
  params_.add("lambda", lambda, "cubic parameter");
  pattern_.insert(0, 0) = 0.0;
  pattern_.makeCompressed();
}

Status CubicProblem::residual(const Vector& u, Vector& F) {
  F.resize(1);
  F[0] = u[0] * u[0] * u[0] - 3.0 * u[0] - params_.value(0);
  return {};
}

Status CubicProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  residual(u, F);
  J = pattern_;
  J.valuePtr()[0] = 3.0 * u[0] * u[0] - 3.0;
  return {};
}

Status CubicProblem::parameter_derivative(int, const Vector&, Vector& dF) {
  dF = Vector::Constant(1, -1.0);
  return {};
}

Status CubicProblem::observables(const Vector& u, std::vector<double>& v) {
  v = {u[0]};
  return {};
}

Status CubicProblem::monitors(const Vector& u, std::vector<double>& v) {
  v = {u[0] - 0.5};
  return {};
}

FunctionProblem::FunctionProblem(std::string name, int n, const std::vector<std::pair<std::string, double>>& parameters,
                                 Residual F, Jacobian J, ParameterDerivative Fp)
    : name_(std::move(name)), n_(n), pattern_(n, n), F_(std::move(F)), J_(std::move(J)), Fp_(std::move(Fp)) {
  for (const auto& [p, value] : parameters) params_.add(p, value, "parameter of " + name_);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) pattern_.insert(i, j) = 0.0;
  pattern_.makeCompressed();
}

void FunctionProblem::set_monitors(std::vector<std::string> names, Monitors m) {
  monitor_names_ = std::move(names);
  monitors_ = std::move(m);
}

Vector FunctionProblem::values() const { return Eigen::Map<const Vector>(params_.values(), params_.size()); }

Status FunctionProblem::residual(const Vector& u, Vector& F) {
  F = F_(u, values());
  return {};
}

Status FunctionProblem::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  F = F_(u, values());
  const Eigen::MatrixXd D = J_(u, values());
  J = pattern_;  // dense: every entry is in the pattern
  for (int j = 0; j < n_; ++j)
    for (int i = 0; i < n_; ++i) J.coeffRef(i, j) = D(i, j);
  return {};
}

Status FunctionProblem::parameter_derivative(int p, const Vector& u, Vector& dF) {
  dF = Fp_(p, u, values());
  return {};
}

Status FunctionProblem::mass_matrix(const Vector&, SparseMatrix& B) {
  B = pattern_;
  for (int i = 0; i < n_; ++i) B.coeffRef(i, i) = 1.0;
  return {};
}

Status FunctionProblem::monitors(const Vector& u, std::vector<double>& v) {
  v = monitors_ ? monitors_(u) : std::vector<double>{};
  return {};
}

Status FailingBand::check() const {
  const double l = inner_->parameters().value(0);
  if (l >= a_ && l <= b_) return {StatusCode::InvalidState, "the model breaks down here"};
  return {};
}

Status FailingBand::residual(const Vector& u, Vector& F) {
  Status st = check();
  return st.is_ok() ? inner_->residual(u, F) : st;
}

Status FailingBand::jacobian(const Vector& u, Vector& F, SparseMatrix& J) {
  Status st = check();
  return st.is_ok() ? inner_->jacobian(u, F, J) : st;
}

ContinuationOptions bratu_fold_options(const std::string& stop, double above) {
  ContinuationOptions o;
  o.parameter = "lambda";
  o.stop.lower = 0.0;
  o.step.initial = 0.1;
  o.step.max = 0.5;
  o.events.tolerance = 1e-12;
  o.stop.observable = stop;
  o.stop.above = above;
  return o;
}

ContinuationOptions pitchfork_trivial_options() {
  ContinuationOptions o;
  o.parameter = "lambda";
  o.stop.upper = 45.0;
  o.step.initial = 0.5;
  o.step.max = 2.0;
  o.events.tolerance = 1e-10;
  return o;
}

std::vector<const BranchPoint*> RecordingObserver::of_kind(PointKind k) const {
  std::vector<const BranchPoint*> out;
  for (const auto& p : points)
    if (p.kind == k) out.push_back(&p);
  return out;
}

FunctionProblem brusselator_ode(double a, double b) {
  return FunctionProblem(
      "brusselator", 2, {{"a", a}, {"b", b}},
      [](const Vector& u, const Vector& p) {
        Vector F(2);
        F << -(p[0] - (p[1] + 1.0) * u[0] + u[0] * u[0] * u[1]), -(p[1] * u[0] - u[0] * u[0] * u[1]);
        return F;
      },
      [](const Vector& u, const Vector& p) {
        Eigen::MatrixXd J(2, 2);
        J << (p[1] + 1.0) - 2.0 * u[0] * u[1], -u[0] * u[0], -p[1] + 2.0 * u[0] * u[1], u[0] * u[0];
        return J;
      },
      [](int k, const Vector& u, const Vector&) {
        Vector d(2);
        if (k == 0)
          d << -1.0, 0.0;
        else
          d << u[0], -u[0];
        return d;
      });
}

}  // namespace keller::test
