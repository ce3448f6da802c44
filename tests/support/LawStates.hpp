// A law's terms and polymer stress at a closed-form steady state (problems/laws/SteadyFlows), for
// the tests that compare computed states with those closed forms.
#pragma once

#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/SteadyFlows.hpp"

namespace keller::test {

// The law's terms at a steady state. The FENE laws' f is the state's own: f recomputed from M
// would amplify M's rounding by tr M / (3b - tr M), which nears 1e13 in fast extension (f itself
// is checked against its definition and the FENE-P table in ConstitutiveLawTest).
inline Relaxation<double> terms_at(FluidModel model, const LawConstants<double>& c, const SteadyConformation& s) {
  Relaxation<double> k = relaxation(model, true, Conformation<double>{s.xx, s.xy, s.yy, s.zz}, c);
  if (uses_b(model)) {
    const double f = s.f;
    k = model == FluidModel::FeneP ? Relaxation<double>{-1.0, f, 0.0, -1.0, f, f}
                                   : Relaxation<double>{-f, f, 0.0, -f, f, f};
  }
  return k;
}

// The polymer stress over the modulus, s0 I + s1 M, of a steady state, with those terms.
inline Conformation<double> closed_stress(FluidModel model, const LawConstants<double>& c,
                                          const SteadyConformation& s) {
  return polymer_stress(Conformation<double>{s.xx, s.xy, s.yy, s.zz}, terms_at(model, c, s), 1.0);
}

}  // namespace keller::test
