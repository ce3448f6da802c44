// Fully developed channel flow of each viscoelastic fluid: in a straight channel fed with the
// fluid's own fully developed state the discrete solution must approach the exact profiles
// (velocity from the 1D solve, M from the steady-shear closed forms at the exact shear rate),
// with the error falling at the order of the elements under refinement across the channel:
// O(h^2) for the Q1 conformation. The Oldroyd-B velocity is a parabola, so its error is only
// what the O(h^2) stress error feeds back (about 1e-5). The Owens (Cross) viscosity has an
// infinite slope at zero shear and drops to a tenth within 1% of the channel width of the
// centreline at these shear rates, so its profile has a near-singular layer there and the
// velocity converges at about h^1.4. The laws added later (Giesekus alpha = 0.3, PTT epsilon =
// 0.25 with the slip xi = 0.1 in the conformation form, FENE-CR b = 20) thin in shear: their
// profiles come from the same 1D solve with their own viscosity, their states from their own
// closed forms, and both forms converge at O(h^2) to the same solution. Giesekus and PTT with
// xi > 0 have a second normal stress difference, so their fully developed pressure varies across
// the channel; the outflow condition allows for it (OutflowTractionKernel), or the velocity
// error stops falling at 5e-5 (measured with Giesekus, ny = 16 to 64). A multi-mode fluid's
// profile comes from the sum of its modes' viscosities, each mode's state from the closed form at
// its own Wi_k = t_k Wi; both converge as one mode's.
#include <gtest/gtest.h>

#include <cmath>
#include <iomanip>
#include <iostream>
#include <tuple>

#include "core/Newton.hpp"
#include "problems/channel/ChannelProblem.hpp"
#include "problems/laws/LogConformation.hpp"
#include "problems/laws/SteadyFlows.hpp"

using namespace keller;

namespace {

struct Errors {
  double velocity = 0, conformation = 0;  // max nodal errors on the cross-section, relative
};

Errors errors_at_section(FluidModel model, bool log_form, int ny, const std::vector<ModeKeys>& modes = {}) {
  ChannelOptions o;
  o.geometry = {2.0, 2.0, 2.0, 0.4};
  o.mesh.name = "custom";
  o.mesh.nx_upstream = 2;
  o.mesh.nx_deformable = 2;
  o.mesh.nx_downstream = 2;
  o.mesh.ny_fluid = ny;
  o.mesh.ratio_x = 1.0;
  o.mesh.ratio_y = 1.0;
  o.Gamma = 1.0;
  o.fluid.model = model;
  o.fluid.log_conformation = log_form;
  o.fluid.Wi = 0.2;
  o.fluid.beta = model == FluidModel::Owens ? OwensParameters().beta() : 0.3;
  o.fluid.constants.b = 20.0;
  o.fluid.constants.alpha = 0.3;
  o.fluid.constants.epsilon = 0.25;
  o.fluid.constants.xi = log_form ? 0.0 : 0.1;  // PTT's slip (the log form has none)
  o.fluid.profile = ProfileKind::FullyDeveloped;
  o.fluid.modes = modes;
  ChannelProblem p(o);
  Vector u = p.initial_guess();
  NewtonSolver newton(p);
  const NewtonResult r = newton.solve(u);
  EXPECT_TRUE(r.converged()) << r.status.describe();

  // exact state on the cross-section x = 2 (a mesh line)
  const DofMap& d = p.dofs();
  const int fv = d.field_index("velocity");
  // (field, t_k, w_k) of each mode
  std::vector<std::tuple<int, double, double>> mode_list = {{d.field_index("conformation"), 1.0, 1.0}};
  for (size_t k = 0; k < modes.size(); ++k)
    mode_list.emplace_back(d.field_index(k == 0 ? "conformation" : "conformation_" + modes[k].name), modes[k].time,
                           modes[k].viscosity);
  if (!modes.empty()) mode_list.erase(mode_list.begin());
  std::vector<int> nodes;
  std::vector<double> ys;
  for (int n = 0; n < p.mesh().num_nodes(); ++n)
    if (std::abs(p.mesh().node(n)[0] - 2.0) < 1e-12) {
      nodes.push_back(n);
      ys.push_back(p.mesh().node(n)[1]);
    }
  InflowProfile profile{ProfileKind::FullyDeveloped, 0.0, 1.0, 0.5};
  OwensParameters owens;
  const auto eta = [&](double g) {
    double eta_p = 0;  // the modes' polymer viscosities at Wi_k = t_k Wi, weighted by their shares
    for (const auto& [f, t, w] : mode_list)
      eta_p += w * (shear_viscosity(model, g, t * o.fluid.Wi, 1.0, 0.3, o.fluid.constants, owens) - 0.3) / 0.7;
    return modes.empty() ? shear_viscosity(model, g, o.fluid.Wi, 1.0, o.fluid.beta, o.fluid.constants, owens)
                         : o.fluid.beta + (1.0 - o.fluid.beta) * eta_p;
  };
  std::vector<double> uex, dudy;
  profile.evaluate(ys, 1.0, eta, uex, dudy);
  Errors e;
  double mscale = 0;
  for (size_t k = 0; k < nodes.size(); ++k) {
    e.velocity = std::max(e.velocity, std::abs(u[d.node_dof(fv, nodes[k], 0)] - uex[k]) / 1.5);
    if (!p.mesh().is_vertex(nodes[k])) continue;
    for (const auto& [fm, t, w] : mode_list) {
      double lam = o.fluid.Wi * t;
      if (model == FluidModel::Owens) lam *= owens_factor(dudy[k] * dudy[k], 1.0, owens);
      const SteadyConformation s = steady_shear(model, lam * dudy[k], o.fluid.constants);
      double c[3] = {u[d.node_dof(fm, nodes[k], 0)], u[d.node_dof(fm, nodes[k], 1)], u[d.node_dof(fm, nodes[k], 2)]};
      if (log_form) {
        const Sym2<double> M = sym_exp(Sym2<double>{c[0], c[1], c[2]});
        c[0] = M.xx;
        c[1] = M.xy;
        c[2] = M.yy;
      }
      const double ex[3] = {s.xx, s.xy, s.yy};
      for (int j = 0; j < 3; ++j) {
        e.conformation = std::max(e.conformation, std::abs(c[j] - ex[j]));
        mscale = std::max(mscale, std::abs(ex[j]));
      }
    }
  }
  e.conformation /= mscale;
  return e;
}

struct Orders {
  std::vector<Errors> errors;
  std::vector<double> velocity, conformation;
};

Orders convergence(FluidModel model, bool log_form, const std::vector<ModeKeys>& modes = {}) {
  Orders o;
  for (int ny : {4, 8, 16}) {
    o.errors.push_back(errors_at_section(model, log_form, ny, modes));
    std::cout << std::setprecision(4) << to_string(model) << (log_form ? " log" : "") << " ny = " << ny
              << ": velocity error " << o.errors.back().velocity << ", conformation error "
              << o.errors.back().conformation << "\n";
  }
  for (size_t k = 0; k + 1 < o.errors.size(); ++k) {
    o.velocity.push_back(std::log2(o.errors[k].velocity / o.errors[k + 1].velocity));
    o.conformation.push_back(std::log2(o.errors[k].conformation / o.errors[k + 1].conformation));
    std::cout << "  observed orders: velocity " << o.velocity.back() << ", conformation " << o.conformation.back()
              << "\n";
  }
  return o;
}

}  // namespace

