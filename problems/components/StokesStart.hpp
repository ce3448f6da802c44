// A starting state for steady flow in any geometry: creeping flow of a Newtonian fluid of
// viscosity 1 (the zero-shear viscosity eta0 = 1 of every keller fluid) under the same boundary
// conditions, one linear solve. Started from it (with the relaxed conformation), Newton reaches
// viscoelastic steady states that it does not reach from rest or from an inflow profile
// continued downstream (docs/boundaries.md has the measurements).
#pragma once

#include <memory>
#include <string>

#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "core/Status.hpp"
#include "problems/components/FlowBoundaries.hpp"

namespace keller {

class FlowEquations;

class StokesStart final : public AssembledProblem {
 public:
  // velocity_scale: the value of the flow's velocity scale (its boundary velocities' factor).
  StokesStart(const Mesh& mesh, const std::string& group, const FlowBoundaries& boundaries, double velocity_scale);
  ~StokesStart() override;

  std::string name() const override { return "stokes-start"; }
  // At rest with the boundary values.
  Vector initial_guess() override;
  // The Stokes flow, in this problem's unknowns (dofs()).
  Status solve(Vector& u);
  const DofMap& dofs() const { return *dofs_; }

 private:
  std::unique_ptr<FlowEquations> flow_;
  std::unique_ptr<DofMap> dofs_;
  std::shared_ptr<DirichletTerm> dirichlet_;
};

}  // namespace keller
