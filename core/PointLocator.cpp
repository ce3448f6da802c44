#include "core/PointLocator.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "core/ReferenceElement.hpp"

namespace keller {

PointLocator::PointLocator(const Mesh& mesh, int group) : mesh_(&mesh) {
  std::vector<int> elements;
  for (int e = 0; e < mesh.num_elements(); ++e)
    if (group < 0 || mesh.element_group(e) == group) elements.push_back(e);
  struct Box {
    double x0, x1, y0, y1;
  };
  std::vector<Box> boxes;
  double gx0 = std::numeric_limits<double>::infinity(), gx1 = -gx0, gy0 = gx0, gy1 = -gx0;
  for (int e : elements) {
    Box b{gx0, -gx0, gx0, -gx0};
    for (int n : mesh.element(e)) {
      b.x0 = std::min(b.x0, mesh.node(n)[0]);
      b.x1 = std::max(b.x1, mesh.node(n)[0]);
      b.y0 = std::min(b.y0, mesh.node(n)[1]);
      b.y1 = std::max(b.y1, mesh.node(n)[1]);
    }
    // curved edges can bulge past their nodes: pad by a quarter of the box size
    const double px = 0.25 * (b.x1 - b.x0) + 1e-12, py = 0.25 * (b.y1 - b.y0) + 1e-12;
    b = {b.x0 - px, b.x1 + px, b.y0 - py, b.y1 + py};
    boxes.push_back(b);
    gx0 = std::min(gx0, b.x0);
    gx1 = std::max(gx1, b.x1);
    gy0 = std::min(gy0, b.y0);
    gy1 = std::max(gy1, b.y1);
  }
  if (elements.empty()) return;
  const int nb = std::max(1, static_cast<int>(std::sqrt(static_cast<double>(elements.size()))));
  nbx_ = nby_ = nb;
  x0_ = gx0;
  y0_ = gy0;
  dx_ = (gx1 - gx0) / nbx_;
  dy_ = (gy1 - gy0) / nby_;
  buckets_.assign(static_cast<size_t>(nbx_) * nby_, {});
  auto clampi = [](int v, int n) { return std::min(std::max(v, 0), n - 1); };
  for (size_t k = 0; k < elements.size(); ++k) {
    const Box& b = boxes[k];
    const int i0 = clampi(static_cast<int>((b.x0 - x0_) / dx_), nbx_),
              i1 = clampi(static_cast<int>((b.x1 - x0_) / dx_), nbx_);
    const int j0 = clampi(static_cast<int>((b.y0 - y0_) / dy_), nby_),
              j1 = clampi(static_cast<int>((b.y1 - y0_) / dy_), nby_);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) buckets_[static_cast<size_t>(i + nbx_ * j)].push_back(elements[k]);
  }
}

bool PointLocator::invert(int e, double x, double y, MeshPoint& out, double tol) const {
  double xy[9][2];
  mesh_->element_nodes(e, xy);
  double size = 0;
  for (int a = 0; a < 9; ++a) size = std::max({size, std::abs(xy[a][0] - xy[4][0]), std::abs(xy[a][1] - xy[4][1])});
  double s = 0, t = 0;
  bool converged = false;
  for (int it = 0; it < 40 && !converged; ++it) {
    double N[9], dN[9][2];
    ref::q2_shape(s, t, N, dN);
    double fx = -x, fy = -y, J00 = 0, J01 = 0, J10 = 0, J11 = 0;
    for (int a = 0; a < 9; ++a) {
      fx += N[a] * xy[a][0];
      fy += N[a] * xy[a][1];
      J00 += dN[a][0] * xy[a][0];
      J01 += dN[a][1] * xy[a][0];
      J10 += dN[a][0] * xy[a][1];
      J11 += dN[a][1] * xy[a][1];
    }
    if (std::hypot(fx, fy) <= 1e-13 * size) {
      converged = true;
      break;
    }
    const double det = J00 * J11 - J01 * J10;
    if (!(std::abs(det) > 0)) return false;
    double ds = (J11 * fx - J01 * fy) / det, dt = (-J10 * fx + J00 * fy) / det;
    const double step = std::hypot(ds, dt);
    if (step > 1.0) {  // damp long steps: the map is only trusted near the element
      ds /= step;
      dt /= step;
    }
    s -= ds;
    t -= dt;
    if (std::abs(s) > 3.0 || std::abs(t) > 3.0) return false;  // far outside this element
  }
  if (!converged) return false;
  if (std::abs(s) > 1 + tol || std::abs(t) > 1 + tol) return false;
  out = {e, std::clamp(s, -1.0, 1.0), std::clamp(t, -1.0, 1.0)};
  return true;
}

std::vector<MeshPoint> PointLocator::locate_all(double x, double y, double tol) const {
  std::vector<MeshPoint> out;
  if (buckets_.empty()) return out;
  const double fx = (x - x0_) / dx_, fy = (y - y0_) / dy_;
  if (!(fx >= 0 && fy >= 0 && fx <= nbx_ && fy <= nby_)) return out;
  const int ii = std::min(static_cast<int>(fx), nbx_ - 1), jj = std::min(static_cast<int>(fy), nby_ - 1);
  for (int e : buckets_[static_cast<size_t>(ii + nbx_ * jj)]) {
    MeshPoint p;
    if (invert(e, x, y, p, tol)) out.push_back(p);
  }
  return out;
}

std::optional<MeshPoint> PointLocator::locate(double x, double y, double tol) const {
  auto all = locate_all(x, y, tol);
  if (all.empty()) return std::nullopt;
  return all.front();
}

}  // namespace keller
