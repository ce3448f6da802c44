// Where the flow kernels find their parameters in the ParameterSet, and the scales those set
// (model.md units: eta0 = 1, the solvent viscosity is beta, lambda = Wi / Gamma, the polymer
// modulus is (1 - beta) Gamma / Wi). One struct for every fluid: a Newtonian fluid leaves the
// viscoelastic indices at -1.
#pragma once

#include <string>

#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller {

struct FlowParameterIndices {
  int Re = -1;              // -1: no inertia
  int Gamma = -1;           // velocity scale (mean inflow velocity); -1: 1
  int Wi = -1;              // viscoelastic fluids only
  int beta = -1;            // solvent viscosity ratio; -1: beta = 1 (Newtonian)
  LawParameterIndices law;  // the constitutive law's constants (b, alpha, epsilon, xi)
};

template <class P>
P velocity_scale(const FlowParameterIndices& p, const P* params) {
  return p.Gamma >= 0 ? params[p.Gamma] : P(1.0);
}

// Re / Gamma, the factor of the convective term and of dv/dt; 0 without inertia.
template <class P>
P flow_density(const FlowParameterIndices& p, const P* params, bool inertia) {
  return inertia ? P(params[p.Re] / velocity_scale(p, params)) : P(0.0);
}

template <class P>
P solvent_viscosity(const FlowParameterIndices& p, const P* params) {
  return p.beta >= 0 ? params[p.beta] : P(1.0);
}

// The polymer modulus (1 - beta) Gamma / Wi of tau_p = modulus (s0 I + s1 M).
template <class P>
P polymer_modulus(const FlowParameterIndices& p, const P* params) {
  return (1.0 - params[p.beta]) * velocity_scale(p, params) / params[p.Wi];
}

// One mode of a multi-mode fluid: its conformation field, where its time ratio t_k is among the
// parameters (-1: t_k = 1) and its share w_k of the polymer viscosity. The mode relaxes in
// lambda_k = t_k lambda with modulus w_k (1 - beta) Gamma / (t_k Wi), so that its polymer
// viscosity is w_k (1 - beta). A one-mode fluid is the default mode, whose scales are bitwise
// those of a fluid without modes.
struct PolymerMode {
  std::string field = "conformation";
  int time = -1;
  double share = 1.0;
};

template <class P>
P mode_relaxation_time(const P& lambda, const PolymerMode& m, const P* params) {
  return m.time >= 0 ? P(lambda * params[m.time]) : lambda;
}

template <class P>
P mode_modulus(const P& modulus, const PolymerMode& m, const P* params) {
  P g = modulus;
  if (m.share != 1.0) g = g * m.share;
  if (m.time >= 0) g = g / params[m.time];
  return g;
}

}  // namespace keller
