#include "continuation/engine/FixedParameterSolve.hpp"

#include <chrono>

#include "continuation/engine/ArclengthNorm.hpp"
#include "continuation/engine/ContinuationOptions.hpp"
#include "continuation/engine/Corrector.hpp"
#include "continuation/engine/Evaluator.hpp"
#include "continuation/engine/KeptFactorisation.hpp"

namespace keller {

FixedParameterResult solve_at_fixed_parameter(Problem& problem, const std::string& parameter, Vector& u,
                                              const NewtonOptions& newton, const SparseLUOptions& lu,
                                              const StartFactorisation& near) {
  const auto t0 = std::chrono::steady_clock::now();
  ContinuationOptions o;
  o.parameter = parameter;
  o.corrector.method = near.lu ? CorrectorOptions::Method::Chord : CorrectorOptions::Method::Newton;
  if (!near.lu) o.corrector.max_iterations = newton.max_iterations;
  const int p = problem.parameters().index(parameter);
  Evaluator ev(problem, p, parameter);
  KeptFactorisation kept(problem, lu, o.corrector.block_elimination);
  const ArclengthNorm norm(problem.size(), 1.0, o.theta);  // (Deuflhard's test: steps only)
  Corrector corrector(ev, kept, norm, o, newton);
  double value = problem.parameters().value(p);
  const Constraint row = Constraint::parameter(value);
  // the chord starts on the nearby factorisation, the border evaluated at u (where it cannot be
  // adopted, the chord's first iteration factorises)
  if (near.lu) kept.adopt_at(ev, near, u, value, row);
  const CorrectorResult r = corrector.correct(u, value, row, Corrector::Kind::Located);
  FixedParameterResult out;
  out.status = r.status;
  out.iterations = r.iterations;
  out.factorisations = kept.count();
  out.factorisation = kept.inner_factorisation();
  // (the run's measured renewal cost passed on: a solve's own timings are too few to measure it)
  if (out.factorisation.lu) out.factorisation.renewal_cost = near.renewal_cost;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

}  // namespace keller
