// AssembledProblem on a problem of four unknowns assembled from two terms: a kernel over the
// neighbouring pairs (springs, a source lambda e^u, time terms with a u-dependent B) and a strong
// condition u_0 = 2 mu whose row's weak contributions are redirected to row 3. F is checked
// against the same sums written out, J against central differences of F, dF/dp against its
// closed form, B and the time terms against the local blocks assembled by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>

#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/KernelTerm.hpp"

using namespace keller;

namespace {

constexpr int kUnknowns = 4;

// One pair (i, i + 1): r_0 = (u_0 - u_1) - lambda e^{u_0} / 2, r_1 = (u_1 - u_0) - lambda e^{u_1} / 2;
// time terms r = B udot with B = [[1 + u_0^2, 1/4], [1/4, 1 + u_1^2]].
class PairKernel {
 public:
  static constexpr int kSize = 2;
  std::string name() const { return "pair"; }
  int num_items() const { return kUnknowns - 1; }
  void item_dofs(int item, int* dofs) const {
    dofs[0] = item;
    dofs[1] = item + 1;
  }
  template <class T, class P>
  Status evaluate(int, const T* u, const P* params, T* r) const {
    using std::exp;
    r[0] = (u[0] - u[1]) - 0.5 * params[0] * exp(u[0]);
    r[1] = (u[1] - u[0]) - 0.5 * params[0] * exp(u[1]);
    return {};
  }
  template <class W>
  Status rate(int, const double* u, const W* udot, const double*, W* r) const {
    r[0] = (1.0 + u[0] * u[0]) * udot[0] + 0.25 * udot[1];
    r[1] = 0.25 * udot[0] + (1.0 + u[1] * u[1]) * udot[1];
    return {};
  }
};

class PairChain final : public AssembledProblem {
 public:
  explicit PairChain(bool time_dependent = true) {
    const int i_lambda = params_.add("lambda", 0.7, "source strength");
    const int i_mu = params_.add("mu", 0.15, "half the value held at u_0");
    EXPECT_EQ(i_lambda, 0);  // PairKernel reads lambda as params[0]
    auto held = std::make_shared<DirichletTerm>("held", params_);
    held->add(0, [i_mu](const ParameterSet& p) { return 2.0 * p.value(i_mu); });
    auto pairs = std::make_shared<KernelTerm<PairKernel>>(PairKernel{}, params_);
    assemble(kUnknowns, {pairs, held}, {{0, 3}}, time_dependent ? TimeForm::Assembled : TimeForm::None);
  }
  std::string name() const override { return "pair-chain"; }
  Vector initial_guess() override { return Vector::Zero(kUnknowns); }
  SolutionFields fields(const Vector&) const override { return {}; }
};

// A problem that forgets to assemble its terms.
class Unassembled final : public AssembledProblem {
 public:
  std::string name() const override { return "unassembled"; }
  Vector initial_guess() override { return Vector::Zero(1); }
  SolutionFields fields(const Vector&) const override { return {}; }
};

// A problem that assembles twice.
class AssembledTwice final : public AssembledProblem {
 public:
  AssembledTwice() {
    assemble(1, {});
    assemble(1, {});
  }
  std::string name() const override { return "twice"; }
  Vector initial_guess() override { return Vector::Zero(1); }
  SolutionFields fields(const Vector&) const override { return {}; }
};

Vector test_point() {
  Vector u(kUnknowns);
  u << 0.3, -0.2, 0.5, 0.1;
  return u;
}

// The kernel's rows summed by hand (weak), then row 0 replaced by the condition and its weak
// sum added to row 3. d_lambda: the same for dF/dlambda.
Vector expected_residual(const Vector& u, double lambda, double mu, bool d_lambda = false) {
  Vector weak = Vector::Zero(kUnknowns);
  for (int i = 0; i + 1 < kUnknowns; ++i) {
    const double a = u[i], b = u[i + 1];
    weak[i] += d_lambda ? -0.5 * std::exp(a) : (a - b) - 0.5 * lambda * std::exp(a);
    weak[i + 1] += d_lambda ? -0.5 * std::exp(b) : (b - a) - 0.5 * lambda * std::exp(b);
  }
  Vector F = weak;
  F[0] = d_lambda ? 0.0 : u[0] - 2.0 * mu;
  F[3] += weak[0];
  return F;
}

Eigen::MatrixXd expected_mass(const Vector& u) {
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(kUnknowns, kUnknowns);
  for (int i = 0; i + 1 < kUnknowns; ++i) {
    const int rows[2] = {i == 0 ? 3 : i, i + 1};  // row 0's weak share goes to row 3
    const double local[2][2] = {{1.0 + u[i] * u[i], 0.25}, {0.25, 1.0 + u[i + 1] * u[i + 1]}};
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) B(rows[a], i + b) += local[a][b];
  }
  return B;
}

}  // namespace

