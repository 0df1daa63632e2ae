// A column compacting under its own weight (AMPLE's test: Coombs & Augarde, "AMPLE: a material
// point learning environment", 2020; Charlton, Coombs & Augarde 2017): a body of reference
// height l0 on a fixed base, rollers on both sides (no lateral displacement), under a body
// force rho0 g along -y scaled by a load factor f. The motion is 1D, x = X, y = phi(Y), and
// quasi-static equilibrium in the reference configuration gives the first Piola-Kirchhoff
// stress exactly, for any material:
//   dP_yy/dY = f rho0 g,  P_yy(l0) = 0   =>   P_yy(Y) = -f rho0 g (l0 - Y).
// With F = diag(1, s), J = s, the Cauchy stress is sigma_yy = P_yy s / J = P_yy: also exact.
// The stretch s(Y) follows from the material law:
//   linear elastic (small strain):  s = 1 + sigma_yy / M,  M = lambda + 2 mu (constrained modulus);
//   neo-Hookean:  sigma_yy = (mu (s^2 - 1) + lambda ln s) / s,  solved for s by Newton;
//   J2 plasticity (Hencky, linear hardening; physics/materials/J2PlasticityModel.hpp): uniaxial
//     strain e = ln s is a proportional path, so with K = lambda + 2 mu / 3 and
//     d = sqrt(2/3) |e| (the norm of dev e),
//       tau_yy = K e + sign(e) sqrt(2/3) q,  q = 2 mu d (elastic) or
//       q = 2 mu (d - Gamma), Gamma = (2 mu d - sqrt(2/3) sigma_y) / (2 mu + 2 H / 3),
//     and sigma_yy = tau_yy / s, solved for e by bisection (monotone in e);
// and the displacement is u_y(Y) = int_0^Y (s - 1) dY (closed form for the linear law, 5-point
// Gauss-Legendre on 64 intervals for neo-Hookean: exact to round-off for this smooth integrand).
// The lateral stress is sigma_xx = lambda (s - 1) (linear), lambda ln s / s (neo-Hookean), or
// (K e - sign(e) q / sqrt(6)) / s (J2).
#pragma once

namespace impm {

struct SelfWeightColumnExact {
  double height = 1, density = 1, gravity = 1;  // l0, rho0, g (magnitude, acting along -y)
  double lambda = 0, mu = 1;
  enum class Law { Linear, NeoHookean, J2 } law = Law::Linear;
  double yieldStress = 0, hardening = 0;  // J2

  // Y is measured from the base (reference configuration); f is the load factor.
  double stressYY(double Y, double f) const { return -f * density * gravity * (height - Y); }
  double stretch(double Y, double f) const;
  double displacementY(double Y, double f) const;
  double stressXX(double Y, double f) const;
  // J2: the Kirchhoff tau_yy and tau_xx at log strain e (uniaxial strain).
  void j2Kirchhoff(double e, double& tauYY, double& tauXX) const;
};

}  // namespace impm
