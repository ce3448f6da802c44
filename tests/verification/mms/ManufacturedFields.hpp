// The smooth fields of the manufactured solutions and the mesh maps they live on.
//
// Velocity from the stream function psi = y + 0.4 y^2 + A sin(k1 x + c1) cos(k2 y + c2):
// a mean flow in +x (inflow on the left), a shear that keeps the shear rate away from zero
// (the Owens relaxation time has an infinite slope there), and a cellular part that gives
// every velocity-gradient component, extension included. Pressure: a smooth wave.
// Log-conformation Psi = a I + N with N = [[d, c], [c, -d]] vanishing at (0.45, 0.55): M is
// isotropic there, so the log form's series branches (rho^2 < 1e-3) are used near it, and
// anisotropic elsewhere (eigenvalues of M from 0.82 to 2.06). M_zz = exp(psi_zz)
// for FENE-P with a dynamic M_zz. Every field is an entire function of (x, y), so the
// manufactured solution is defined on whatever domain the mesh covers.
#pragma once

#include <cmath>

#include "StrongForm.hpp"

namespace keller::mms {

struct ManufacturedFields {
  static constexpr double A = 0.15, k1 = 2.1, k2 = 1.7, c1 = 0.3, c2 = 0.4;

  template <class S>
  void velocity(const S (&x)[2], S (&v)[2]) const {
    using std::cos;
    using std::sin;
    // (d psi / dy, -d psi / dx); StrongFormTest checks div v = 0 by dual numbers
    const S sx = sin(k1 * x[0] + c1), cx = cos(k1 * x[0] + c1);
    const S sy = sin(k2 * x[1] + c2), cy = cos(k2 * x[1] + c2);
    v[0] = 1.0 + 0.8 * x[1] - A * k2 * sx * sy;
    v[1] = -A * k1 * cx * cy;
  }

  template <class S>
  S pressure(const S (&x)[2]) const {
    using std::cos;
    using std::sin;
    return S(0.6 * sin(1.3 * x[0] + 0.2) * cos(0.9 * x[1] - 0.1) + 0.3 * x[0] * x[1]);
  }

  template <class S>
  void log_conformation(const S (&x)[2], S (&psi)[4]) const {
    using std::cos;
    using std::sin;
    const S a = 0.1 + 0.3 * sin(1.1 * x[0] + 0.7 * x[1]);
    const S d = 0.45 * (x[0] - 0.45) + 0.1 * (x[1] - 0.55) * x[0];
    const S c = 0.35 * (x[1] - 0.55) - 0.15 * (x[0] - 0.45) * (x[0] - 0.45);
    psi[0] = a + d;
    psi[1] = c;
    psi[2] = a - d;
    psi[3] = S(0.1 + 0.15 * sin(0.9 * x[0] + 0.6 * x[1]));
  }

  template <class S>
  void conformation(const S (&x)[2], S (&m)[4]) const {
    using std::exp;
    S psi[4];
    log_conformation(x, psi);
    const S p[3] = {psi[0], psi[1], psi[2]};
    S e[3];
    series_exp(p, e);
    m[0] = e[0];
    m[1] = e[1];
    m[2] = e[2];
    m[3] = exp(psi[3]);
  }
};

// The fixed mesh: the unit square of logical coordinates mapped non-affinely, every boundary
// curved, elements curved and of varying size and shape (det of the map between 0.39 and 1.39).
inline void distorted_square(double s, double t, double& x, double& y) {
  const double pi = 3.14159265358979323846;
  x = s + 0.06 * std::sin(2 * pi * s) * std::sin(pi * t) + 0.08 * t * t;
  y = t + 0.06 * std::sin(pi * s) * std::sin(2 * pi * t) - 0.05 * s * s;
}

// The unit square with its top wall pushed down by up to 30% in the middle, as a collapsing
// wall does, and a shear along it: the prescribed motion of the moving-mesh forms.
inline void collapsed_square(double s, double t, double& x, double& y) {
  const double pi = 3.14159265358979323846;
  const double bump = std::sin(pi * s);
  x = s + 0.05 * std::sin(2 * pi * s) * std::sin(pi * t);
  y = t * (1.0 - 0.3 * bump * bump) + 0.04 * std::sin(pi * t) * s;
}

}  // namespace keller::mms
