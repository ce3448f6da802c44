// The strong form of the steady flow equations of model.md, evaluated on smooth fields given as
// templated functions of position, for manufactured solutions: the momentum body force and the
// constitutive source that make those fields an exact solution. Derivatives of the fields come
// from forward-mode dual numbers (nested for the second derivatives of the velocity), so
// nothing is differentiated by hand.
//
// Written from model.md on purpose without the kernels' law code (ConstitutiveLaw.hpp,
// LogConformation.hpp): a source built from the same functions as the discrete equations would
// cancel an error in them. The conformation equation is written with matrix products, the
// Peterlin and Cross factors and each law's relaxation P(M) from their published definitions
// (Giesekus' (M - I) + alpha (M - I)^2, PTT's Y (M - I) with the Gordon-Schowalter slip,
// FENE-CR's f (M - I)), exp(Psi) by its Taylor series, and the
// log-conformation equation as the definition of the reformulation: with M = exp(Psi),
// v . grad M = Dexp_Psi[v . grad Psi], and Dexp_Psi[X] = M X for X commuting with Psi, so
//   log-form residual = Dexp_Psi^{-1}[conformation-form residual]
//   = v . grad Psi - Dexp_Psi^{-1}[K M + M K^T] + P(M) M^-1 / lambda_eff,
// which involves neither the eigenvectors of M nor the Fattal-Kupferman formulas, and is
// smooth where the eigenvalues coincide.
#pragma once

#include <Eigen/Dense>
#include <cmath>
#include <stdexcept>
#include <unsupported/Eigen/AutoDiff>

#include "problems/laws/ConstitutiveLaw.hpp"

namespace keller::mms {

// A scalar carrying its gradient in the plane.
template <class S>
using Grad = Eigen::AutoDiffScalar<Eigen::Matrix<S, 2, 1>>;

// The continuous problem: which law, which unknown, and the parameters (model units).
struct FluidSpec {
  FluidModel model = FluidModel::Newtonian;
  bool log_form = false;
  bool dynamic_zz = false;  // FENE-P: M_zz an unknown (else f M_zz = 1 eliminates it)
  double Re = 0.0;          // > 0: the convective term
  double Gamma = 1.0, Wi = 1.0, beta = 0.5, b = 10.0;
  double alpha = 0.0, epsilon = 0.0, xi = 0.0;  // Giesekus; PTT (xi: conformation form only)
  OwensParameters owens;

  bool viscoelastic() const { return model != FluidModel::Newtonian; }
  int conformation_components() const { return model == FluidModel::FeneP && dynamic_zz ? 4 : 3; }
};

// The value of a (possibly nested) dual number.
inline double innermost_value(double x) { return x; }
template <class D>
double innermost_value(const Eigen::AutoDiffScalar<D>& x) {
  return innermost_value(x.value());
}

// exp of the symmetric matrix [[p0, p1], [p1, p2]] -> e (same layout), by scaling and squaring
// of the Taylor series: the scaled matrix has Frobenius norm <= 1/4, so 18 terms leave a
// relative truncation error below 1e-25.
template <class S>
void series_exp(const S (&p)[3], S (&e)[3]) {
  const double p0 = innermost_value(p[0]), p1 = innermost_value(p[1]), p2 = innermost_value(p[2]);
  const double norm = std::sqrt(p0 * p0 + 2 * p1 * p1 + p2 * p2);
  int squarings = 0;
  while (norm / std::ldexp(1.0, squarings) > 0.25) ++squarings;
  const double scale = std::ldexp(1.0, -squarings);
  const S q[3] = {p[0] * scale, p[1] * scale, p[2] * scale};
  // term_k = q^k / k!; q and every power of it commute, so all stay symmetric
  S term[3] = {S(1.0), S(0.0), S(1.0)};
  e[0] = S(1.0);
  e[1] = S(0.0);
  e[2] = S(1.0);
  for (int k = 1; k <= 18; ++k) {
    const S t0 = (term[0] * q[0] + term[1] * q[1]) / double(k);
    const S t1 = (term[0] * q[1] + term[1] * q[2]) / double(k);
    const S t2 = (term[1] * q[1] + term[2] * q[2]) / double(k);
    term[0] = t0;
    term[1] = t1;
    term[2] = t2;
    e[0] += t0;
    e[1] += t1;
    e[2] += t2;
  }
  for (int s = 0; s < squarings; ++s) {
    const S s0 = e[0] * e[0] + e[1] * e[1];
    const S s1 = e[1] * (e[0] + e[2]);
    const S s2 = e[1] * e[1] + e[2] * e[2];
    e[0] = s0;
    e[1] = s1;
    e[2] = s2;
  }
}

// Fields provides, for any scalar S (double or nested dual numbers):
//   void velocity(const S (&x)[2], S (&v)[2]) const;      solenoidal
//   S pressure(const S (&x)[2]) const;
//   void conformation(const S (&x)[2], S (&m)[4]) const;  M_xx, M_xy, M_yy, M_zz (SPD)
// and, for the log form, void log_conformation(const double (&x)[2], double (&psi)[4]) const
// with exp(Psi) = M (psi_zz = log M_zz).
template <class Fields>
class StrongForm {
 public:
  StrongForm(FluidSpec fluid, Fields fields) : fluid_(fluid), fields_(fields) {}

