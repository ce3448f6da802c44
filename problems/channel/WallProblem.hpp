// The deformable wall alone: the neo-Hookean block of the collapsible channel, clamped on its
// sides, with the external follower pressure Pe on its top face and a uniform follower pressure
// Pin on its bottom face (standing in for the fluid). With Pin < Pe the wall bends into the
// channel. Validates the solid before it is coupled (area conservation, large deflections,
// continuation in Pe and in the thickness t).
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/Quantities.hpp"
#include "core/Scene.hpp"
#include "problems/channel/ChannelMesh.hpp"
#include "problems/components/SolidWall.hpp"

namespace keller {

struct WallOptions {
  ChannelGeometry geometry;
  ChannelMeshSpec mesh;
  double Pe = 0.04;
  double Pin = 0.0;
  // The wall's density rho_s W^2 G / eta0^2 (time in eta0 / G): > 0 gives it inertia and the
  // time-dependent form B du/dt = -F (the wall velocity an unknown); 0: quasi-static, no such form.
  double inertia = 0.0;

  static void declare(SceneSchema& schema);
  static WallOptions from_scene(const Scene& scene);
};

class WallProblem final : public AssembledProblem {
 public:
  explicit WallProblem(const WallOptions& options);

  std::string name() const override { return "wall"; }
  Vector initial_guess() override;
  std::vector<std::string> observable_names() const override { return observables_.names(); }
  Status observables(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  const SolidWall& wall() const { return *wall_; }
  // One observable by name, computed alone; throws std::invalid_argument for an unknown name.
  double observable(const std::string& name, const Vector& u) const { return observables_.value(name, u); }

 private:
  WallOptions options_;
  Mesh mesh_;
  std::unique_ptr<SolidWall> wall_;
  int iPin_ = -1;
  std::unique_ptr<DofMap> dofs_;
  std::shared_ptr<DirichletTerm> dirichlet_;
  mutable Mesh deformed_;  // the mesh at the last solution written out
  Quantities observables_;
};

}  // namespace keller
