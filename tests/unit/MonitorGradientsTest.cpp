// The optional capability of core/MonitorGradients.hpp: found only where a problem offers it, and
// its defaults where a problem offers none of it or only a part (one place, the monitor itself;
// place gradients by one-sided differences; a monitor's gradient at the place of the minimum).
#include <gtest/gtest.h>

#include <algorithm>
#include <stdexcept>

#include "core/MonitorGradients.hpp"
#include "support/ContinuationTestSupport.hpp"

using namespace keller;

namespace {

// F_i = u_i - lambda (i = 0, 1, 2); the monitor "min q" is the minimum over the places
// q_i = u_i^2 + c_i, c = (0.3, 0.1, 0.2): at u = (1, 2, 0.5), q = (1.3, 4.1, 0.45), its minimum at
// place 2, each q_i's gradient 2 u_i e_i.
class Squares : public test::DiagonalProblem {
 public:
  Squares() : DiagonalProblem("squares", 3, 0.0) {}
  Vector initial_guess() override { return Vector::Zero(3); }
  std::vector<std::string> monitor_names() const override { return {"min q"}; }
  Status monitors(const Vector& u, std::vector<double>& v) override {
    std::vector<double> q;
    places(u, q);
    v = {std::min({q[0], q[1], q[2]})};
    return {};
  }

 protected:
  static void places(const Vector& u, std::vector<double>& q) {
    q = {u[0] * u[0] + 0.3, u[1] * u[1] + 0.1, u[2] * u[2] + 0.2};
  }
  double f(int, double u, double lambda) const override { return u - lambda; }
  double df_du(int, double, double) const override { return 1.0; }
  double df_dlambda(int, double, double) const override { return -1.0; }
};

// The same problem offering the places of "min q" (and nothing else of the capability).
class SquaresWithPlaces final : public Squares, public MonitorGradients {
 public:
  bool has_places(int monitor) const override { return monitor == 0; }
  Status monitor_places(int, const Vector& u, std::vector<double>& values) override {
    places(u, values);
    return {};
  }
};

const Vector kAt = Eigen::Vector3d(1.0, 2.0, 0.5);

}  // namespace

// A problem that does not offer the capability: not found; its monitor is its only place, whose
// gradient is the differences of the monitor (one-sided, step 1e-7 max(1, |u_j|): error about
// 1e-7 of the second derivative 2); a monitor it does not have is an error naming it.
TEST(MonitorGradients, AProblemWithoutItHasOnePlaceTheMonitor) {
  Squares p;
  EXPECT_EQ(monitor_gradients(p), nullptr);
  std::vector<double> v;
  ASSERT_TRUE(places_of(p, 0, kAt, v).is_ok());
  ASSERT_EQ(v.size(), 1u);
  EXPECT_DOUBLE_EQ(v[0], 0.45);
  Vector g;
  ASSERT_TRUE(place_gradient_of(p, 0, 0, kAt, g).is_ok());
  EXPECT_NEAR(g[0], 0.0, 1e-15);
  EXPECT_NEAR(g[1], 0.0, 1e-15);
  EXPECT_NEAR(g[2], 1.0, 1e-6);
  EXPECT_THROW(places_of(p, 1, kAt, v), std::out_of_range);
  EXPECT_THROW(place_gradient_of(p, 0, 1, kAt, g), std::out_of_range);
  try {
    places_of(p, 1, kAt, v);
  } catch (const std::out_of_range& e) {
    EXPECT_NE(std::string(e.what()).find("'squares'"), std::string::npos) << e.what();
  }
}

// A problem offering the places alone: found; its places; each place's gradient by the default
// differences of its places; no monitor or observable gradient offered, and the default monitor
// gradient (were one offered) that of the place where the minimum sits.
TEST(MonitorGradients, OfferedPlacesTheirGradientsAndTheMinimumsByDefault) {
  SquaresWithPlaces p;
  MonitorGradients* offered = monitor_gradients(p);
  ASSERT_EQ(offered, &p);
  EXPECT_FALSE(offered->has_monitor_gradient(0));
  EXPECT_FALSE(offered->has_observable_gradient(0));
  EXPECT_FALSE(offered->has_places(1));
  std::vector<double> v;
  ASSERT_TRUE(places_of(p, 0, kAt, v).is_ok());
  ASSERT_EQ(v.size(), 3u);
  EXPECT_DOUBLE_EQ(v[1], 4.1);
  Vector g;
  ASSERT_TRUE(place_gradient_of(p, 0, 1, kAt, g).is_ok());
  EXPECT_NEAR(g[1], 4.0, 1e-6);  // 2 u_1
  EXPECT_NEAR(g[0], 0.0, 1e-15);
  EXPECT_NEAR(g[2], 0.0, 1e-15);
  ASSERT_TRUE(offered->monitor_gradient(0, kAt, g).is_ok());
  EXPECT_NEAR(g[2], 1.0, 1e-6);  // the minimum at place 2: 2 u_2
  EXPECT_NEAR(g[0], 0.0, 1e-15);
  EXPECT_THROW(offered->observable_gradient(0, kAt, g), std::logic_error);
  EXPECT_THROW(place_gradient_of(p, 0, 3, kAt, g), std::out_of_range);
}
