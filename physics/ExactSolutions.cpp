#include "physics/ExactSolutions.hpp"

#include <cmath>

namespace impm {

namespace {
const double kPi = std::acos(-1.0);
double ramp(double s) { return s > 0 ? s : 0.0; }
double step(double s) { return s > 0 ? 1.0 : (s < 0 ? 0.0 : 0.5); }
}  // namespace

// ---------------------------------------------------------------- bar under a step load

double BarStepExact::waveSpeed() const { return std::sqrt(E / rho); }

// Shared modal sum: sum_r (-1)^(r-1) / (2r-1)^p * f(k x) * [1 - cos(k c t)], k = (2r-1) pi / (2L);
// f = sin for displacement (p = 2), cos for stress (p = 1).
static double barSeries(const BarStepExact& b, double x, double t, int terms, bool stress) {
  if (t <= 0) return 0.0;
  const double c = b.waveSpeed();
  double sum = 0;
  for (int r = 1; r <= terms; ++r) {
    const double m = 2 * r - 1, k = m * kPi / (2 * b.L), sign = (r % 2) ? 1.0 : -1.0;
    const double shape = stress ? std::cos(k * x) / m : std::sin(k * x) / (m * m);
    sum += sign * shape * (1 - std::cos(k * c * t));
  }
  // u prefactor 8 F0 L / (pi^2 E A); E du/dx brings k = m pi / (2L), giving 4 F0 / (pi A).
  return stress ? 4 * b.F0 / (kPi * b.A) * sum : 8 * b.F0 * b.L / (kPi * kPi * b.E * b.A) * sum;
}

double BarStepExact::displacementSeries(double x, double t, int terms) const {
  return barSeries(*this, x, t, terms, false);
}
double BarStepExact::stressSeries(double x, double t, int terms) const { return barSeries(*this, x, t, terms, true); }

// Each n is one more transit pair of the front; once the leading argument (2n+1)L - x exceeds
// ct the front of that and every later n has not arrived yet, so the sum is finite.
double BarStepExact::displacementClosed(double x, double t) const {
  if (t <= 0) return 0.0;
  const double ct = waveSpeed() * t;
  double sum = 0;
  for (int n = 0; ct - (2 * n + 1) * L + x >= 0; ++n) {
    const double sign = (n % 2) ? -1.0 : 1.0;
    sum += sign * (ramp(ct - (2 * n + 1) * L + x) - ramp(ct - (2 * n + 1) * L - x));
  }
  return F0 / (E * A) * sum;
}

double BarStepExact::stressClosed(double x, double t) const {
  if (t <= 0) return 0.0;
  const double ct = waveSpeed() * t;
  double sum = 0;
  for (int n = 0; ct - ((2 * n + 1) * L - x) >= 0; ++n) {
    const double sign = (n % 2) ? -1.0 : 1.0;
    sum += sign * (step(ct - ((2 * n + 1) * L - x)) + step(ct - ((2 * n + 1) * L + x)));
  }
  return F0 / A * sum;
}

// ---------------------------------------------------------------- harmonically forced beam

double BeamHarmonicExact::omega1() const { return kPi * kPi / (L * L) * std::sqrt(E * I / rhoA); }

// Mode n: sin(n pi a/L) sin(n pi x/L) / (n^4 - (omega/omega_1)^2) * [sin(omega t) - omega/omega_n
// sin(omega_n t)], omega_n = n^2 omega_1. The curvature multiplies each term by -(n pi/L)^2.
static double beamSeries(const BeamHarmonicExact& b, double x, double t, int terms, bool curv) {
  if (t <= 0) return 0.0;
  const double w1 = b.omega1(), ratio2 = (b.omega / w1) * (b.omega / w1);
  double sum = 0;
  for (int n = 1; n <= terms; ++n) {
    const double kn = n * kPi / b.L, wn = double(n) * n * w1;
    double term = std::sin(kn * b.a) * std::sin(kn * x) / (double(n) * n * n * n - ratio2) *
                  (std::sin(b.omega * t) - b.omega / wn * std::sin(wn * t));
    sum += curv ? -kn * kn * term : term;
  }
  return 2 * b.F0 * b.L * b.L * b.L / (kPi * kPi * kPi * kPi * b.E * b.I) * sum;
}

double BeamHarmonicExact::deflection(double x, double t, int terms) const {
  return beamSeries(*this, x, t, terms, false);
}
double BeamHarmonicExact::curvature(double x, double t, int terms) const {
  return beamSeries(*this, x, t, terms, true);
}
double BeamHarmonicExact::bendingStress(double x, double yFromNeutralAxis, double t, int terms) const {
  return -E * yFromNeutralAxis * curvature(x, t, terms);
}

// ---------------------------------------------------------------- standing wave in a fixed-fixed bar

double BarStandingWaveExact::waveSpeed() const { return std::sqrt(E / rho); }
double BarStandingWaveExact::omega() const { return waveSpeed() * n * kPi / L; }
double BarStandingWaveExact::displacement(double x, double t) const {
  return V / omega() * std::sin(n * kPi * x / L) * std::sin(omega() * t);
}
double BarStandingWaveExact::velocity(double x, double t) const {
  return V * std::sin(n * kPi * x / L) * std::cos(omega() * t);
}
// E du/dx = E (V / omega) (n pi / L) cos(n pi x / L) sin(omega t) = E V / c cos(...) sin(omega t).
double BarStandingWaveExact::stress(double x, double t) const {
  return E * V / waveSpeed() * std::cos(n * kPi * x / L) * std::sin(omega() * t);
}

}  // namespace impm