TEST(AssembledProblemTest, OwnsItsParametersAndItsTermsReadThem) {
  PairChain p;
  EXPECT_EQ(p.size(), kUnknowns);
  EXPECT_EQ(p.jacobian_pattern().rows(), kUnknowns);
  EXPECT_EQ(p.jacobian_pattern().cols(), kUnknowns);
  EXPECT_EQ(p.parameters().names(), "lambda, mu");
  EXPECT_EQ(&p.parameters(), &static_cast<const PairChain&>(p).parameters());
  EXPECT_EQ(p.assembler().terms().size(), 2u);

  const Vector u = test_point();
  Vector F;
  ASSERT_TRUE(p.residual(u, F).is_ok());
  // the same sums in another order: rounding of O(1) values
  EXPECT_LT((F - expected_residual(u, 0.7, 0.15)).lpNorm<Eigen::Infinity>(), 1e-14);
  // a value set through parameters() is the one the terms read
  p.parameters().set("lambda", 1.3);
  p.parameters().set("mu", -0.4);
  ASSERT_TRUE(p.residual(u, F).is_ok());
  EXPECT_LT((F - expected_residual(u, 1.3, -0.4)).lpNorm<Eigen::Infinity>(), 1e-14);
  EXPECT_NEAR(F[0], u[0] + 0.8, 1e-15);
}

TEST(AssembledProblemTest, JacobianMatchesCentralDifferences) {
  PairChain p;
  const Vector u = test_point();
  Vector F, F0;
  SparseMatrix J = p.jacobian_pattern();
  ASSERT_TRUE(p.jacobian(u, F, J).is_ok());
  ASSERT_TRUE(p.residual(u, F0).is_ok());
  EXPECT_EQ((F - F0).lpNorm<Eigen::Infinity>(), 0.0);  // the Jacobian's F is the residual
  const Eigen::MatrixXd dense(J);
  // h = 1e-6: truncation h^2 |F'''| / 6 ~ 1e-13, rounding eps |F| / h ~ 1e-10
  const double h = 1e-6;
  double worst = 0.0;
  for (int c = 0; c < kUnknowns; ++c) {
    Vector up = u, um = u, Fp, Fm;
    up[c] += h;
    um[c] -= h;
    ASSERT_TRUE(p.residual(up, Fp).is_ok());
    ASSERT_TRUE(p.residual(um, Fm).is_ok());
    const Vector column = (Fp - Fm) / (2 * h);
    worst = std::max(worst, (dense.col(c) - column).lpNorm<Eigen::Infinity>());
  }
  EXPECT_LT(worst, 1e-8);
  // the redirected row: dF_3/du_0 holds row 0's weak entry, 1 - 0.7 e^{u_0} / 2
  EXPECT_NEAR(dense(3, 0), 1.0 - 0.35 * std::exp(u[0]), 1e-14);
  EXPECT_EQ(dense(0, 0), 1.0);  // the held row: u_0 - 2 mu
  EXPECT_EQ(dense(0, 1), 0.0);
}

TEST(AssembledProblemTest, ParameterDerivativesOfKernelAndCondition) {
  PairChain p;
  const Vector u = test_point();
  Vector dF;
  ASSERT_TRUE(p.parameter_derivative(p.parameters().index("lambda"), u, dF).is_ok());
  EXPECT_LT((dF - expected_residual(u, 0.7, 0.15, true)).lpNorm<Eigen::Infinity>(), 1e-14);
  ASSERT_TRUE(p.parameter_derivative(p.parameters().index("mu"), u, dF).is_ok());
  Vector expected = Vector::Zero(kUnknowns);
  expected[0] = -2.0;  // d(u_0 - 2 mu)/dmu; g is affine, its central difference exact to rounding
  EXPECT_LT((dF - expected).lpNorm<Eigen::Infinity>(), 1e-12);
}

TEST(AssembledProblemTest, MassMatrixAndTimeTermsFromTheTerms) {
  PairChain p;
  const Vector u = test_point();
  SparseMatrix B;
  ASSERT_TRUE(p.mass_matrix(u, B).is_ok());
  const Eigen::MatrixXd dense(B);
  EXPECT_LT((dense - expected_mass(u)).lpNorm<Eigen::Infinity>(), 1e-15);
  EXPECT_EQ(dense.row(0).lpNorm<Eigen::Infinity>(), 0.0);  // the held row has no time derivative
  Vector udot(kUnknowns), R;
  udot << 1.0, -2.0, 0.5, 3.0;
  ASSERT_TRUE(p.time_residual(u, udot, R).is_ok());
  EXPECT_LT((R - expected_mass(u) * udot).lpNorm<Eigen::Infinity>(), 1e-14);
}

