// Beam solutions for the verification budget of Problem 2 (shared/reference/benchmarks.md):
// simply supported beam under a point force F0 sin(omega t) at x = a, from rest.
//
//  * TimoshenkoBeamHarmonic: the same problem in Timoshenko beam theory (shear deformation and
//    rotary inertia), exact modal solution. Against BeamHarmonicExact (Euler-Bernoulli) it
//    measures what shear and rotary inertia contribute (about 0.4% on omega_1 at h/L = 0.05).
//  * Newmark histories: the SAME modal series (Euler-Bernoulli or Timoshenko), each modal
//    coordinate advanced by Newmark's average-acceleration rule (beta = 1/4, gamma = 1/2) with
//    step dt from rest, load sampled at the step times. That is what an integration that is
//    exact in space and Newmark in time produces, so w_Newmark - w_exact isolates the time
//    discretisation error (period elongation, (omega dt)^2 / 12 to leading order).
//
// References:
//  S. P. Timoshenko, "On the correction for shear of the differential equation for transverse
//    vibrations of prismatic bars", Philosophical Magazine 41 (1921) 744-746.
//  S. M. Han, H. Benaroya, T. Wei, "Dynamics of transversely vibrating beams using four
//    engineering theories", J. Sound Vib. 225(5) (1999) 935-988 (simply supported Timoshenko
//    beam: frequency equation and modes).
//  G. R. Cowper, "The shear coefficient in Timoshenko's beam theory", J. Appl. Mech. 33 (1966)
//    335-340.
//  N. M. Newmark, "A method of computation for structural dynamics", J. Eng. Mech. Div. ASCE 85
//    (1959) 67-94; period of the average-acceleration rule: T. J. R. Hughes, The Finite Element
//    Method (1987), ch. 9.
//
// Plain C++17, no Trilinos or Kokkos.
#pragma once

#include <vector>

#include "physics/ExactSolutions.hpp"

namespace impm {

// ---------------------------------------------------------------- one modal coordinate
// q'' + W^2 q = g sin(w t).

// Exact response from rest: g / (W^2 - w^2) * (sin(w t) - (w/W) sin(W t)). Singular at w = W
// (resonance), which the callers avoid.
double harmonicModalResponse(double W, double g, double w, double t);

// Newmark average acceleration with step dt, from q(0) = q0, q'(0) = v0, a(0) = g sin(0) - W^2 q0
// (from the equation), load sampled at the step times. Returns q at t = 0, dt, ..., steps*dt.
std::vector<double> newmarkModalHistory(double W, double g, double w, double dt, int steps, double q0 = 0.0,
                                        double v0 = 0.0);

// Frequency at which the average-acceleration rule advances a free mode of frequency W:
// (2/dt) atan(W dt / 2) = W (1 - (W dt)^2 / 12 + ...), i.e. period elongation (W dt)^2 / 12.
double newmarkFrequency(double W, double dt);

// ---------------------------------------------------------------- Euler-Bernoulli helpers
// BeamHarmonicExact (physics/ExactSolutions.hpp) keeps its interface; these add histories.

// w(x, k dt), k = 0..steps, of the exact modal series (same as BeamHarmonicExact::deflection).
std::vector<double> deflectionHistory(const BeamHarmonicExact& b, double x, double dt, int steps, int terms = 200);
// The same series with each modal coordinate advanced by Newmark average acceleration.
std::vector<double> deflectionHistoryNewmark(const BeamHarmonicExact& b, double x, double dt, int steps,
                                             int terms = 200);

// ---------------------------------------------------------------- Timoshenko beam
// Simply supported Timoshenko beam, point force F0 sin(forceOmega t) at x = a, zero
// initial conditions:
//   rho A w_tt - kappa G A (w_xx - psi_x) = F(t) delta(x - a)
//   rho I psi_tt - E I psi_xx - kappa G A (w_x - psi) = 0
// with w = psi_x = 0 at both ends. Modes w = W_n(t) sin(k x), psi = Psi_n(t) cos(k x),
// k = n pi / L, give per n the 2x2 system M q'' + K q = f, q = (W_n, Psi_n):
//   M = diag(rho A, rho I),
//   K = [[kappa G A k^2, -kappa G A k], [-kappa G A k, E I k^2 + kappa G A]],
//   f = [(2/L) sin(k a) F(t), 0].
// Its generalized eigenproblem has two branches per n: branch 0 (bending, -> the Euler-Bernoulli
// n^2 omega_1 for a slender beam) and branch 1 (shear, about sqrt(kappa G A / (rho I)) and up).
// Each mass-normalised eigenvector phi (phi^T M phi = 1) turns the system into eta'' + W^2 eta =
// phi_w (2/L) sin(k a) F0 sin(forceOmega t), solved exactly from rest (harmonicModalResponse), and
// W_n = sum over both branches of phi_w eta.
struct TimoshenkoBeamHarmonic {
  double L, a;  // span, load position (from the left support)
  double E, G;  // bending modulus (E or E/(1-nu^2), caller decides) and shear modulus
  // Shear coefficient: 5/6 for a rectangle; Cowper (1966) gives 10(1+nu)/(12+11nu) (0.850 at
  // nu = 0.3).
  double kappa = 5.0 / 6.0;
  double A, I;        // cross-section area and second moment
  double rho;         // density (rho A per length, rho I rotary inertia)
  double F0;          // force amplitude (N)
  double forceOmega;  // its angular frequency (rad/s); not "omega", which names the natural frequencies

  struct Mode {
    double omega;   // natural frequency (rad/s)
    double weight;  // phi_w^2 of the mass-normalised eigenvector (-> 1/(rho A) for branch 0 of a slender beam)
  };
  // Mode n >= 1, branch 0 (bending, lower) or 1 (shear, upper).
  Mode mode(int n, int branch) const;
  double omega(int n, int branch = 0) const { return mode(n, branch).omega; }

  double deflection(double x, double t, int terms = 200) const;
  // w(x, k dt), k = 0..steps: the exact series, and the same series advanced by Newmark.
  std::vector<double> deflectionHistory(double x, double dt, int steps, int terms = 200) const;
  std::vector<double> deflectionHistoryNewmark(double x, double dt, int steps, int terms = 200) const;
};

}  // namespace impm