  const FluidSpec& fluid() const { return fluid_; }
  const Fields& fields() const { return fields_; }

  // Velocity and its gradient K_ij = d v_i / d x_j at x.
  template <class S>
  void velocity_gradient(const S (&x)[2], S (&v)[2], S (&K)[2][2]) const {
    using A = Grad<S>;
    const A xa[2] = {A(x[0], 2, 0), A(x[1], 2, 1)};
    A va[2];
    fields_.velocity(xa, va);
    for (int i = 0; i < 2; ++i) {
      v[i] = va[i].value();
      for (int j = 0; j < 2; ++j) K[i][j] = va[i].derivatives()(j);
    }
  }

  // M_zz as the equations see it: the field's where it is an unknown, else 1, the steady state of
  // its own equation for every law but FENE-P (whose f M_zz = 1 peterlin() uses instead).
  template <class S>
  S zz(const S (&m)[4]) const {
    return fluid_.dynamic_zz ? m[3] : S(1.0);
  }

  // Peterlin factor f(M) of model.md (FENE-P), or the FENE-CR one f = (b - 1) / (b - tr M / 3)
  // with M_zz = 1 (its own steady state); 1 for the other laws.
  template <class S>
  S peterlin(const S (&m)[4]) const {
    const double b = fluid_.b;
    if (fluid_.model == FluidModel::FeneCr) return S(b - 1.0) / (b - (m[0] + m[2] + zz(m)) / 3.0);
    if (fluid_.model != FluidModel::FeneP) return S(1.0);
    if (fluid_.dynamic_zz) return S(b - 1.0) / (b - (m[0] + m[2] + m[3]) / 3.0);
    // f M_zz = 1: f = (b - 1) / (b - (M_xx + M_yy + 1/f) / 3), solved for f
    return S(b - 2.0 / 3.0) / (b - (m[0] + m[2]) / 3.0);
  }

  // The polymer stress over the modulus, tau_p / modulus, from the laws' definitions: f M - I
  // (FENE-P), f (M - I) (FENE-CR), M - I (the others); in-plane [[xx, xy], [xy, yy]].
  template <class S>
  void polymer_stress(const S (&m)[4], S (&t)[3]) const {
    const S f = peterlin(m);
    if (fluid_.model == FluidModel::FeneCr) {
      t[0] = f * (m[0] - 1.0);
      t[1] = f * m[1];
      t[2] = f * (m[2] - 1.0);
    } else {
      t[0] = f * m[0] - 1.0;
      t[1] = f * m[1];
      t[2] = f * m[2] - 1.0;
    }
  }

