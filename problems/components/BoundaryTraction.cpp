#include "problems/components/BoundaryTraction.hpp"

#include <cmath>

#include "core/ElementGeometry.hpp"
#include "problems/laws/ConstitutiveLaw.hpp"
#include "problems/laws/LogConformation.hpp"

namespace keller {

BoundaryTraction::BoundaryTraction(const Mesh& mesh, const DofMap& dofs, const FlowEquations& flow)
    : mesh_(&mesh), dofs_(&dofs), flow_(&flow) {
  fv_ = dofs.field_index("velocity");
  fp_ = dofs.field_index("pressure");
}

bool BoundaryTraction::evaluate(const Vector& u, const ParameterSet& params, const BoundaryEdge& be,
                                std::array<TractionPoint, ref::kEdgeQp>& out) const {
  const bool ve = flow_->options().viscoelastic();
  const double* p = params.values();
  const double beta = ve ? solvent_viscosity(flow_->parameter_indices(), p) : 1.0;
  const ref::Tables& tb = ref::tables();
  auto gather = [&](int f, int n, double* v) {
    int d[36];
    dofs_->element_dofs(f, be.element, d);
    for (int i = 0; i < n; ++i) v[i] = u[d[i]];
  };
  double xy[9][2];
  mesh_->element_nodes(be.element, xy);
  std::array<EdgeQpGeometry<double>, ref::kEdgeQp> geo;
  if (!map_edge(xy, be.edge, geo)) return false;
  double v[18], pc[3];
  gather(fv_, 18, v);
  gather(fp_, 3, pc);
  for (int q = 0; q < ref::kEdgeQp; ++q) {
    const EdgeQpGeometry<double>& g = geo[static_cast<size_t>(q)];
    TractionPoint& t = out[static_cast<size_t>(q)];
    double K[2][2] = {{0, 0}, {0, 0}};
    for (int a = 0; a < 9; ++a)
      for (int j = 0; j < 2; ++j) {
        K[0][j] += g.dN2dx[a][j] * v[a];
        K[1][j] += g.dN2dx[a][j] * v[9 + a];
      }
    t.velocity[0] = t.velocity[1] = 0;
    for (int a = 0; a < 9; ++a) {
      t.velocity[0] += tb.edge_N2[be.edge][q][a] * v[a];
      t.velocity[1] += tb.edge_N2[be.edge][q][a] * v[9 + a];
    }
    // the P1disc pressure is linear in physical coordinates about the element's centre node
    t.pressure = pc[0] + (g.x[0] - xy[4][0]) * pc[1] + (g.x[1] - xy[4][1]) * pc[2];
    t.sxx = -t.pressure + 2.0 * beta * K[0][0];
    t.sxy = beta * (K[0][1] + K[1][0]);
    t.syy = -t.pressure + 2.0 * beta * K[1][1];
    if (ve) {
      const Conformation<double> tp = flow_->polymer_stress_at(u, p, be.element, tb.edge_N1[be.edge][q]);
      t.sxx += tp.xx;
      t.sxy += tp.xy;
      t.syy += tp.yy;
    }
    for (int i = 0; i < 2; ++i) {
      t.x[i] = g.x[i];
      t.normal[i] = g.normal[i];
    }
    t.wds = g.wds;
    t.traction[0] = t.sxx * g.normal[0] + t.sxy * g.normal[1];
    t.traction[1] = t.sxy * g.normal[0] + t.syy * g.normal[1];
  }
  return true;
}

}  // namespace keller