TEST(AssembledProblemTest, WithoutTimeFormHasNoMassMatrix) {
  PairChain p(false);
  const Vector u = test_point();
  SparseMatrix B;
  Vector R;
  EXPECT_THROW(p.mass_matrix(u, B), std::logic_error);
  EXPECT_THROW(p.time_residual(u, u, R), std::logic_error);
  Vector F;  // the steady form is unaffected
  ASSERT_TRUE(p.residual(u, F).is_ok());
  EXPECT_LT((F - expected_residual(u, 0.7, 0.15)).lpNorm<Eigen::Infinity>(), 1e-14);
}

TEST(AssembledProblemTest, MisuseThrowsNamingTheProblem) {
  Unassembled p;
  try {
    p.size();
    FAIL() << "no error for a problem whose terms were never assembled";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'unassembled'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("assemble()"), std::string::npos) << e.what();
  }
  Vector F;
  EXPECT_THROW(p.residual(Vector::Zero(1), F), std::logic_error);
  try {
    AssembledTwice twice;
    FAIL() << "no error for terms assembled twice";
  } catch (const std::logic_error& e) {
    EXPECT_NE(std::string(e.what()).find("'twice'"), std::string::npos) << e.what();
  }
}

// A boundary value that does not exist at the parameters (its function throws std::domain_error)
// fails the evaluation with the function's reason, in the residual, the Jacobian and dF/dp; any
// other exception is a bug and is not swallowed.
TEST(DirichletTerm, AValueThatDoesNotExistFailsTheEvaluationWithItsReason) {
  ParameterSet params;
  const int a = params.add("a", 1.0, "a parameter");
  DirichletTerm d("inflow", params);
  d.add(0, [a](const ParameterSet& p) {
    if (p.value(a) > 2.0) throw std::domain_error("no profile beyond a = 2");
    return p.value(a);
  });
  double u = 0.5, r = 0, J = 0, dr = 0;
  ASSERT_TRUE(d.residual(0, &u, &r).is_ok());
  EXPECT_EQ(r, -0.5);
  params.set(a, 3.0);
  for (const Status& st : {d.residual(0, &u, &r), d.jacobian(0, &u, &r, &J), d.parameter_derivative(0, a, &u, &dr)}) {
    EXPECT_EQ(st.code(), StatusCode::InvalidState);
    EXPECT_NE(st.message().find("inflow: no profile beyond a = 2"), std::string::npos) << st.message();
  }
  DirichletTerm bug("bug", params);
  bug.add(0, [](const ParameterSet&) -> double { throw std::logic_error("a bug"); });
  EXPECT_THROW(bug.residual(0, &u, &r), std::logic_error);
}

// dF/dp of a boundary value g = a^2 near the open lower bound of a > 0 (as the wall elasticity's):
// at a = 4e-7, within the difference step 1e-6 of the bound, the difference is one-sided on the
// admissible side (it evaluated g at a = 0 before, which ParameterSet refused with an exception
// that ended a Hopf curve's run as an internal error), to its truncation error h = 1e-6;
// centrally, to rounding, away from the bound.
TEST(DirichletTerm, ParameterDerivativeStaysInsideTheAdmissibleRange) {
  ParameterSet params;
  const int a = params.add("a", 4e-7, "a parameter", Range{0.0, INFINITY, true, false});
  DirichletTerm d("wall", params);
  d.add(0, [a](const ParameterSet& p) { return p.value(a) * p.value(a); });
  double u = 0.0, dr = 0.0;
  ASSERT_TRUE(d.parameter_derivative(0, a, &u, &dr).is_ok());
  EXPECT_NEAR(dr, -(2.0 * 4e-7 + 1e-6), 1e-12);  // one-sided: -((a + h)^2 - a^2) / h = -(2a + h)
  params.set(a, 0.5);
  ASSERT_TRUE(d.parameter_derivative(0, a, &u, &dr).is_ok());
  EXPECT_NEAR(dr, -1.0, 1e-9);
  // a range narrower than the step leaves no room on either side: a failed evaluation, not dr = 0
  const int narrow = params.add("n", 5e-8, "a narrow parameter", 0.0, 1e-7);
  DirichletTerm e("wall", params);
  e.add(0, [narrow](const ParameterSet& p) { return p.value(narrow); });
  const Status st = e.parameter_derivative(0, narrow, &u, &dr);
  EXPECT_EQ(st.code(), StatusCode::InvalidState);
  EXPECT_NE(st.message().find("no room"), std::string::npos) << st.message();
}
