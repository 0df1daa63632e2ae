// The axis-aligned displacement manufactured solution of Wallstedt & Guilkey (JCP 227, 2008;
// Uintah's MMS): on a square (cube) body [o, o + L]^dim of the ln J neo-Hookean material,
//   u_d(X, t) = A sin(2 pi xi_d) sin(omega t),   xi_d = (X_d - o_d) / L,   omega = pi c / L,
// with c = sqrt(E / rho0) (their choice). Each displacement component depends on its own
// coordinate only, so F is diagonal, F_dd = 1 + (2 pi A / L) cos(2 pi xi_d) sin(omega t), and the
// first Piola-Kirchhoff stress P = mu (F - F^-T) + lambda ln J F^-T is diagonal too:
//   P_dd = mu (F_dd - 1/F_dd) + lambda ln J / F_dd,
//   dP_dd/dX_d = F_dd' (mu + (mu + lambda (1 - ln J)) / F_dd^2),
// (ln J depends on X_d through F_dd only). Momentum balance rho0 a = Div P + rho0 b then gives the
// body force per unit mass that makes u exact: b_d = a_d - (dP_dd/dX_d) / rho0. The normal
// displacement vanishes on every face (rollers: u_d = 0 at xi_d = 0 and 1), the particles start
// undeformed (u = 0) with v_d = A omega sin(2 pi xi_d). Everything is evaluated at a particle's
// reference position X, on the device (the body force is applied to every particle each step).
#pragma once

#include <Kokkos_Core.hpp>

#include <cmath>

namespace impm {

struct AxisAlignedManufactured {
  int dim = 2;
  double amplitude = 0;                    // A (m)
  double length = 1;                       // L: the body's side (m)
  double origin[3] = {0, 0, 0};            // o: its lower corner
  double omega = 0;                        // pi sqrt(E / rho0) / L (rad/s)
  double mu = 0, lambda = 0, density = 0;  // the body's neo-Hookean constants and rho0

  static constexpr double kPi = 3.14159265358979323846;

  KOKKOS_INLINE_FUNCTION double phase(const double* X, int d) const { return 2 * kPi * (X[d] - origin[d]) / length; }
  KOKKOS_INLINE_FUNCTION double displacement(const double* X, double t, int d) const {
    return amplitude * std::sin(phase(X, d)) * std::sin(omega * t);
  }
  KOKKOS_INLINE_FUNCTION double velocity(const double* X, double t, int d) const {
    return amplitude * omega * std::sin(phase(X, d)) * std::cos(omega * t);
  }
  KOKKOS_INLINE_FUNCTION double acceleration(const double* X, double t, int d) const {
    return -amplitude * omega * omega * std::sin(phase(X, d)) * std::sin(omega * t);
  }
  // F_dd and its derivative along X_d.
  KOKKOS_INLINE_FUNCTION double stretch(const double* X, double t, int d) const {
    return 1 + 2 * kPi * amplitude / length * std::cos(phase(X, d)) * std::sin(omega * t);
  }
  KOKKOS_INLINE_FUNCTION double stretchGradient(const double* X, double t, int d) const {
    return -4 * kPi * kPi * amplitude / (length * length) * std::sin(phase(X, d)) * std::sin(omega * t);
  }
  KOKKOS_INLINE_FUNCTION double logJ(const double* X, double t) const {
    double J = 1;
    for (int d = 0; d < dim; ++d) J *= stretch(X, t, d);
    return std::log(J);
  }
  // The body force per unit mass that makes the field exact.
  KOKKOS_INLINE_FUNCTION double bodyForce(const double* X, double t, int d) const {
    const double F = stretch(X, t, d), lnJ = logJ(X, t);
    const double divP = stretchGradient(X, t, d) * (mu + (mu + lambda * (1 - lnJ)) / (F * F));
    return acceleration(X, t, d) - divP / density;
  }
  // Cauchy stress sigma_dd = (mu (F_dd^2 - 1) + lambda ln J) / J; in plane strain d = 2 is the
  // out-of-plane component (F_zz = 1).
  KOKKOS_INLINE_FUNCTION double stress(const double* X, double t, int d) const {
    const double lnJ = logJ(X, t), J = std::exp(lnJ);
    const double F = d < dim ? stretch(X, t, d) : 1.0;
    return (mu * (F * F - 1) + lambda * lnJ) / J;
  }
};

}  // namespace impm