  // The relaxation term of the conformation equation, M^box = -P / lambda_eff, as each law is
  // published: f M - I (FENE-P), f (M - I) (FENE-CR), (M - I) + alpha (M - I)^2 (Giesekus),
  // Y (M - I) with Y = 1 + epsilon (tr M - 3) or exp(epsilon (tr M - 3)) (PTT), M - I otherwise.
  // Returns the in-plane 2x2 part; zz in pzz.
  Eigen::Matrix2d relaxation(const double (&m)[4], double& pzz) const {
    Eigen::Matrix2d M, I = Eigen::Matrix2d::Identity();
    M << m[0], m[1], m[1], m[2];
    const double f = peterlin(m), tr = m[0] + m[2] + zz(m);
    switch (fluid_.model) {
      case FluidModel::FeneP: pzz = f * m[3] - 1.0; return f * M - I;
      case FluidModel::FeneCr: pzz = f * (m[3] - 1.0); return f * (M - I);
      case FluidModel::Giesekus:
        pzz = (m[3] - 1.0) + fluid_.alpha * (m[3] - 1.0) * (m[3] - 1.0);
        return (M - I) + fluid_.alpha * (M - I) * (M - I);
      case FluidModel::PttLinear:
      case FluidModel::PttExponential: {
        const double x = fluid_.epsilon * (tr - 3.0);
        const double Y = fluid_.model == FluidModel::PttLinear ? 1.0 + x : std::exp(x);
        pzz = Y * (m[3] - 1.0);
        return Y * (M - I);
      }
      default: pzz = m[3] - 1.0; return M - I;
    }
  }

  // 1 / lambda_eff at a point with velocity gradient K: Gamma / Wi, divided by the Cross
  // factor eta_p(gdot) / eta_p0 for Owens, gdot^2 = 2 D:D, dimensional rate gdot U0 / (Gamma W),
  // regularised by the law's rate floor.
  double inverse_relaxation_time(const double (&K)[2][2]) const {
    double inv = fluid_.Gamma / fluid_.Wi;
    if (fluid_.model == FluidModel::Owens) {
      const OwensParameters& o = fluid_.owens;
      const double dxy = 0.5 * (K[0][1] + K[1][0]);
      const double gdot2 = 2.0 * (K[0][0] * K[0][0] + K[1][1] * K[1][1] + 2.0 * dxy * dxy);
      const double rate = std::sqrt(gdot2 * std::pow(o.rate_scale / fluid_.Gamma, 2) + o.rate_floor * o.rate_floor);
      const double theta1 = o.theta2 * o.eta_pinf / o.eta_p0;
      const double cross = (1.0 + theta1 * std::pow(rate, o.m)) / (1.0 + o.theta2 * std::pow(rate, o.m));
      inv /= cross;
    }
    return inv;
  }

  // Total in-plane stress T = -P I + eta_s (K + K^T) + tau_p, tau_p = (1 - beta) (Gamma/Wi) (f M - I),
  // eta_s = beta (1 for a Newtonian fluid).
  template <class S>
  void stress(const S (&x)[2], S (&T)[2][2]) const {
    S v[2], K[2][2];
    velocity_gradient(x, v, K);
    const S P = fields_.pressure(x);
    const double eta_s = fluid_.viscoelastic() ? fluid_.beta : 1.0;
    for (int i = 0; i < 2; ++i)
      for (int j = 0; j < 2; ++j) T[i][j] = eta_s * (K[i][j] + K[j][i]) - (i == j ? P : S(0.0));
    if (!fluid_.viscoelastic()) return;
    S m[4], t[3];
    fields_.conformation(x, m);
    polymer_stress(m, t);
    const double modulus = (1.0 - fluid_.beta) * fluid_.Gamma / fluid_.Wi;
    T[0][0] += modulus * t[0];
    T[0][1] += modulus * t[1];
    T[1][0] += modulus * t[1];
    T[1][1] += modulus * t[2];
  }

