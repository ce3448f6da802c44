#include "problems/components/FlowEquations.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>

#include "core/KernelTerm.hpp"
#include "core/RateConstraintTerm.hpp"
#include "problems/components/StokesStart.hpp"
#include "problems/kernels/NewtonianFlowKernel.hpp"
#include "problems/kernels/OutflowTractionKernel.hpp"
#include "problems/kernels/TractionKernel.hpp"
#include "problems/laws/LawKeys.hpp"
#include "problems/laws/LogConformation.hpp"
#include "problems/laws/SteadyFlows.hpp"

namespace keller {

FlowEquations::FlowEquations(const Mesh& mesh, const std::string& group, FluidOptions options,
                             FlowBoundaries boundaries, ParameterSet& params, int iGamma)
    : mesh_(&mesh), group_(group), options_(std::move(options)), boundaries_(std::move(boundaries)), params_(&params) {
  index_.Gamma = iGamma;
  // without the convective term Re stays 0: a run that sets it (a curve's second parameter) is refused
  // instead of computing Stokes flow at every Re
  index_.Re = options_.inertia
                  ? params.add("Re", options_.Re, "Reynolds number", Range::non_negative())
                  : params.add("Re", options_.Re,
                               "Reynolds number; 0 in this run: Stokes flow, the convective term not assembled "
                               "(parameters.Re > 0 or continuation.parameter = \"Re\" assembles it)",
                               Range::between(0.0, 0.0));
  if (options_.Re > 0 && !options_.inertia) throw std::invalid_argument("Re > 0 needs the convective term");
  if (options_.viscoelastic()) {
    index_.Wi = params.add("Wi", options_.Wi, "Weissenberg number", Range::positive());
    index_.beta = params.add("beta", options_.beta, "viscosity ratio eta_s / eta0", Range{0.0, 1.0, true, false});
    index_.law = add_law_parameters(params, options_.model, options_.log_conformation, options_.constants);
    const std::vector<int> times = add_mode_parameters(params, options_.modes);
    modes_.resize(std::max<size_t>(1, times.size()));
    for (size_t k = 0; k < times.size(); ++k)
      modes_[k] = {k == 0 ? "conformation" : "conformation_" + options_.modes[k].name, times[k],
                   options_.modes[k].viscosity};
  }
  elements_ = mesh.elements_in_group(mesh.group_index(group));
  geometry_.resize(elements_.size());
  double area = 0;
  for (size_t k = 0; k < elements_.size(); ++k) {
    double xy[9][2];
    mesh.element_nodes(elements_[k], xy);
    if (!map_element(xy, geometry_[k]))
      throw std::invalid_argument(fmt::format("element {} is inverted or degenerate", elements_[k]));
    for (const auto& g : geometry_[k]) area += g.wdetJ;
  }
  options_.kernel.model = options_.model;
  options_.kernel.log_conformation = options_.log_conformation;
  options_.kernel.inertia = options_.inertia;
  options_.kernel.supg.global_size = std::sqrt(area / static_cast<double>(elements_.size()));

  fields_ = {{"velocity", Basis::Q2, {"vx", "vy"}, {group}}, {"pressure", Basis::P1Disc, {"p"}, {group}}};
  if (options_.viscoelastic()) {
    fields_.push_back({"gradient", Basis::Q1, {"Lxx", "Lxy", "Lyx", "Lyy"}, {group}});
    std::vector<std::string> comps = options_.log_conformation ? std::vector<std::string>{"Psi_xx", "Psi_xy", "Psi_yy"}
                                                               : std::vector<std::string>{"Mxx", "Mxy", "Myy"};
    if (options_.conformation_components() == 4) comps.push_back(options_.log_conformation ? "Psi_zz" : "Mzz");
    for (const PolymerMode& m : modes_) fields_.push_back({m.field, Basis::Q1, comps, {group}});
  }
  boundaries_.validate(mesh);
  for (const InflowCondition& c : boundaries_.inflows) {
    Inflow in;
    in.nodes = mesh.boundary_nodes(c.boundary);
    if (c.fully_developed) {
      in.frame = InflowFrame::of(mesh, c.boundary, boundaries_.symmetry);
      in.profile.kind = options_.profile;
      in.profile.y_lo = in.frame.lo;
      in.profile.y_hi = in.frame.hi;
      in.profile.power_index = options_.power_index;
      for (int n : in.nodes) in.across.push_back(in.frame.across(mesh.node(n)));
    }
    inflows_.push_back(std::move(in));
  }
  for (const std::string& s : boundaries_.symmetry) axis_normal_components(mesh, s, "symmetry line");
  for (const OutflowCondition& c : boundaries_.outflows)
    if (c.fully_developed) axis_normal_components(mesh, c.boundary, "fully developed outflow");
}

double FlowEquations::velocity_scale() const { return index_.Gamma >= 0 ? params_->value(index_.Gamma) : 1.0; }

std::function<double(double)> FlowEquations::viscosity(const ParameterSet& p) const {
  const FluidModel model = options_.model;
  const double Gamma = index_.Gamma >= 0 ? p.value(index_.Gamma) : 1.0;
  const double Wi = index_.Wi >= 0 ? p.value(index_.Wi) : 0.0, beta = index_.beta >= 0 ? p.value(index_.beta) : 1.0;
  const LawConstants<double> law = law_constants(index_.law, p.values());
  const OwensParameters owens = options_.kernel.owens;
  if (modes_.size() <= 1) return [=](double gdot) { return shear_viscosity(model, gdot, Wi, Gamma, beta, law, owens); };
  // the modes' polymer viscosities, each at its own Wi_k = t_k Wi
  std::vector<std::pair<double, double>> modes;  // (t_k Wi, w_k)
  for (const PolymerMode& m : modes_) modes.emplace_back(Wi * p.value(m.time), m.share);
  return [=](double gdot) {
    double eta_p = 0.0;
    for (const auto& [W, share] : modes) eta_p += share * shear_viscosity(model, gdot, W, Gamma, 0.0, law, owens);
    return beta + (1.0 - beta) * eta_p;
  };
}

std::array<double, 4> FlowEquations::mode_shear_state(const ParameterSet& p, size_t mode, double gdot,
                                                      const LawConstants<double>& law) const {
  const double U = index_.Gamma >= 0 ? p.value(index_.Gamma) : 1.0;
  double lam = mode_relaxation_time(p.value(index_.Wi) / U, modes_[mode], p.values());
  if (options_.model == FluidModel::Owens) lam *= owens_factor(gdot * gdot, U, options_.kernel.owens);
  return steady_state(lam * gdot, law);
}

std::array<double, 4> FlowEquations::steady_state(double W, const LawConstants<double>& law) const {
  const SteadyConformation s = steady_shear(options_.model, W, law);
  if (!options_.log_conformation) return {s.xx, s.xy, s.yy, s.zz};
  const Sym2<double> l = sym_log({s.xx, s.xy, s.yy});
  return {l.xx, l.xy, l.yy, std::log(s.zz)};
}

const FlowEquations::InflowValues& FlowEquations::inflow_values(const ParameterSet& p) const {
  const std::vector<double> key(p.values(), p.values() + p.size());
  for (const auto& [k, v] : inflow_cache_)
    if (k == key) return v;
  InflowValues iv;
  const double U = index_.Gamma >= 0 ? p.value(index_.Gamma) : 1.0;
  const bool ve = options_.viscoelastic();
  const LawConstants<double> b = law_constants(index_.law, p.values());
  iv.conformation.resize(modes_.size());
  for (size_t k = 0; k < inflows_.size(); ++k) {
    const InflowCondition& c = boundaries_.inflows[k];
    const Inflow& in = inflows_[k];
    auto& vel = iv.velocity.emplace_back();
    for (auto& mode : iv.conformation) mode.emplace_back();
    if (!c.fully_developed) {
      vel.assign(in.nodes.size(), {c.velocity[0] * U, c.velocity[1] * U});
      if (ve)
        for (auto& mode : iv.conformation) mode[k].assign(in.nodes.size(), steady_state(0.0, b));
      continue;
    }
    // a profile leaving the domain is the entering one reversed
    const double mean = U * c.mean_velocity, sign = mean < 0 ? -1.0 : 1.0;
    std::vector<double> u, dudy;
    in.profile.evaluate(in.across, sign * mean, viscosity(p), u, dudy);
    for (size_t i = 0; i < u.size(); ++i)
      vel.push_back({sign * u[i] * in.frame.normal[0], sign * u[i] * in.frame.normal[1]});
    if (!ve || mean < 0) continue;
    for (size_t mode = 0; mode < modes_.size(); ++mode)
      for (double g : dudy) iv.conformation[mode][k].push_back(in.frame.rotate(mode_shear_state(p, mode, g, b)));
  }
  if (inflow_cache_.size() >= 4) inflow_cache_.erase(inflow_cache_.begin());
  inflow_cache_.emplace_back(key, std::move(iv));
  return inflow_cache_.back().second;
}

template <int NC, bool Moving>
void FlowEquations::add_viscoelastic_kernels(const DofMap& dofs, const std::vector<BoundaryEdge>& outflow) {
  const ParameterSet& params = *params_;
  for (size_t k = 0; k < modes_.size(); ++k) {
    ViscoelasticKernelOptions o = options_.kernel;
    o.mode = modes_[k];
    if (k == 0)
      terms_.push_back(std::make_shared<KernelTerm<ViscoelasticFlowKernel<NC, Moving>>>(
          ViscoelasticFlowKernel<NC, Moving>(*mesh_, dofs, elements_, &geometry_, index_, o), params));
    else
      terms_.push_back(std::make_shared<KernelTerm<PolymerModeKernel<NC, Moving>>>(
          PolymerModeKernel<NC, Moving>(*mesh_, dofs, elements_, &geometry_, index_, o), params));
    if (!outflow.empty())
      terms_.push_back(std::make_shared<KernelTerm<OutflowTractionKernel<NC>>>(
          OutflowTractionKernel<NC>(*mesh_, dofs, outflow, index_, o), params));
  }
}

template <bool Moving>
void FlowEquations::add_kernels(const DofMap& dofs) {
  const ParameterSet& params = *params_;
  std::vector<BoundaryEdge> outflow;  // of the fully developed outflows
  for (const OutflowCondition& c : boundaries_.outflows)
    if (c.fully_developed)
      outflow.insert(outflow.end(), mesh_->boundary(c.boundary).begin(), mesh_->boundary(c.boundary).end());
  if (!options_.viscoelastic()) {
    terms_.push_back(std::make_shared<KernelTerm<NewtonianFlowKernel<Moving>>>(
        NewtonianFlowKernel<Moving>(*mesh_, dofs, elements_, &geometry_, index_, options_.inertia,
                                    options_.kernel.source, options_.kernel.ale),
        params));
  } else if (options_.conformation_components() == 3) {
    add_viscoelastic_kernels<3, Moving>(dofs, outflow);
  } else {
    add_viscoelastic_kernels<4, Moving>(dofs, outflow);
  }
  for (const TractionCondition& c : boundaries_.tractions)
    terms_.push_back(std::make_shared<KernelTerm<TractionKernel>>(
        TractionKernel(*mesh_, dofs, mesh_->boundary(c.boundary), c.traction), params));
}

void FlowEquations::build(const ComponentBuild& b) {
  const DofMap& dofs = b.dofs;
  DirichletTerm& dirichlet = b.dirichlet;
  dofs_ = &dofs;
  if (b.moving_mesh)
    add_kernels<true>(dofs);
  else
    add_kernels<false>(dofs);

  // Dirichlet conditions, each overriding those before it at shared nodes: fully developed
  // outflows, inflows, symmetry lines, driven walls, walls (no slip wins at corners), moving
  // walls. The conformation keeps its inflow value at the inflow corners.
  const int fv = dofs.field_index("velocity");
  std::map<int, DirichletTerm::ValueFunction> values;
  std::set<int> zeros;
  auto set_value = [&](int dof, DirichletTerm::ValueFunction g) {
    zeros.erase(dof);
    values[dof] = std::move(g);
  };
  auto set_zero = [&](int dof) {
    values.erase(dof);
    zeros.insert(dof);
  };
  for (const OutflowCondition& c : boundaries_.outflows)
    if (c.fully_developed)
      for (const auto& [n, normal] : axis_normal_components(*mesh_, c.boundary, "fully developed outflow"))
        for (int k : normal) set_zero(dofs.node_dof(fv, n, 1 - k));  // the tangential component
  for (size_t k = 0; k < inflows_.size(); ++k) {
    const InflowCondition& c = boundaries_.inflows[k];
    const Inflow& in = inflows_[k];
    for (size_t i = 0; i < in.nodes.size(); ++i) {
      const int n = in.nodes[i];
      for (int d = 0; d < 2; ++d) {
        const double direction =
            c.fully_developed ? in.frame.normal[static_cast<size_t>(d)] : c.velocity[static_cast<size_t>(d)];
        if (direction == 0.0)
          set_zero(dofs.node_dof(fv, n, d));
        else
          set_value(dofs.node_dof(fv, n, d), [this, k, i, d](const ParameterSet& p) {
            return inflow_values(p).velocity[k][i][static_cast<size_t>(d)];
          });
      }
      if (!options_.viscoelastic() || !mesh_->is_vertex(n) || (c.fully_developed && c.mean_velocity < 0)) continue;
      for (size_t mode = 0; mode < modes_.size(); ++mode) {
        const int fm = dofs.field_index(modes_[mode].field);
        for (int m = 0; m < options_.conformation_components(); ++m)
          values[dofs.node_dof(fm, n, m)] = [this, mode, k, i, m](const ParameterSet& p) {
            return inflow_values(p).conformation[mode][k][i][static_cast<size_t>(m)];
          };
      }
    }
  }
  for (const std::string& s : boundaries_.symmetry)
    for (const auto& [n, normal] : axis_normal_components(*mesh_, s, "symmetry line"))
      for (int k : normal) set_zero(dofs.node_dof(fv, n, k));
  for (const DrivenWall& w : boundaries_.driven_walls)
    for (int n : mesh_->boundary_nodes(w.boundary))
      for (int d = 0; d < 2; ++d) {
        const double v = w.velocity[static_cast<size_t>(d)];
        if (v == 0.0)
          set_zero(dofs.node_dof(fv, n, d));
        else
          set_value(dofs.node_dof(fv, n, d),
                    [this, v](const ParameterSet& p) { return v * (index_.Gamma >= 0 ? p.value(index_.Gamma) : 1.0); });
      }
  std::set<int> rigid;
  for (const std::string& w : boundaries_.walls)
    for (int n : mesh_->boundary_nodes(w)) {
      rigid.insert(n);
      for (int c = 0; c < 2; ++c) set_zero(dofs.node_dof(fv, n, c));
    }
  auto kinematic = std::make_shared<RateConstraintTerm>("kinematic");
  for (const std::string& w : boundaries_.moving_walls)
    for (int n : mesh_->boundary_nodes(w))
      for (int c = 0; c < 2; ++c) {
        const int dof = dofs.node_dof(fv, n, c);
        values.erase(dof);
        if (b.moving_mesh && !rigid.count(n)) {
          zeros.erase(dof);
          kinematic->add(dof, dofs.node_dof(dofs.field_index("position"), n, c));
        } else {
          zeros.insert(dof);
        }
      }
  if (kinematic->num_items() > 0) terms_.push_back(kinematic);
  // every boundary has a given normal velocity: the pressure level is fixed at one point
  if (!boundaries_.pressure_level_fixed())
    zeros.insert(dofs.element_dof(dofs.field_index("pressure"), elements_[0], 0, 0));
  for (auto& [dof, g] : values) dirichlet.add(dof, g);
  for (int dof : zeros) dirichlet.add(dof, 0.0);
}

void FlowEquations::initial_guess(Vector& u) const {
  if (inflows_.empty() || !boundaries_.inflows[0].fully_developed)
    throw std::logic_error("FlowEquations::initial_guess needs a fully developed first inflow; use rest_state");
  const Inflow& in = inflows_[0];
  const DofMap& dofs = *dofs_;
  const int fv = dofs.field_index("velocity");
  const Mesh& m = *mesh_;
  std::vector<int> nodes;
  std::vector<double> ys;
  for (int n = 0; n < m.num_nodes(); ++n)
    if (dofs.node_dof(fv, n, 0) >= 0) {
      nodes.push_back(n);
      ys.push_back(std::clamp(in.frame.across(m.node(n)), in.frame.lo, in.frame.hi));
    }
  std::vector<double> vel, dudy;
  const double mean = velocity_scale() * boundaries_.inflows[0].mean_velocity, sign = mean < 0 ? -1.0 : 1.0;
  in.profile.evaluate(ys, sign * mean, viscosity(*params_), vel, dudy);
  const bool ve = options_.viscoelastic();
  const int fl = ve ? dofs.field_index("gradient") : -1;
  const LawConstants<double> b = law_constants(index_.law, params_->values());
  for (size_t k = 0; k < nodes.size(); ++k) {
    const int n = nodes[k];
    u[dofs.node_dof(fv, n, 0)] = sign * vel[k] * in.frame.normal[0];
    u[dofs.node_dof(fv, n, 1)] = in.frame.identity() ? 0.0 : sign * vel[k] * in.frame.normal[1];
    if (!ve || dofs.node_dof(fl, n, 0) < 0) continue;
    for (size_t mode = 0; mode < modes_.size(); ++mode) {
      const auto state = in.frame.rotate(mode_shear_state(*params_, mode, dudy[k], b));
      const int fm = dofs.field_index(modes_[mode].field);
      for (int c = 0; c < options_.conformation_components(); ++c)
        u[dofs.node_dof(fm, n, c)] = state[static_cast<size_t>(c)];
    }
    const auto L = in.frame.shear_gradient(sign * dudy[k]);
    for (int c = 0; c < 4; ++c) u[dofs.node_dof(fl, n, c)] = L[static_cast<size_t>(c)];
  }
}

void FlowEquations::rest_state(Vector& u) const {
  const DofMap& dofs = *dofs_;
  const int fv = dofs.field_index("velocity");
  const bool ve = options_.viscoelastic();
  const int fl = ve ? dofs.field_index("gradient") : -1;
  const auto relaxed = ve ? steady_state(0.0, law_constants(index_.law, params_->values())) : std::array<double, 4>{};
  for (int n = 0; n < mesh_->num_nodes(); ++n) {
    if (dofs.node_dof(fv, n, 0) < 0) continue;
    for (int c = 0; c < 2; ++c) u[dofs.node_dof(fv, n, c)] = 0.0;
    if (!ve || dofs.node_dof(fl, n, 0) < 0) continue;
    for (const PolymerMode& mode : modes_)
      for (int c = 0; c < options_.conformation_components(); ++c)
        u[dofs.node_dof(dofs.field_index(mode.field), n, c)] = relaxed[static_cast<size_t>(c)];
    for (int c = 0; c < 4; ++c) u[dofs.node_dof(fl, n, c)] = 0.0;
  }
}

Status FlowEquations::stokes_state(Vector& u) const {
  rest_state(u);
  StokesStart stokes(*mesh_, group_, boundaries_, velocity_scale());
  Vector s;
  if (Status st = stokes.solve(s); !st.is_ok()) return st;
  const DofMap &to = *dofs_, &from = stokes.dofs();
  const int fv = to.field_index("velocity"), sv = from.field_index("velocity");
  const int fp = to.field_index("pressure"), sp = from.field_index("pressure");
  for (int n = 0; n < mesh_->num_nodes(); ++n)
    for (int c = 0; c < 2; ++c)
      if (to.node_dof(fv, n, c) >= 0) u[to.node_dof(fv, n, c)] = s[from.node_dof(sv, n, c)];
  for (int e : elements_)
    for (int k = 0; k < 3; ++k) u[to.element_dof(fp, e, k, 0)] = s[from.element_dof(sp, e, k, 0)];
  return {};
}

}  // namespace keller
