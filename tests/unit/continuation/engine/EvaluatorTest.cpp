// The engine's access to what a problem offers beyond the contract (continuation/engine/Evaluator):
// the gradient of a monitor or observable where the problem offers one (MonitorGradients), and the
// pieces of an observable that is the smallest of them (ObservablePieces), each as a function of
// the branch with its derivative in the parameter; nothing where the problem offers nothing.
#include <gtest/gtest.h>

#include <array>
#include <stdexcept>

#include "continuation/engine/Evaluator.hpp"
#include "support/ContinuationTestSupport.hpp"
#include "support/TestProblems.hpp"

using namespace keller;

namespace {

// F_i = u_i - (1 + i) lambda (i = 0, 1, 2). Observables "u0" and "gap", the smallest of the
// pieces p_j = u_j - c_j lambda, c = (0, 1.5, 2.8): at u = (1, 2, 3) they are (1, 2, 3) at
// lambda = 0 and (1, 0.5, 0.2) at lambda = 1. Offers the gap's gradient (the smallest piece's, e_j)
// and its pieces, not u0's gradient.
class Gapped final : public test::DiagonalProblem, public MonitorGradients, public ObservablePieces {
 public:
  Gapped() : DiagonalProblem("gapped", 3, 0.0) {}
  Vector initial_guess() override { return Vector::Zero(3); }
  std::vector<std::string> observable_names() const override { return {"u0", "gap"}; }
  Status observables(const Vector& u, std::vector<double>& v) override {
    int j = 0;
    smallest_piece(1, u, j);
    v = {u[0], piece(j, u)};
    return {};
  }
  bool has_observable_gradient(int observable) const override { return observable == 1; }
  Status observable_gradient(int observable, const Vector& u, Vector& g) override {
    int j = 0;
    smallest_piece(observable, u, j);
    return piece_gradient(observable, j, u, g);
  }
  bool has_pieces(int observable) const override { return observable == 1; }
  Status smallest_piece(int, const Vector& u, int& j) override {
    j = 0;
    for (int k = 1; k < 3; ++k)
      if (piece(k, u) < piece(j, u)) j = k;
    return {};
  }
  Status piece_value(int, int j, const Vector& u, double& value) override {
    value = piece(j, u);
    return {};
  }
  Status piece_gradient(int, int j, const Vector&, Vector& g) override {
    g = Vector::Unit(3, j);
    return {};
  }

 private:
  double piece(int j, const Vector& u) const { return u[j] - std::array<double, 3>{0.0, 1.5, 2.8}[j] * lambda(); }
  double f(int i, double u, double l) const override { return u - (1 + i) * l; }
  double df_du(int, double, double) const override { return 1.0; }
  double df_dlambda(int i, double, double) const override { return -(1 + i); }
};

const Vector kAt = Eigen::Vector3d(1.0, 2.0, 3.0);

}  // namespace

TEST(Evaluator, AProblemOfferingNothingHasNoGradientsAndNoPieces) {
  test::CubicProblem p(0.0);
  Evaluator ev(p, 0, "lambda");
  EXPECT_EQ(ev.gradient_function(0, true, 0.0), nullptr);
  EXPECT_EQ(ev.gradient_function(0, false, 0.0), nullptr);
  EXPECT_FALSE(ev.has_pieces(0));
  int piece = 0;
  EXPECT_THROW(ev.smallest_piece(0, Vector::Zero(1), 0.0, piece), std::logic_error);
  EXPECT_THROW(ev.piece_function(0, 0, 0.0), std::logic_error);
}

// The gap minus the threshold 0.25 at (u, lambda = 1): its value, the offered gradient in u (the
// smallest piece's, place 2), and in lambda by central differences (exact here: the gap is linear
// in lambda near 1); the parameter left at lambda. u0 offers no gradient.
TEST(Evaluator, AnOfferedGradientIsAFunctionOfTheBranch) {
  Gapped p;
  Evaluator ev(p, 0, "lambda");
  EXPECT_EQ(ev.gradient_function(0, true, 0.0), nullptr);
  const GradientFunction g = ev.gradient_function(1, true, 0.25);
  ASSERT_TRUE(g);
  double value = 0.0, gl = 0.0;
  Vector gu;
  ASSERT_TRUE(g(kAt, 1.0, 1e-3, true, value, gu, gl).is_ok());
  EXPECT_NEAR(value, 0.2 - 0.25, 1e-15);
  EXPECT_EQ(gu, Vector(Vector::Unit(3, 2)));
  EXPECT_NEAR(gl, -2.8, 1e-9);
  EXPECT_EQ(p.parameters().value(0), 1.0);
}

// The smallest piece where the parameter is (set by the call), and one piece as a function of the
// branch wherever it is not the smallest: no piece is held between the calls.
TEST(Evaluator, PiecesAreFunctionsOfTheStateAndParameterAlone) {
  Gapped p;
  Evaluator ev(p, 0, "lambda");
  ASSERT_TRUE(ev.has_pieces(1));
  EXPECT_FALSE(ev.has_pieces(0));
  int piece = -1;
  ASSERT_TRUE(ev.smallest_piece(1, kAt, 0.0, piece).is_ok());
  EXPECT_EQ(piece, 0);
  ASSERT_TRUE(ev.smallest_piece(1, kAt, 1.0, piece).is_ok());
  EXPECT_EQ(piece, 2);
  EXPECT_EQ(p.parameters().value(0), 1.0);
  const GradientFunction g = ev.piece_function(1, 1, 0.25);
  double value = 0.0, gl = 0.0;
  Vector gu;
  ASSERT_TRUE(g(kAt, 1.0, 1e-3, true, value, gu, gl).is_ok());
  EXPECT_NEAR(value, 0.5 - 0.25, 1e-15);
  EXPECT_EQ(gu, Vector(Vector::Unit(3, 1)));
  EXPECT_NEAR(gl, -1.5, 1e-9);
  ASSERT_TRUE(g(kAt, 0.0, 1e-3, false, value, gu, gl).is_ok());
  EXPECT_NEAR(value, 2.0 - 0.25, 1e-15);
  std::vector<double> v;
  ASSERT_TRUE(p.observables(kAt, v).is_ok());
  EXPECT_EQ(v[1], 1.0);  // the gap itself at lambda = 0: piece 0's
}
