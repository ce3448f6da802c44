#include "problems/components/FluidMeshMotion.hpp"

#include <algorithm>
#include <cmath>
#include <set>

#include "core/ElementGeometry.hpp"
#include "core/KernelTerm.hpp"
#include "problems/kernels/EllipticMeshKernel.hpp"

namespace keller {

void MeshMotionOptions::declare(SceneSchema& s) {
  s.section("mesh_motion", "the elliptic equations that move the fluid mesh with the wall");
  s.string("mesh_motion.wall_nodes", "sliding",
           "rigid-wall nodes slide along the wall (mesh lines meet it orthogonally) or stay fixed",
           {"sliding", "fixed"});
}

MeshMotionOptions MeshMotionOptions::from_scene(const Scene& scene) {
  MeshMotionOptions o;
  o.sliding_walls = scene.string("mesh_motion.wall_nodes") == "sliding";
  return o;
}

FluidMeshMotion::FluidMeshMotion(const Mesh& mesh, const std::string& group, MeshMotionOptions options,
                                 MeshMotionBoundaries boundaries)
    : mesh_(&mesh), options_(options), boundaries_(std::move(boundaries)) {
  elements_ = mesh.elements_in_group(mesh.group_index(group));
}

void FluidMeshMotion::build(const ComponentBuild& b) {
  const DofMap& dofs = b.dofs;
  DirichletTerm& dirichlet = b.dirichlet;
  const ParameterSet& params = b.params;
  const std::vector<int>& owned_nodes = b.owned_position_nodes;
  terms_.push_back(std::make_shared<KernelTerm<EllipticMeshKernel>>(
      EllipticMeshKernel(*mesh_, dofs, elements_, owned_nodes), params));
  const int fx = dofs.field_index("position");
  auto owned = [&](int n) { return std::binary_search(owned_nodes.begin(), owned_nodes.end(), n); };
  std::set<int> fix_x, fix_y;
  for (const auto& w : boundaries_.walls)
    for (int n : mesh_->boundary_nodes(w)) {
      fix_y.insert(n);
      if (!options_.sliding_walls) fix_x.insert(n);
    }
  for (const auto& end : boundaries_.ends)
    for (int n : mesh_->boundary_nodes(end)) {
      fix_x.insert(n);
      fix_y.insert(n);
    }
  for (int n : fix_x)
    if (!owned(n)) dirichlet.add(dofs.node_dof(fx, n, 0), mesh_->node(n)[0]);
  for (int n : fix_y)
    if (!owned(n)) dirichlet.add(dofs.node_dof(fx, n, 1), mesh_->node(n)[1]);
}

void FluidMeshMotion::generated_state(const DofMap& dofs, Vector& u) const {
  const int fx = dofs.field_index("position");
  for (int e : elements_)
    for (int n : mesh_->element(e))
      for (int i = 0; i < 2; ++i) u[dofs.node_dof(fx, n, i)] = mesh_->node(n)[i];
}

double FluidMeshMotion::min_relative_jacobian(const DofMap& dofs, const Vector& u) const {
  const int fx = dofs.field_index("position");
  const ref::Tables& tb = ref::tables();
  double m = INFINITY;
  for (int e : elements_) {
    double xy[9][2], X[9][2];
    mesh_->element_nodes(e, X);
    for (int a = 0; a < 9; ++a)
      for (int i = 0; i < 2; ++i) xy[a][i] = u[dofs.node_dof(fx, mesh_->element(e)[a], i)];
    for (int q = 0; q < ref::kQp; ++q) {
      double J[2][2] = {{0, 0}, {0, 0}}, J0[2][2] = {{0, 0}, {0, 0}};
      for (int a = 0; a < 9; ++a)
        for (int i = 0; i < 2; ++i)
          for (int j = 0; j < 2; ++j) {
            J[i][j] += xy[a][i] * tb.dN2[q][a][j];
            J0[i][j] += X[a][i] * tb.dN2[q][a][j];
          }
      m = std::min(m, (J[0][0] * J[1][1] - J[0][1] * J[1][0]) / (J0[0][0] * J0[1][1] - J0[0][1] * J0[1][0]));
    }
  }
  return m;
}

}  // namespace keller
