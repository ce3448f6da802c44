// Steady flow in the channel of model.md with rigid walls, for any of the four fluids (Stokes,
// or Navier-Stokes when Re > 0). The inflow carries a fully developed profile of mean Gamma and,
// for viscoelastic fluids, the local steady-shear conformation; walls are no-slip; the outflow
// is fully developed with the pressure datum P = 0 there (v_y = 0 and the natural condition
// with the polymer traction). Only the fields and terms the scene asks for exist.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/AssembledProblem.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/PointLocator.hpp"
#include "core/Quantities.hpp"
#include "core/Scene.hpp"
#include "problems/channel/ChannelMesh.hpp"
#include "problems/components/FlowEquations.hpp"

namespace keller {

struct ChannelOptions {
  ChannelGeometry geometry;
  ChannelMeshSpec mesh;
  FluidOptions fluid;
  double Gamma = 4.95e-4;

  static void declare(SceneSchema& schema);
  static ChannelOptions from_scene(const Scene& scene);
};

class ChannelProblem final : public AssembledProblem {
 public:
  explicit ChannelProblem(const ChannelOptions& options);
  // With a given mesh (blocks and boundaries as build_channel_mesh names them), e.g. a
  // distorted one in tests.
  ChannelProblem(const ChannelOptions& options, Mesh mesh);

  std::string name() const override { return "channel"; }
  Vector initial_guess() override;
  double residual_scale() const override;
  std::vector<std::string> observable_names() const override { return observables_.names(); }
  Status observables(const Vector& u, std::vector<double>& values) override;
  // min_m1 for a viscoelastic fluid: zero where M loses positive definiteness.
  std::vector<std::string> monitor_names() const override { return monitors_.names(); }
  Status monitors(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  const ChannelOptions& options() const { return options_; }
  const FlowEquations& flow() const { return *flow_; }
  // One observable by name, computed alone; throws std::invalid_argument for an unknown name.
  double observable(const std::string& name, const Vector& u) const { return observables_.value(name, u); }
  // Mean pressure over the cross-section x = x0 (0 <= y <= 1), sampled with a composite Gauss
  // rule; where the section runs along element edges the one-sided values are averaged.
  double section_pressure(const Vector& u, double x0) const;
  // Flow rate int v . n ds (n towards +x) through every vertical mesh line, upstream to
  // downstream: the discrete continuity equation makes these equal to rounding.
  std::vector<double> column_flow_rates(const Vector& u) const;

 private:
  void setup();
  void declare_quantities();
  double pressure_at(const Vector& u, const MeshPoint& p) const;

  ChannelOptions options_;
  Mesh mesh_;
  std::unique_ptr<DofMap> dofs_;
  int iGamma_ = -1;
  std::unique_ptr<FlowEquations> flow_;
  std::shared_ptr<DirichletTerm> dirichlet_;
  std::unique_ptr<PointLocator> locator_;
  Quantities observables_, monitors_;
};

}  // namespace keller
