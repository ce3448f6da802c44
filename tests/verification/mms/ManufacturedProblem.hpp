// A manufactured-solution problem: the project's flow kernels (Newtonian, or viscoelastic by
// DEVSS-TG/SUPG in conformation or log-conformation form, on a fixed mesh or with the node
// positions as unknowns) on an n x n mesh of a non-affinely mapped square, with the sources of
// StrongForm and boundary data from the exact solution: v on the whole boundary, the
// conformation unknowns on the inflow part (edges with v . n < 0 at their midpoint), and the
// pressure datum through one coefficient (the mean of element 0, whose continuity row it
// replaces). On a moving mesh the mesh is the unit square, its positions are unknowns held by
// Dirichlet rows at the map's image of its nodes (a prescribed non-affine motion), and the
// fields are those of the deformed domain: the discrete problem is then the fixed-mesh one on
// the mapped mesh, reached through the kernels' moving-mesh form. Errors of the discrete
// solution are measured on a 5x5 Gauss rule per element.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "ManufacturedFields.hpp"
#include "StrongForm.hpp"
#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Mesh.hpp"
#include "problems/kernels/ViscoelasticFlowKernel.hpp"

namespace keller::mms {

// The map of the unit square the mesh lives on (ManufacturedFields.hpp).
enum class SquareMap { Distorted, Collapsed };

struct ManufacturedOptions {
  FluidSpec fluid;
  int n = 8;  // elements per side
  SquareMap map = SquareMap::Distorted;
  // positions as unknowns (the Moving kernels) on a mesh of the unit square, held at the map's
  // image of its nodes: the map is then the prescribed mesh motion
  bool moving = false;
  ViscoelasticKernelOptions kernel;  // SUPG and DEVSS settings (model and formulation from fluid)
};

// Relative errors of one field: L2 norm of the error over the L2 norm of the exact field, and
// the largest error at the 5x5 Gauss points over the largest exact value there (vector fields:
// the Euclidean norm of the components at a point).
struct FieldError {
  double l2 = 0, max = 0;
};
struct Errors {
  FieldError velocity, pressure, gradient, conformation;  // conformation: M, or Psi in the log form
};

class ManufacturedProblem final : public AssembledProblem {
 public:
  explicit ManufacturedProblem(const ManufacturedOptions& options);

  std::string name() const override { return "manufactured"; }
  // The exact solution interpolated: nodal values, and the pressure's value and gradient at
  // each element's centre node.
  Vector initial_guess() override;
  SolutionFields fields(const Vector& u) const override { return extract_fields(mesh_, *dofs_, u); }

  Errors errors(const Vector& u) const;
  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  const StrongForm<ManufacturedFields>& strong_form() const { return strong_; }

 private:
  // Physical position of mesh node n: the mesh's own, or its image under the prescribed motion.
  Mesh::Point position(int n) const;
  // Exact values of the unknowns at a point: v (2), P, L = K (4), conformation unknowns (4).
  void exact(const double (&x)[2], double (&v)[2], double& P, double (&L)[4], double (&c)[4]) const;

  ManufacturedOptions options_;
  StrongForm<ManufacturedFields> strong_;
  Mesh mesh_;
  std::unique_ptr<DofMap> dofs_;
  std::vector<int> elements_;
  std::vector<std::array<QpGeometry<double>, ref::kQp>> geometry_;
  std::shared_ptr<DirichletTerm> dirichlet_;
};

}  // namespace keller::mms