  // Body force f = (Re/Gamma) v . grad v - div T.
  void momentum_source(const double (&x)[2], double (&force)[2]) const {
    using D = Grad<double>;
    const D xd[2] = {D(x[0], 2, 0), D(x[1], 2, 1)};
    D T[2][2];
    stress(xd, T);
    for (int i = 0; i < 2; ++i) force[i] = -(T[i][0].derivatives()(0) + T[i][1].derivatives()(1));
    if (fluid_.Re > 0.0) {
      double v[2], K[2][2];
      velocity_gradient(x, v, K);
      const double rho = fluid_.Re / fluid_.Gamma;
      for (int i = 0; i < 2; ++i) force[i] += rho * (K[i][0] * v[0] + K[i][1] * v[1]);
    }
  }

  // Source of the conformation equation, components xx, xy, yy, zz:
  //   v . grad M - (K M + M K^T) + (f M - I) / lambda_eff (zz: no stretching in planar flow),
  // or of the log-conformation equation (Dexp_Psi^{-1} of that; zz: divided by M_zz).
  void constitutive_source(const double (&x)[2], double (&s)[4]) const {
    using D = Grad<double>;
    const D xd[2] = {D(x[0], 2, 0), D(x[1], 2, 1)};
    D md[4];
    fields_.conformation(xd, md);
    double v[2], K[2][2];
    velocity_gradient(x, v, K);
    double m[4];
    for (int c = 0; c < 4; ++c) m[c] = md[c].value();
    double conv[4];
    for (int c = 0; c < 4; ++c) conv[c] = v[0] * md[c].derivatives()(0) + v[1] * md[c].derivatives()(1);
    Eigen::Matrix2d Km, Mm;
    Km << K[0][0], K[0][1], K[1][0], K[1][1];
    Mm << m[0], m[1], m[1], m[2];
    // the Gordon-Schowalter derivative of PTT: M^nabla + xi (D M + M D) - 2 xi D
    const bool ptt = fluid_.model == FluidModel::PttLinear || fluid_.model == FluidModel::PttExponential;
    const double xi = ptt ? fluid_.xi : 0.0;
    const Eigen::Matrix2d Dm = 0.5 * (Km + Km.transpose());
    const Eigen::Matrix2d stretch = Km * Mm + Mm * Km.transpose() - xi * (Dm * Mm + Mm * Dm) + 2.0 * xi * Dm;
    const double inv = inverse_relaxation_time(K);
    double pzz = 0;
    const Eigen::Matrix2d P = relaxation(m, pzz);
    Eigen::Matrix2d res;
    res << conv[0], conv[1], conv[1], conv[2];
    res += -stretch + inv * P;
    s[0] = res(0, 0);
    s[1] = res(0, 1);
    s[2] = res(1, 1);
    s[3] = conv[3] + inv * pzz;
    if (!fluid_.log_form) return;
    // Dexp at Psi, as the 3x3 matrix of directional derivatives on symmetric matrices
    double psi[4];
    if constexpr (requires(const Fields& fs, double(&p)[4]) { fs.log_conformation(x, p); })
      fields_.log_conformation(x, psi);
    else
      throw std::logic_error("StrongForm: the log form needs the fields' log_conformation");
    using D3 = Eigen::AutoDiffScalar<Eigen::Vector3d>;
    const D3 p[3] = {D3(psi[0], 3, 0), D3(psi[1], 3, 1), D3(psi[2], 3, 2)};
    D3 e[3];
    series_exp(p, e);
    Eigen::Matrix3d J;
    for (int r = 0; r < 3; ++r) J.row(r) = e[r].derivatives().transpose();
    const Eigen::Vector3d sl = J.partialPivLu().solve(Eigen::Vector3d(s[0], s[1], s[2]));
    s[0] = sl[0];
    s[1] = sl[1];
    s[2] = sl[2];
    s[3] /= m[3];
  }

 private:
  FluidSpec fluid_;
  Fields fields_;
};

}  // namespace keller::mms
