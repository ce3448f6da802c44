// The 2D Bratu problem  Laplace(u) + lambda e^u = 0 on the unit square, u = 0 on the boundary,
// with Q2 finite elements on a uniform n x n mesh (weak form: int grad u . grad phi
// - lambda e^u phi = 0). Fold at lambda_c = 6.8081244226 with max u = 1.39166121 there.
// Exercises the whole finite-element path (mesh, dof map, AD kernel, assembly, UMFPACK).
#pragma once

#include <memory>

#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Scene.hpp"

namespace keller {

class Bratu2DProblem final : public AssembledProblem {
 public:
  static constexpr int max_elements_per_side = 4000;
  Bratu2DProblem(int elements_per_side, double lambda);

  std::string name() const override { return "bratu2d"; }
  Vector initial_guess() override { return Vector::Zero(size()); }
  std::vector<std::string> observable_names() const override { return {"u_max", "u_centre"}; }
  Status observables(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override { return extract_fields(mesh_, *dofs_, u); }
  std::string summary() const override;

  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  // Value of the finite-element solution at a point (x, y) in the unit square.
  double evaluate(const Vector& u, double x, double y) const;

  static constexpr double kLambdaCritical = 6.8081244226;
  // Reads the [bratu] keys that Bratu1DProblem::declare declares for both problems.
  static std::unique_ptr<Problem> from_scene(const Scene& scene);

 private:
  int n_;
  Mesh mesh_;
  std::unique_ptr<DofMap> dofs_;
  std::vector<std::array<QpGeometry<double>, ref::kQp>> geometry_;
  std::shared_ptr<DirichletTerm> dirichlet_;
};

}  // namespace keller
