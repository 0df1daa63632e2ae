// Exact solutions of the two verification problems (shared/reference/benchmarks.md), used to
// check MPM results. Plain C++17, no Trilinos or Kokkos, so tests and tools can use it anywhere.
#pragma once

namespace impm {

// Problem 1: 1D rod fixed at x=0, step force F0 at x=L from t=0 (Meirovitch).
struct BarStepExact {
  double L, A, E, rho, F0;   // E is the modulus the comparison uses (E or E/(1-nu^2)); caller decides
  double waveSpeed() const;  // sqrt(E/rho)
  // Modal series of benchmarks.md; converges like 1/(2r-1)^2.
  double displacementSeries(double x, double t, int terms = 2000) const;
  // E du/dx of the same series; converges only like 1/(2r-1) and rings (Gibbs) at the fronts.
  double stressSeries(double x, double t, int terms = 2000) const;
  // d'Alembert: F0/(E A) * sum_n (-1)^n [R(ct-(2n+1)L+x) - R(ct-(2n+1)L-x)], R(s) = max(s,0).
  double displacementClosed(double x, double t) const;
  // F0/A * sum_n (-1)^n [H(ct-((2n+1)L-x)) + H(ct-((2n+1)L+x))], with H(0) = 1/2 (the value the
  // series converges to on a front).
  double stressClosed(double x, double t) const;
};

// Problem 2: simply supported Euler-Bernoulli beam, force F0 sin(omega t) at x=a (Volterra &
// Zachmanoglou), typo corrected: last sine is sin(n^2 omega_1 t). Singular if omega equals a
// natural frequency n^2 omega_1 (resonance), which the benchmark avoids (omega/omega_1 = 2.08).
struct BeamHarmonicExact {
  double L, a, E, I, rhoA, F0, omega;
  double omega1() const;  // (pi^2/L^2) sqrt(E I / rhoA)
  double deflection(double x, double t, int terms = 200) const;
  double curvature(double x, double t, int terms = 200) const;  // d2w/dx2 (same series differentiated)
  // axial bending stress at height yFromNeutralAxis (positive up): -E * y * curvature
  double bendingStress(double x, double yFromNeutralAxis, double t, int terms = 200) const;
};

// Free vibration of a rod fixed at both ends (x = 0 and x = L), started from zero displacement
// with the velocity V sin(n pi x / L) (one standing-wave mode): u = (V / omega) sin(n pi x / L)
// sin(omega t), omega = c n pi / L, c = sqrt(E / rho). Linear small-strain theory.
struct BarStandingWaveExact {
  double L, E, rho, V;  // E is the modulus the comparison uses (E or E/(1-nu^2)); caller decides
  int n;
  double waveSpeed() const;  // sqrt(E/rho)
  double omega() const;      // c n pi / L
  double displacement(double x, double t) const;
  double velocity(double x, double t) const;
  double stress(double x, double t) const;  // E du/dx
};

}  // namespace impm
