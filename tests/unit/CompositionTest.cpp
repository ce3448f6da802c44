// Problems composed of components, and quantities declared by name: a Composition orders the
// fields as added, builds the components in that order and tells each which position rows the
// ones before it own; a Quantities evaluates one quantity without the others; and the
// collapsible channel's observables and monitors by name are bit for bit the ones of a whole
// evaluation.
#include <gtest/gtest.h>

#include <stdexcept>

#include "core/Quantities.hpp"
#include "problems/channel/ChannelMesh.hpp"
#include "problems/channel/CollapsibleChannelProblem.hpp"
#include "problems/components/Composition.hpp"

using namespace keller;

namespace {

// A component that records what it saw when built; its one term is named after it.
class Recorder final : public Component {
 public:
  Recorder(std::string name, std::vector<FieldSpec> fields, std::vector<int> owns, std::vector<std::string>* log)
      : name_(std::move(name)), fields_(std::move(fields)), owns_(std::move(owns)), log_(log) {}
  std::string name() const override { return name_; }
  std::vector<FieldSpec> fields() const override { return fields_; }
  void build(const ComponentBuild& b) override {
    log_->push_back(name_);
    seen_owned = b.owned_position_nodes;
    seen_moving = b.moving_mesh;
    terms_.push_back(std::make_shared<DirichletTerm>(name_ + "-term", b.params));
  }
  const std::vector<std::shared_ptr<const Term>>& terms() const override { return terms_; }
  std::vector<int> position_nodes() const override { return owns_; }
  std::vector<int> seen_owned;
  bool seen_moving = false;

 private:
  std::string name_;
  std::vector<FieldSpec> fields_;
  std::vector<int> owns_;
  std::vector<std::string>* log_;
  std::vector<std::shared_ptr<const Term>> terms_;
};

ChannelMeshSpec tiny_mesh() {
  ChannelMeshSpec s;
  s.name = "custom";
  s.nx_upstream = 1;
  s.nx_deformable = 3;
  s.nx_downstream = 1;
  s.ny_fluid = 2;
  s.ny_solid = 1;
  return s;
}

}  // namespace

TEST(Quantities, OneByNameComputesThatOneAlone) {
  Quantities q;
  int calls[3] = {0, 0, 0};
  q.add("a", [&](const Vector& u) { return ++calls[0], u[0]; });
  q.add("b", [&](const Vector& u) { return ++calls[1], 2.0 * u[0]; });
  q.add("c", [&](const Vector& u) { return ++calls[2], 3.0 * u[0]; });
  const Vector u = Vector::Constant(1, 1.5);
  EXPECT_EQ(q.value("b", u), 3.0);
  EXPECT_EQ(calls[0], 0);
  EXPECT_EQ(calls[1], 1);
  EXPECT_EQ(calls[2], 0);
  std::vector<double> all;
  q.evaluate(u, all);
  EXPECT_EQ(all, (std::vector<double>{1.5, 3.0, 4.5}));
  EXPECT_EQ(q.names(), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_THROW(q.value("d", u), std::invalid_argument);
  EXPECT_THROW(q.add("a", [](const Vector&) { return 0.0; }), std::invalid_argument);
}

TEST(Composition, FieldsInOrderComponentsBuiltInOrderOwnedPositionsPassedOn) {
  const Mesh mesh = build_channel_mesh(ChannelGeometry{}, tiny_mesh(), true);
  ParameterSet params;
  std::vector<std::string> log;
  Recorder first("first", {{"velocity", Basis::Q2, {"vx", "vy"}, {"fluid"}}}, {}, &log);
  Recorder second("second", {{"solid_pressure", Basis::P1Disc, {"pi"}, {"solid"}}}, {9, 4, 7}, &log);
  Recorder third("third", {}, {2}, &log);
  Recorder fourth("fourth", {}, {}, &log);
  ComposedSystem s = Composition()
                         .add(first)
                         .share({"position", Basis::Q2, {"x", "y"}, {"fluid", "solid"}})
                         .add(second)
                         .add(third)
                         .add(fourth)
                         .build(mesh, params, "clamps");
  ASSERT_EQ(s.dofs->num_fields(), 3);
  EXPECT_EQ(s.dofs->field(0).name, "velocity");
  EXPECT_EQ(s.dofs->field(1).name, "position");
  EXPECT_EQ(s.dofs->field(2).name, "solid_pressure");
  EXPECT_EQ(log, (std::vector<std::string>{"first", "second", "third", "fourth"}));
  EXPECT_TRUE(first.seen_moving);
  EXPECT_TRUE(first.seen_owned.empty());
  EXPECT_TRUE(second.seen_owned.empty());
  EXPECT_EQ(third.seen_owned, (std::vector<int>{4, 7, 9}));  // sorted: the assembler's rows look them up
  EXPECT_EQ(fourth.seen_owned, (std::vector<int>{2, 4, 7, 9}));
  const auto extra = std::make_shared<DirichletTerm>("extra", params);
  std::vector<std::string> names;
  for (const auto& t : s.terms({extra})) names.push_back(t->name());
  EXPECT_EQ(names,
            (std::vector<std::string>{"first-term", "second-term", "third-term", "fourth-term", "extra", "clamps"}));

  std::vector<std::string> log2;
  Recorder alone("alone", {{"velocity", Basis::Q2, {"vx", "vy"}, {"fluid"}}}, {}, &log2);
  const ComposedSystem fixed = Composition().add(alone).build(mesh, params);
  EXPECT_FALSE(alone.seen_moving);  // no position field: a fixed mesh
  EXPECT_EQ(fixed.terms().back()->name(), "dirichlet");
}

TEST(Observables, CollapsibleChannelByNameEqualsTheWholeEvaluation) {
  CollapsibleOptions o;
  o.mesh = tiny_mesh();
  o.Gamma = 0.05;
  o.Pe = 0.3;
  o.fluid.model = FluidModel::OldroydB;
  o.fluid.Wi = 0.7;
  o.fluid.beta = 0.3;
  CollapsibleChannelProblem problem(o);
  Vector u = problem.initial_guess();
  for (int k = 0; k < u.size(); ++k) u[k] += 1e-3 * std::sin(1.0 + k);  // away from the symmetric start
  std::vector<double> all;
  ASSERT_TRUE(problem.observables(u, all).is_ok());
  const std::vector<std::string> names = problem.observable_names();
  ASSERT_EQ(names.size(), all.size());
  EXPECT_EQ(names, (std::vector<std::string>{"dx_max", "dy_max", "gap_min", "dP", "dP_inlet_outlet", "Q_in", "Q_out",
                                             "area_change", "mesh_quality", "min_detF", "min_m1", "max_m3", "x_min_m1",
                                             "y_min_m1", "max_trM"}));
  for (size_t k = 0; k < names.size(); ++k) {
    EXPECT_EQ(problem.observable(names[k], u), all[k]) << names[k];
  }
  std::vector<double> mon;
  ASSERT_TRUE(problem.monitors(u, mon).is_ok());
  EXPECT_EQ(problem.monitor_names(), (std::vector<std::string>{"min_m1"}));
  ASSERT_EQ(mon.size(), 1u);
  EXPECT_EQ(mon[0], all[10]);
  EXPECT_THROW((void)problem.observable("Wi", u), std::invalid_argument);

  o.fluid.model = FluidModel::Newtonian;
  CollapsibleChannelProblem newtonian(o);
  EXPECT_TRUE(newtonian.monitor_names().empty());
  EXPECT_EQ(newtonian.observable_names().size(), 10u);
}
