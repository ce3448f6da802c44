#include "continuation/FixedParameterSolve.hpp"

#include "continuation/ArclengthNorm.hpp"
#include "continuation/ContinuationOptions.hpp"
#include "continuation/Corrector.hpp"
#include "continuation/Evaluator.hpp"
#include "continuation/KeptFactorisation.hpp"

namespace keller {

FixedParameterResult solve_at_fixed_parameter(Problem& problem, const std::string& parameter, Vector& u,
                                              const NewtonOptions& newton, const SparseLUOptions& lu) {
  ContinuationOptions o;
  o.parameter = parameter;
  o.corrector.method = CorrectorOptions::Method::Newton;
  o.corrector.max_iterations = newton.max_iterations;
  const int p = problem.parameters().index(parameter);
  Evaluator ev(problem, p, parameter);
  KeptFactorisation kept(problem, lu, o.corrector.block_elimination);
  const ArclengthNorm norm(problem.size(), 1.0, o.theta);  // (unused by Newton iterations)
  Corrector corrector(ev, kept, norm, o, newton);
  double value = problem.parameters().value(p);
  const CorrectorResult r = corrector.correct(u, value, Constraint::parameter(value), Corrector::Kind::Step);
  FixedParameterResult out;
  out.status = r.status;
  out.iterations = r.iterations;
  out.factorisations = kept.count();
  return out;
}

}  // namespace keller
