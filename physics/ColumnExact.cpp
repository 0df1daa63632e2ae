#include "physics/ColumnExact.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace impm {

double SelfWeightColumnExact::stretch(double Y, double f) const {
  const double sigma = stressYY(Y, f);
  if (law == Law::Linear) return 1.0 + sigma / (lambda + 2 * mu);
  if (law == Law::J2) {
    // sigma_yy(e) = tau_yy(e) / exp(e) rises monotonically with e: bisection on [-3, 0] (compression).
    double lo = -3.0, hi = 0.0;
    for (int it = 0; it < 200 && hi - lo > 1e-16; ++it) {
      const double mid = 0.5 * (lo + hi);
      double tyy, txx;
      j2Kirchhoff(mid, tyy, txx);
      (tyy * std::exp(-mid) > sigma ? hi : lo) = mid;
    }
    return std::exp(0.5 * (lo + hi));
  }
  // phi(s) = mu (s^2 - 1) + lambda ln s - sigma s = 0; phi' = 2 mu s + lambda / s - sigma > 0 for
  // sigma <= 0 (compression), so Newton from s = 1 converges monotonically.
  double s = 1.0;
  for (int it = 0; it < 100; ++it) {
    const double phi = mu * (s * s - 1) + lambda * std::log(s) - sigma * s;
    const double dphi = 2 * mu * s + lambda / s - sigma;
    const double step = phi / dphi;
    s -= step;
    if (std::abs(step) < 1e-15 * s) return s;
  }
  throw std::runtime_error("self-weight column: the stretch did not converge (load beyond the neo-Hookean range?)");
}

double SelfWeightColumnExact::displacementY(double Y, double f) const {
  if (law == Law::Linear) {
    const double M = lambda + 2 * mu;
    return -f * density * gravity * (height * Y - 0.5 * Y * Y) / M;
  }
  static const double xi[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  static const double wi[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                               0.2369268850561891};
  const int intervals = 64;
  const double h = Y / intervals;
  double sum = 0;
  for (int k = 0; k < intervals; ++k)
    for (int q = 0; q < 5; ++q) sum += 0.5 * h * wi[q] * (stretch((k + 0.5) * h + 0.5 * h * xi[q], f) - 1.0);
  return sum;
}

double SelfWeightColumnExact::stressXX(double Y, double f) const {
  const double s = stretch(Y, f);
  if (law == Law::J2) {
    double tyy, txx;
    j2Kirchhoff(std::log(s), tyy, txx);
    return txx / s;
  }
  return law == Law::NeoHookean ? lambda * std::log(s) / s : lambda * (s - 1.0);
}

void SelfWeightColumnExact::j2Kirchhoff(double e, double& tauYY, double& tauXX) const {
  const double K = lambda + 2 * mu / 3, root23 = std::sqrt(2.0 / 3.0);
  const double d = root23 * std::abs(e);
  const double Gamma = std::max(0.0, (2 * mu * d - root23 * yieldStress) / (2 * mu + 2 * hardening / 3));
  const double q = 2 * mu * (d - Gamma);
  const double sign = e < 0 ? -1.0 : 1.0;
  // n = dev e / |dev e| = sign(e) (-1, 2, -1) / sqrt(6).
  tauYY = K * e + sign * 2.0 / std::sqrt(6.0) * q;
  tauXX = K * e - sign / std::sqrt(6.0) * q;
}

}  // namespace impm
