// Volume sources of the flow equations, as functions of the physical position: a body force in
// the momentum equation and a source in each constitutive (conformation or log-conformation)
// equation. No physical problem of model.md has them; they exist for manufactured solutions,
// whose sources make a chosen smooth field an exact solution of the continuous equations.
//
// Sign convention: the source is the right-hand side of the strong form,
//   momentum      (Re/Gamma) v . grad v - div T = force
//   conformation  v . grad M - L M - M L^T + (f M - I) / lambda_eff = constitutive
//                 (log form: v . grad Psi - T(L, Psi) - (exp(-Psi) - f I) / lambda_eff)
// so the kernels subtract int phi . force and weight the constitutive source like the rest of
// that equation (Galerkin plus SUPG), which keeps SUPG consistent.
//
// A source is data, not a function of the unknowns: on a moving mesh it is evaluated at the
// Gauss points' current positions, but its dependence on the node positions is not in the
// Jacobian (manufactured solutions hold the positions fixed).
#pragma once

#include <functional>

namespace keller {

struct FlowSource {
  // force[0..1] at position x; empty: no body force
  std::function<void(const double (&x)[2], double (&force)[2])> momentum;
  // the source of conformation component c (xx, xy, yy, zz, in the unknowns' order) at x;
  // empty: none
  std::function<void(const double (&x)[2], double (&source)[4])> constitutive;
};

}  // namespace keller
