#include "core/BlockMeshBuilder.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace keller {

int BlockMeshBuilder::add_block(BlockSpec spec) {
  if (spec.nx < 1 || spec.ny < 1) throw std::invalid_argument("block '" + spec.name + "': needs at least 1x1 elements");
  if (!spec.map) throw std::invalid_argument("block '" + spec.name + "': no map");
  blocks_.push_back(std::move(spec));
  return static_cast<int>(blocks_.size()) - 1;
}

void BlockMeshBuilder::connect(int a, Side sa, int b, Side sb) {
  const int n = static_cast<int>(blocks_.size());
  if (a < 0 || a >= n || b < 0 || b >= n) throw std::invalid_argument("connect: block index out of range");
  connections_.push_back({a, sa, b, sb});
}

namespace {

struct UnionFind {
  std::vector<int> parent;
  explicit UnionFind(int n) : parent(n) { std::iota(parent.begin(), parent.end(), 0); }
  int find(int x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  }
  void unite(int x, int y) {
    x = find(x);
    y = find(y);
    if (x != y) parent[std::max(x, y)] = std::min(x, y);
  }
};

// Logical node indices (i, j) along a side, in increasing logical coordinate.
std::vector<std::pair<int, int>> side_nodes(int nx, int ny, Side side) {
  std::vector<std::pair<int, int>> out;
  const int ni = 2 * nx + 1, nj = 2 * ny + 1;
  switch (side) {
    case Side::Bottom:
      for (int i = 0; i < ni; ++i) out.emplace_back(i, 0);
      break;
    case Side::Top:
      for (int i = 0; i < ni; ++i) out.emplace_back(i, nj - 1);
      break;
    case Side::Left:
      for (int j = 0; j < nj; ++j) out.emplace_back(0, j);
      break;
    case Side::Right:
      for (int j = 0; j < nj; ++j) out.emplace_back(ni - 1, j);
      break;
  }
  return out;
}

}  // namespace

Mesh BlockMeshBuilder::build() const {
  if (blocks_.empty()) throw std::invalid_argument("BlockMeshBuilder: no blocks");
  std::vector<Mesh::Point> pos;
  std::vector<int> offset;
  double extent = 0.0;
  for (const BlockSpec& b : blocks_) {
    offset.push_back(static_cast<int>(pos.size()));
    const std::vector<double> sv = b.grading_s.vertices(b.nx), tv = b.grading_t.vertices(b.ny);
    auto logical = [](const std::vector<double>& v, int k) {
      return (k % 2 == 0) ? v[k / 2] : 0.5 * (v[k / 2] + v[k / 2 + 1]);
    };
    for (int j = 0; j <= 2 * b.ny; ++j) {
      for (int i = 0; i <= 2 * b.nx; ++i) {
        const Mesh::Point p = b.map(logical(sv, i), logical(tv, j));
        if (!std::isfinite(p[0]) || !std::isfinite(p[1]))
          throw std::invalid_argument("block '" + b.name + "': map returned a non-finite point");
        extent = std::max({extent, std::abs(p[0]), std::abs(p[1])});
        pos.push_back(p);
      }
    }
  }
  auto id = [&](int blk, int i, int j) { return offset[blk] + i + (2 * blocks_[blk].nx + 1) * j; };

  UnionFind uf(static_cast<int>(pos.size()));
  const double tol = 1e-9 * std::max(1.0, extent);
  for (const Connection& c : connections_) {
    const BlockSpec& A = blocks_[c.a];
    const BlockSpec& B = blocks_[c.b];
    const auto na = side_nodes(A.nx, A.ny, c.sa), nb = side_nodes(B.nx, B.ny, c.sb);
    if (na.size() != nb.size())
      throw std::invalid_argument("connect: sides of blocks '" + A.name + "' and '" + B.name +
                                  "' have different numbers of elements");
    for (size_t k = 0; k < na.size(); ++k) {
      const int ia = id(c.a, na[k].first, na[k].second), ib = id(c.b, nb[k].first, nb[k].second);
      const double d = std::hypot(pos[ia][0] - pos[ib][0], pos[ia][1] - pos[ib][1]);
      if (d > tol)
        throw std::invalid_argument("connect: glued sides of blocks '" + A.name + "' and '" + B.name +
                                    "' do not coincide (distance " + std::to_string(d) + ")");
      uf.unite(ia, ib);
    }
  }

  std::vector<int> new_id(pos.size(), -1);
  std::vector<Mesh::Point> nodes;
  for (size_t k = 0; k < pos.size(); ++k) {
    const int r = uf.find(static_cast<int>(k));
    if (new_id[r] < 0) {
      new_id[r] = static_cast<int>(nodes.size());
      nodes.push_back(pos[r]);
    }
    new_id[k] = new_id[r];
  }

  std::vector<std::array<int, 9>> elements;
  std::vector<int> group;
  std::vector<std::string> group_names;
  std::map<std::string, std::vector<BoundaryEdge>> boundaries;
  std::vector<MeshBlock> mblocks;
  for (int bi = 0; bi < static_cast<int>(blocks_.size()); ++bi) {
    const BlockSpec& b = blocks_[bi];
    auto git = std::find(group_names.begin(), group_names.end(), b.group);
    if (git == group_names.end()) git = group_names.insert(group_names.end(), b.group);
    const int g = static_cast<int>(git - group_names.begin());
    MeshBlock mb;
    mb.name = b.name;
    mb.group = g;
    mb.nx = b.nx;
    mb.ny = b.ny;
    for (int j = 0; j <= 2 * b.ny; ++j)
      for (int i = 0; i <= 2 * b.nx; ++i) mb.node_grid.push_back(new_id[id(bi, i, j)]);
    for (int j = 0; j < b.ny; ++j) {
      for (int i = 0; i < b.nx; ++i) {
        std::array<int, 9> el{};
        for (int bb = 0; bb < 3; ++bb)
          for (int aa = 0; aa < 3; ++aa) el[aa + 3 * bb] = new_id[id(bi, 2 * i + aa, 2 * j + bb)];
        mb.elements.push_back(static_cast<int>(elements.size()));
        elements.push_back(el);
        group.push_back(g);
      }
    }
    for (int s = 0; s < 4; ++s) {
      const std::string& name = b.side_names[s];
      if (name.empty()) continue;
      auto& list = boundaries[name];
      switch (static_cast<Side>(s)) {
        case Side::Bottom:
          for (int i = 0; i < b.nx; ++i) list.push_back({mb.element(i, 0), 0});
          break;
        case Side::Right:
          for (int j = 0; j < b.ny; ++j) list.push_back({mb.element(b.nx - 1, j), 1});
          break;
        case Side::Top:
          for (int i = 0; i < b.nx; ++i) list.push_back({mb.element(i, b.ny - 1), 2});
          break;
        case Side::Left:
          for (int j = 0; j < b.ny; ++j) list.push_back({mb.element(0, j), 3});
          break;
      }
    }
    mblocks.push_back(std::move(mb));
  }
  Mesh mesh(std::move(nodes), std::move(elements), std::move(group), std::move(group_names), std::move(boundaries),
            std::move(mblocks));
  const auto [jmin, jmax] = mesh.jacobian_range();
  if (!(jmin > 0.0)) throw std::invalid_argument("BlockMeshBuilder: the mesh has an inverted or degenerate element");
  return mesh;
}

}  // namespace keller
