#include "problems/components/StokesStart.hpp"

#include "core/Newton.hpp"
#include "problems/components/Composition.hpp"
#include "problems/components/FlowEquations.hpp"

namespace keller {

StokesStart::StokesStart(const Mesh& mesh, const std::string& group, const FlowBoundaries& boundaries,
                         double velocity_scale) {
  const int iGamma = params_.add("Gamma", velocity_scale, "velocity scale", Range::positive());
  flow_ = std::make_unique<FlowEquations>(mesh, group, FluidOptions{}, boundaries, params_, iGamma);
  ComposedSystem system = Composition().add(*flow_).build(mesh, params_);
  dofs_ = std::move(system.dofs);
  dirichlet_ = system.dirichlet;
  assemble(dofs_->size(), system.terms());
}

StokesStart::~StokesStart() = default;

Vector StokesStart::initial_guess() {
  Vector u = Vector::Zero(size());
  for (int k = 0; k < dirichlet_->num_items(); ++k) u[dirichlet_->dofs()[k]] = dirichlet_->value(k);
  return u;
}

Status StokesStart::solve(Vector& u) {
  u = initial_guess();
  NewtonSolver newton(*this);
  return newton.solve(u).status;
}

}  // namespace keller
