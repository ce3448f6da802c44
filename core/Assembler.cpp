#include "core/Assembler.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

namespace keller {

namespace {

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

Status item_failure(const Term& t, int item, const Status& st) {
  return {st.code(), fmt::format("term '{}' item {}: {}", t.name(), item, st.message())};
}

}  // namespace

std::vector<int> non_finite_entries(const Vector& v, int limit) {
  std::vector<int> out;
  for (int i = 0; i < v.size() && static_cast<int>(out.size()) < limit; ++i)
    if (!std::isfinite(v[i])) out.push_back(i);
  return out;
}

Assembler::Assembler(int n, std::vector<std::shared_ptr<const Term>> terms, std::vector<std::pair<int, int>> redirects)
    : n_(n), terms_(std::move(terms)), target_(n), owned_(n, -1) {
  for (int r = 0; r < n; ++r) target_[r] = r;
  std::vector<int> dofs;
  for (size_t ti = 0; ti < terms_.size(); ++ti) {
    const Term& t = *terms_[ti];
    dofs.resize(t.local_size());
    for (int item = 0; item < t.num_items(); ++item) {
      t.item_dofs(item, dofs.data());
      for (int d : dofs)
        if (d < 0 || d >= n)
          throw std::invalid_argument(
              fmt::format("term '{}' item {}: unknown index {} out of range", t.name(), item, d));
      if (!t.owns_rows()) continue;
      for (int i = 0; i < t.local_rows(); ++i) {
        const int r = dofs[i];
        if (owned_[r] >= 0)
          throw std::invalid_argument(
              fmt::format("row {} is owned by both '{}' and '{}'", r, terms_[owned_[r]]->name(), t.name()));
        owned_[r] = static_cast<int>(ti);
        target_[r] = -1;
      }
    }
  }
  for (const auto& [from, to] : redirects) {
    if (from < 0 || from >= n || to < 0 || to >= n) throw std::invalid_argument("redirect: row out of range");
    if (owned_[from] < 0)
      throw std::invalid_argument(fmt::format("redirect: row {} is not owned by a strong term", from));
    target_[from] = to;
  }

  std::vector<std::vector<int>> cols(n);
  for (int c = 0; c < n; ++c) cols[c].push_back(c);
  for (const auto& tp : terms_) {
    const Term& t = *tp;
    const bool owns = t.owns_rows();
    dofs.resize(t.local_size());
    for (int item = 0; item < t.num_items(); ++item) {
      t.item_dofs(item, dofs.data());
      for (int i = 0; i < t.local_rows(); ++i) {
        const int r = destination(owns, dofs[i]);
        if (r < 0) continue;
        for (int c : dofs) cols[c].push_back(r);
      }
    }
    // keep memory bounded on big meshes: compact once per term
    for (auto& col : cols) {
      std::sort(col.begin(), col.end());
      col.erase(std::unique(col.begin(), col.end()), col.end());
    }
  }
  long nnz = 0;
  for (const auto& col : cols) nnz += static_cast<long>(col.size());
  pattern_.resize(n, n);
  pattern_.resizeNonZeros(nnz);
  int* outer = pattern_.outerIndexPtr();
  int* inner = pattern_.innerIndexPtr();
  double* val = pattern_.valuePtr();
  long k = 0;
  for (int c = 0; c < n; ++c) {
    outer[c] = static_cast<int>(k);
    for (int r : cols[c]) {
      inner[k] = r;
      val[k] = 0.0;
      ++k;
    }
  }
  outer[n] = static_cast<int>(k);
  pattern_.makeCompressed();

  for (const auto& tp : terms_) {
    const Term& t = *tp;
    const int m = t.local_size(), kr = t.local_rows();
    const bool owns = t.owns_rows();
    std::vector<int> pos(static_cast<size_t>(t.num_items()) * kr * m);
    dofs.resize(m);
    for (int item = 0; item < t.num_items(); ++item) {
      t.item_dofs(item, dofs.data());
      int* p = &pos[static_cast<size_t>(item) * kr * m];
      for (int i = 0; i < kr; ++i) {
        const int r = destination(owns, dofs[i]);
        for (int j = 0; j < m; ++j) p[i * m + j] = r < 0 ? -1 : position(r, dofs[j]);
      }
    }
    positions_.push_back(std::move(pos));
  }
}

int Assembler::position(int row, int col) const {
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  const int* b = inner + outer[col];
  const int* e = inner + outer[col + 1];
  const int* it = std::lower_bound(b, e, row);
  return (it != e && *it == row) ? static_cast<int>(it - inner) : -1;
}

Status Assembler::assemble_vector(const Vector& u, Vector& out, const LocalVector& local) const {
  out.setZero(n_);
  std::vector<int> dofs;
  std::vector<double> ul, rl;
  for (const auto& tp : terms_) {
    const Term& t = *tp;
    // the term's sizes and ownership once, not a virtual call per local entry (a residual of a
    // small problem spent 40% of its time in them)
    const int m = t.local_size(), k = t.local_rows(), items = t.num_items();
    const bool owns = t.owns_rows();
    dofs.resize(m);
    ul.resize(m);
    rl.resize(k);
    for (int item = 0; item < items; ++item) {
      t.item_dofs(item, dofs.data());
      for (int j = 0; j < m; ++j) ul[j] = u[dofs[j]];
      Status st = local(t, item, ul.data(), rl.data());
      if (!st.is_ok()) return item_failure(t, item, st);
      for (int i = 0; i < k; ++i) {
        const int r = destination(owns, dofs[i]);
        if (r >= 0) out[r] += rl[i];
      }
    }
  }
  if (auto bad = non_finite_entries(out, 1); !bad.empty())
    return {StatusCode::NotFinite, fmt::format("not finite in row {}", bad[0])};
  return {};
}

Status Assembler::weak_residual(const Vector& u, Vector& F) const {
  F.setZero(n_);
  std::vector<int> dofs;
  std::vector<double> ul, rl;
  for (const auto& tp : terms_) {
    const Term& t = *tp;
    if (t.owns_rows()) continue;
    dofs.resize(t.local_size());
    ul.resize(t.local_size());
    rl.resize(t.local_rows());
    for (int item = 0; item < t.num_items(); ++item) {
      t.item_dofs(item, dofs.data());
      for (int j = 0; j < t.local_size(); ++j) ul[j] = u[dofs[j]];
      Status st = t.residual(item, ul.data(), rl.data());
      if (!st.is_ok()) return item_failure(t, item, st);
      for (int i = 0; i < t.local_rows(); ++i) F[dofs[i]] += rl[i];
    }
  }
  return {};
}

Status Assembler::residual(const Vector& u, Vector& F) const {
  const auto t0 = std::chrono::steady_clock::now();
  Status st = assemble_vector(
      u, F, [](const Term& t, int item, const double* ul, double* rl) { return t.residual(item, ul, rl); });
  timing_.residual_seconds += seconds_since(t0);
  ++timing_.residual_calls;
  if (st.code() == StatusCode::NotFinite) return {st.code(), "residual " + st.message()};
  return st;
}

Status Assembler::jacobian(const Vector& u, Vector& F, SparseMatrix& J) const {
  const auto t0 = std::chrono::steady_clock::now();
  if (J.nonZeros() != pattern_.nonZeros() || J.rows() != n_) J = pattern_;
  std::fill(J.valuePtr(), J.valuePtr() + J.nonZeros(), 0.0);
  F.setZero(n_);
  double* val = J.valuePtr();
  std::vector<int> dofs;
  std::vector<double> ul, rl, Jl;
  for (size_t ti = 0; ti < terms_.size(); ++ti) {
    const Term& t = *terms_[ti];
    const int m = t.local_size(), k = t.local_rows();
    const bool owns = t.owns_rows();
    dofs.resize(m);
    ul.resize(m);
    rl.resize(k);
    Jl.resize(static_cast<size_t>(k) * m);
    for (int item = 0; item < t.num_items(); ++item) {
      t.item_dofs(item, dofs.data());
      for (int j = 0; j < m; ++j) ul[j] = u[dofs[j]];
      Status st = t.jacobian(item, ul.data(), rl.data(), Jl.data());
      if (!st.is_ok()) return item_failure(t, item, st);
      const int* pos = &positions_[ti][static_cast<size_t>(item) * k * m];
      for (int i = 0; i < k; ++i) {
        const int r = destination(owns, dofs[i]);
        if (r < 0) continue;
        F[r] += rl[i];
        for (int j = 0; j < m; ++j) val[pos[i * m + j]] += Jl[static_cast<size_t>(i) * m + j];
      }
    }
  }
  timing_.jacobian_seconds += seconds_since(t0);
  ++timing_.jacobian_calls;
  if (auto bad = non_finite_entries(F, 1); !bad.empty())
    return {StatusCode::NotFinite, fmt::format("residual is not finite in row {}", bad[0])};
  for (int c = 0; c < n_; ++c)
    for (int p = J.outerIndexPtr()[c]; p < J.outerIndexPtr()[c + 1]; ++p)
      if (!std::isfinite(val[p]))
        return {StatusCode::NotFinite, fmt::format("Jacobian is not finite at ({}, {})", J.innerIndexPtr()[p], c)};
  return {};
}

Status Assembler::mass_matrix(const Vector& u, SparseMatrix& B) const {
  if (B.nonZeros() != pattern_.nonZeros() || B.rows() != n_) B = pattern_;
  std::fill(B.valuePtr(), B.valuePtr() + B.nonZeros(), 0.0);
  double* val = B.valuePtr();
  std::vector<int> dofs;
  std::vector<double> ul, Bl;
  for (size_t ti = 0; ti < terms_.size(); ++ti) {
    const Term& t = *terms_[ti];
    if (!t.has_mass()) continue;
    const int m = t.local_size(), k = t.local_rows();
    const bool owns = t.owns_rows();
    dofs.resize(m);
    ul.resize(m);
    Bl.resize(static_cast<size_t>(k) * m);
    for (int item = 0; item < t.num_items(); ++item) {
      t.item_dofs(item, dofs.data());
      for (int j = 0; j < m; ++j) ul[j] = u[dofs[j]];
      Status st = t.mass(item, ul.data(), Bl.data());
      if (!st.is_ok()) return item_failure(t, item, st);
      const int* pos = &positions_[ti][static_cast<size_t>(item) * k * m];
      for (int i = 0; i < k; ++i) {
        if (destination(owns, dofs[i]) < 0) continue;
        for (int j = 0; j < m; ++j) val[pos[i * m + j]] += Bl[static_cast<size_t>(i) * m + j];
      }
    }
  }
  return {};
}

Status Assembler::time_residual(const Vector& u, const Vector& udot, Vector& R) const {
  R.setZero(n_);
  std::vector<int> dofs;
  std::vector<double> ul, vl, rl;
  for (const auto& tp : terms_) {
    const Term& t = *tp;
    if (!t.has_mass()) continue;
    const int m = t.local_size(), k = t.local_rows(), items = t.num_items();
    const bool owns = t.owns_rows();
    dofs.resize(m);
    ul.resize(m);
    vl.resize(m);
    rl.resize(k);
    for (int item = 0; item < items; ++item) {
      t.item_dofs(item, dofs.data());
      for (int j = 0; j < m; ++j) {
        ul[j] = u[dofs[j]];
        vl[j] = udot[dofs[j]];
      }
      Status st = t.rate(item, ul.data(), vl.data(), rl.data());
      if (!st.is_ok()) return item_failure(t, item, st);
      for (int i = 0; i < k; ++i) {
        const int r = destination(owns, dofs[i]);
        if (r >= 0) R[r] += rl[i];
      }
    }
  }
  if (auto bad = non_finite_entries(R, 1); !bad.empty())
    return {StatusCode::NotFinite, fmt::format("time terms not finite in row {}", bad[0])};
  return {};
}

Status Assembler::time_dependent_residual(const Vector& u, const Vector& udot, Vector& G) const {
  const auto t0 = std::chrono::steady_clock::now();
  std::vector<int> dofs;
  std::vector<double> vl;
  Status st = assemble_vector(u, G, [&](const Term& t, int item, const double* ul, double* rl) {
    if (!t.has_mass()) return t.residual(item, ul, rl);
    dofs.resize(t.local_size());
    vl.resize(dofs.size());
    t.item_dofs(item, dofs.data());
    for (size_t j = 0; j < dofs.size(); ++j) vl[j] = udot[dofs[j]];
    return t.residual_with_rate(item, ul, vl.data(), rl);
  });
  timing_.residual_seconds += seconds_since(t0);
  ++timing_.residual_calls;
  if (st.code() == StatusCode::NotFinite) return {st.code(), "time-dependent residual " + st.message()};
  return st;
}

Status Assembler::parameter_derivative(int p, const Vector& u, Vector& dF) const {
  const auto t0 = std::chrono::steady_clock::now();
  Status st = assemble_vector(u, dF, [p](const Term& t, int item, const double* ul, double* rl) {
    return t.parameter_derivative(item, p, ul, rl);
  });
  timing_.parameter_seconds += seconds_since(t0);
  ++timing_.parameter_calls;
  if (st.code() == StatusCode::NotFinite) return {st.code(), "dF/dp " + st.message()};
  return st;
}

bool Assembler::has_directional_derivatives() const {
  for (const auto& t : terms_)
    if (!t->has_directional_derivative()) return false;
  return true;
}

Status Assembler::directional_derivative(const Vector& u, const std::vector<const Vector*>& du,
                                         const std::vector<const Vector*>& dp, Vector& out) const {
  const int order = static_cast<int>(du.size());
  if ((order != 2 && order != 3) || dp.size() != du.size())
    throw std::invalid_argument("Assembler::directional_derivative: 2 or 3 directions");
  std::vector<std::vector<double>> local(du.size());
  std::vector<const double*> dul(du.size()), dpl(du.size());
  for (size_t j = 0; j < dp.size(); ++j) dpl[j] = dp[j] ? dp[j]->data() : nullptr;
  std::vector<int> dofs;
  Status st = assemble_vector(u, out, [&](const Term& t, int item, const double* ul, double* rl) {
    dofs.resize(t.local_size());
    t.item_dofs(item, dofs.data());
    for (size_t j = 0; j < du.size(); ++j) {
      if (!du[j]) {
        dul[j] = nullptr;
        continue;
      }
      local[j].resize(dofs.size());
      for (size_t i = 0; i < dofs.size(); ++i) local[j][i] = (*du[j])[dofs[i]];
      dul[j] = local[j].data();
    }
    return t.directional_derivative(item, ul, order, dul.data(), dpl.data(), rl);
  });
  if (st.code() == StatusCode::NotFinite) return {st.code(), "directional derivative " + st.message()};
  return st;
}

}  // namespace keller