TEST(FullyDevelopedChannel, OldroydB) {
  const Orders o = convergence(FluidModel::OldroydB, false);
  for (double p : o.conformation) EXPECT_NEAR(p, 2.0, 0.2);
  for (const Errors& e : o.errors) EXPECT_LT(e.velocity, 1e-4);
}

TEST(FullyDevelopedChannel, FeneP) {
  const Orders o = convergence(FluidModel::FeneP, false);
  for (double p : o.conformation) EXPECT_NEAR(p, 2.0, 0.2);
  for (double p : o.velocity) EXPECT_GT(p, 1.8);
}

TEST(FullyDevelopedChannel, Owens) {
  const Orders o = convergence(FluidModel::Owens, false);
  for (double p : o.velocity) EXPECT_GT(p, 1.2);
  for (const Errors& e : o.errors) EXPECT_LT(e.conformation, 1e-4);
}

TEST(FullyDevelopedChannel, OldroydBLogConformation) {
  const Orders o = convergence(FluidModel::OldroydB, true);
  for (double p : o.conformation) EXPECT_NEAR(p, 2.0, 0.2);
  for (double p : o.velocity) EXPECT_GT(p, 1.5);
  // the same discretisation error as the conformation form, within a factor of two
  const Orders c = convergence(FluidModel::OldroydB, false);
  EXPECT_LT(o.errors.back().conformation, 2 * c.errors.back().conformation);
}

// The laws added to the reference study's: the conformation at O(h^2) and the velocity at
// least at O(h^1.8) in both forms, and the log form's error within twice the conformation form's.
TEST(FullyDevelopedChannel, EveryNewLawInBothForms) {
  for (FluidModel m : {FluidModel::Giesekus, FluidModel::PttLinear, FluidModel::PttExponential, FluidModel::FeneCr}) {
    SCOPED_TRACE(to_string(m));
    const Orders c = convergence(m, false), l = convergence(m, true);
    for (const Orders* o : {&c, &l}) {
      for (double p : o->conformation) EXPECT_NEAR(p, 2.0, 0.2);
      for (double p : o->velocity) EXPECT_GT(p, 1.8);
    }
    EXPECT_LT(l.errors.back().conformation, 2 * c.errors.back().conformation);
  }
}

// Two modes of different times (1 and 0.15 lambda) and shares: the profile of the summed
// viscosity and each mode's own steady shear state, at the one-mode rates, in both forms.
TEST(FullyDevelopedChannel, TwoModePttInBothForms) {
  const std::vector<ModeKeys> modes = {{"slow", 1.0, 0.7}, {"fast", 0.15, 0.3}};
  const Orders c = convergence(FluidModel::PttLinear, false, modes),
               l = convergence(FluidModel::PttLinear, true, modes);
  for (const Orders* o : {&c, &l}) {
    for (double p : o->conformation) EXPECT_NEAR(p, 2.0, 0.2);
    for (double p : o->velocity) EXPECT_GT(p, 1.8);
  }
  EXPECT_LT(l.errors.back().conformation, 2 * c.errors.back().conformation);
}
