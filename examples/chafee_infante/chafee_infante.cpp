// A user's own problem with every keller command: the Chafee-Infante equation
//   u'' + lambda (u - u^3) = 0 on (0, pi),  u(0) = u(pi) = 0,
// by second-order central differences on n intervals (h = pi / n; unknowns: the n - 1 interior
// values). Its trivial branch u = 0 has branch points at the eigenvalues of the discrete
// Laplacian, lambda_k = (4 / h^2) sin^2(k h / 2) (k^2 in the continuum), where sin(k x) bifurcates.
//
// The program registers the problem type "chafee-infante" with its scene keys and hands over to
// keller's command line: `chafee_infante trace scene.toml -o out.h5`, `solve`, `evolve`, `export`,
// `info`, `study` and `--help-scene` work as they do for keller's own problems.
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "core/Problem.hpp"
#include "core/Scene.hpp"
#include "problems/ProblemRegistry.hpp"
#include "runs/CommandLine.hpp"

namespace {

using keller::Status;
using keller::Vector;

class ChafeeInfante final : public keller::Problem {
 public:
  ChafeeInfante(int intervals, double lambda) : n_(intervals), h_(M_PI / intervals) {
    params_.add("lambda", lambda, "coefficient of u - u^3 (branch points of u = 0 near k^2)");
    std::vector<Eigen::Triplet<double, int>> t;
    for (int i = 0; i < size(); ++i)
      for (int j = std::max(0, i - 1); j <= std::min(size() - 1, i + 1); ++j) t.emplace_back(i, j, 0.0);
    pattern_.resize(size(), size());
    pattern_.setFromTriplets(t.begin(), t.end());
    pattern_.makeCompressed();
  }

  // required: the problem's name, size, parameters, Jacobian pattern, residual, starting state
  std::string name() const override { return "chafee-infante"; }
  int size() const override { return n_ - 1; }
  keller::ParameterSet& parameters() override { return params_; }
  const keller::ParameterSet& parameters() const override { return params_; }
  const keller::SparseMatrix& jacobian_pattern() const override { return pattern_; }
  Vector initial_guess() override { return Vector::Zero(size()); }

  Status residual(const Vector& u, Vector& F) override {
    const double lambda = params_.value(0), ih2 = 1.0 / (h_ * h_);
    F.resize(size());
    for (int i = 0; i < size(); ++i) {
      const double l = i > 0 ? u[i - 1] : 0.0, r = i + 1 < size() ? u[i + 1] : 0.0;
      F[i] = -(l - 2.0 * u[i] + r) * ih2 - lambda * (u[i] - u[i] * u[i] * u[i]);
    }
    return {};
  }

  // optional, each with a default: the exact Jacobian (default: finite differences), dF/dlambda,
  // the mass matrix of du/dt = -F (stability, time integration), observables, a summary
  Status jacobian(const Vector& u, Vector& F, keller::SparseMatrix& J) override {
    if (Status st = residual(u, F); !st.is_ok()) return st;
    const double lambda = params_.value(0), ih2 = 1.0 / (h_ * h_);
    J = pattern_;
    for (int i = 0; i < size(); ++i) {
      J.coeffRef(i, i) = 2.0 * ih2 - lambda * (1.0 - 3.0 * u[i] * u[i]);
      if (i > 0) J.coeffRef(i, i - 1) = -ih2;
      if (i + 1 < size()) J.coeffRef(i, i + 1) = -ih2;
    }
    return {};
  }
  Status parameter_derivative(int, const Vector& u, Vector& dF) override {
    dF = -(u.array() - u.array().cube()).matrix();
    return {};
  }
  Status mass_matrix(const Vector&, keller::SparseMatrix& B) override {
    B = pattern_;
    for (int i = 0; i < size(); ++i) B.coeffRef(i, i) = 1.0;
    return {};
  }
  std::vector<std::string> observable_names() const override { return {"u_max", "u_quarter"}; }
  Status observables(const Vector& u, std::vector<double>& values) override {
    values = {u.cwiseAbs().maxCoeff(), u[n_ / 4 - 1]};  // |u| max; u at x = pi / 4 (n a multiple of 4)
    return {};
  }
  std::string summary() const override {
    const double s = std::sin(h_ / 2.0);
    return "Chafee-Infante on " + std::to_string(n_) +
           " intervals; first branch point of u = 0 at lambda = " + std::to_string(4.0 / (h_ * h_) * s * s);
  }

 private:
  int n_;
  double h_;
  keller::ParameterSet params_;
  keller::SparseMatrix pattern_;
};

}  // namespace

int main(int argc, char** argv) {
  keller::use_native_blas_kernels(argv);  // OpenBLAS on the CPU's own kernels (runs/CommandLine.hpp)
  keller::ProblemType type;
  type.name = "chafee-infante";
  type.doc = "u'' + lambda (u - u^3) = 0 on (0, pi) with u = 0 at both ends, central differences";
  type.declare = [](keller::SceneSchema& s) {
    s.section("chafee_infante", "the grid");
    s.integer("chafee_infante.intervals", 64, "intervals on (0, pi), a multiple of 4", keller::Range::between(4, 1e6));
    s.section("parameters", "initial values of the named continuation parameters");
    s.real("parameters.lambda", 0.5, "coefficient of u - u^3");
  };
  type.build = [](const keller::Scene& s) -> std::unique_ptr<keller::Problem> {
    const int n = s.integer("chafee_infante.intervals");
    if (n % 4 != 0) throw s.error("chafee_infante.intervals", "must be a multiple of 4 (u_quarter is a grid value)");
    return std::make_unique<ChafeeInfante>(n, s.real("parameters.lambda"));
  };
  keller::register_problem_type(std::move(type));
  return keller::run_command_line(argc, argv);
}
