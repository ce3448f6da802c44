// Steady flow in the channel of model.md with rigid walls: Stokes (Re = 0) or Navier-Stokes
// (Re > 0) for a Newtonian fluid. The inflow carries a fully developed profile of mean Gamma,
// walls are no-slip, the outflow is fully developed with the pressure datum P = 0 there
// (natural condition T_xx = 0 and v_y = 0). Only the fields and terms the scene asks for exist:
// the convective term is assembled only when inertia is on.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "core/Assembler.hpp"
#include "core/DirichletTerm.hpp"
#include "core/DofMap.hpp"
#include "core/PointLocator.hpp"
#include "core/Problem.hpp"
#include "core/Scene.hpp"
#include "problems/ChannelMesh.hpp"

namespace keller {

struct ChannelOptions {
  ChannelGeometry geometry;
  ChannelMeshSpec mesh;
  std::string fluid_model = "newtonian";
  std::string inflow_profile = "parabolic";
  double Re = 0.0;
  double Gamma = 4.95e-4;
  bool inertia = false;  // assemble (Re/Gamma) v . grad v; true when Re > 0 in the scene

  static void declare(SceneSchema& schema);
  static ChannelOptions from_scene(const Scene& scene);
};

class ChannelProblem final : public Problem {
 public:
  explicit ChannelProblem(const ChannelOptions& options);
  // With a given mesh (blocks and boundaries as build_channel_mesh names them), e.g. a
  // distorted one in tests.
  ChannelProblem(const ChannelOptions& options, Mesh mesh);
  ChannelProblem(const ChannelProblem&) = delete;
  ChannelProblem& operator=(const ChannelProblem&) = delete;

  std::string name() const override { return "channel"; }
  int size() const override { return dofs_->size(); }
  ParameterSet& parameters() override { return params_; }
  const ParameterSet& parameters() const override { return params_; }
  const SparseMatrix& jacobian_pattern() const override { return assembler_->pattern(); }
  Status residual(const Vector& u, Vector& F) override;
  Status jacobian(const Vector& u, Vector& F, SparseMatrix& J) override;
  Status parameter_derivative(int p, const Vector& u, Vector& dF) override;
  Status mass_matrix(const Vector& u, SparseMatrix& B) override { return assembler_->mass_matrix(u, B); }
  Vector initial_guess() override;
  double residual_scale() const override;
  std::vector<std::string> observable_names() const override;
  Status observables(const Vector& u, std::vector<double>& values) override;
  SolutionFields fields(const Vector& u) const override;
  std::string summary() const override;

  const Mesh& mesh() const { return mesh_; }
  const DofMap& dofs() const { return *dofs_; }
  const Assembler& assembler() const { return *assembler_; }
  const ChannelOptions& options() const { return options_; }
  // Fully developed inflow velocity v_x(y) at the current Gamma.
  double inflow_velocity(double y) const;
  // Mean pressure over the cross-section x = x0 (0 <= y <= 1), sampled with a composite Gauss
  // rule; where the section runs along element edges the one-sided values are averaged.
  double section_pressure(const Vector& u, double x0) const;
  // Flow rate int v . n ds (n towards +x) through every vertical mesh line, upstream to
  // downstream: the discrete continuity equation makes these equal to rounding.
  std::vector<double> column_flow_rates(const Vector& u) const;

 private:
  void setup();
  double pressure_at(const Vector& u, const MeshPoint& p) const;

  ChannelOptions options_;
  Mesh mesh_;
  std::unique_ptr<DofMap> dofs_;
  ParameterSet params_;
  int iRe_ = -1, iGamma_ = -1;
  std::vector<int> fluid_elements_;
  std::vector<std::array<QpGeometry<double>, ref::kQp>> geometry_;
  std::shared_ptr<DirichletTerm> dirichlet_;
  std::unique_ptr<Assembler> assembler_;
  std::unique_ptr<PointLocator> locator_;
};

}  // namespace keller
