// Poiseuille flow is in the Q2-P1disc space on bilinear elements, so the discrete solution
// must equal it to rounding on a graded AND distorted mesh: v_x = 6 Gamma y (1 - y), v_y = 0,
// dP/dx = -12 Gamma (beta = 1), P = 0 at the outflow. Navier-Stokes (v . grad v = 0 for this
// flow) must return the same solution.
#include <gtest/gtest.h>

#include <cmath>
#include <iostream>

#include "core/Newton.hpp"
#include "problems/channel/ChannelProblem.hpp"
#include "support/TestSupport.hpp"

using namespace keller;

namespace {

struct Errors {
  double velocity = 0;        // max |v - v_exact| / max |v_exact| over all velocity nodes
  double pressure_slope = 0;  // max over elements of |grad P - (-12 Gamma, 0)| / (12 Gamma)
  double pressure_value = 0;  // max |P - 12 Gamma (19 - x)| at element centres / (12 Gamma 19)
};

Errors poiseuille_errors(const ChannelProblem& p, const Vector& u, double Gamma) {
  Errors e;
  const DofMap& d = p.dofs();
  const int fv = d.field_index("velocity"), fp = d.field_index("pressure");
  const double vmax = 1.5 * Gamma;
  for (int n = 0; n < p.mesh().num_nodes(); ++n) {
    const double y = p.mesh().node(n)[1];
    e.velocity = std::max(e.velocity, std::abs(u[d.node_dof(fv, n, 0)] - 6 * Gamma * y * (1 - y)) / vmax);
    e.velocity = std::max(e.velocity, std::abs(u[d.node_dof(fv, n, 1)]) / vmax);
  }
  const double G = 12 * Gamma;
  for (int el = 0; el < p.mesh().num_elements(); ++el) {
    const double xc = p.mesh().node(p.mesh().element(el)[4])[0];
    e.pressure_value = std::max(e.pressure_value, std::abs(u[d.element_dof(fp, el, 0, 0)] - G * (19 - xc)) / (G * 19));
    e.pressure_slope = std::max(e.pressure_slope, std::abs(u[d.element_dof(fp, el, 1, 0)] + G) / G);
    e.pressure_slope = std::max(e.pressure_slope, std::abs(u[d.element_dof(fp, el, 2, 0)]) / G);
  }
  return e;
}

}  // namespace

TEST(Poiseuille, ExactOnGradedDistortedMeshForStokesAndNavierStokes) {
  for (double Gamma : {1.0, 4.95e-4}) {
    ChannelOptions o;
    o.mesh = ChannelMeshSpec::preset("M1");
    o.Gamma = Gamma;
    Mesh mesh = build_channel_mesh(o.geometry, o.mesh, false);
    test::distort_bilinear(mesh, 0.3, 42);
    ASSERT_GT(mesh.jacobian_range().first, 0.0);
    // the distortion really happened: some element is not a parallelogram
    const auto& el = mesh.element(mesh.block("deformable").element(3, 3));
    const double skew =
        std::abs((mesh.node(el[8])[0] - mesh.node(el[6])[0]) - (mesh.node(el[2])[0] - mesh.node(el[0])[0]));
    EXPECT_GT(skew, 1e-3);

    ChannelProblem stokes(o, mesh);
    Vector us = Vector::Zero(stokes.size());  // start from rest: Newton must find it
    NewtonSolver ns(stokes);
    ASSERT_TRUE(ns.solve(us).converged());
    const Errors es = poiseuille_errors(stokes, us, Gamma);
    std::cout << "Stokes, Gamma = " << Gamma << ": velocity error " << es.velocity << ", pressure slope error "
              << es.pressure_slope << ", pressure error " << es.pressure_value << "\n";
    EXPECT_LT(es.velocity, 1e-10);
    EXPECT_LT(es.pressure_slope, 1e-9);
    EXPECT_LT(es.pressure_value, 1e-10);
    // absolute velocity error <= 1e-10 (for Gamma = 1 the relative and absolute errors coincide)
    EXPECT_LT(es.velocity * 1.5 * Gamma, 1e-10);

    o.fluid.Re = 10.0;
    o.fluid.inertia = true;
    ChannelProblem navier(o, mesh);
    Vector un = Vector::Zero(navier.size());
    NewtonSolver nn(navier);
    const NewtonResult r = nn.solve(un);
    ASSERT_TRUE(r.converged()) << r.status.describe();
    const Errors en = poiseuille_errors(navier, un, Gamma);
    std::cout << "Navier-Stokes Re = 10: velocity error " << en.velocity << ", difference to Stokes "
              << (un - us).cwiseAbs().maxCoeff() / (1.5 * Gamma) << "\n";
    EXPECT_LT(en.velocity, 1e-10);
    EXPECT_LT(en.pressure_slope, 1e-9);
    EXPECT_LT((un - us).cwiseAbs().maxCoeff() / (1.5 * Gamma), 1e-10);

    // observables: pressure drop over the deformable section and flow rates
    std::vector<double> obs;
    stokes.observables(us, obs);
    EXPECT_NEAR(obs[0], 12 * Gamma * 5, 1e-10 * 12 * Gamma * 5);  // dP
    EXPECT_NEAR(obs[1], Gamma, 1e-12 * Gamma);                    // Q_in
    EXPECT_NEAR(obs[2], Gamma, 1e-10 * Gamma);                    // Q_out
  }
}
