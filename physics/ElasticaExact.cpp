#include "physics/ElasticaExact.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace impm {

namespace {

const double kHalfPi = 0.5 * M_PI;

double phi1Of(double p) { return std::asin(std::min(1.0, 1.0 / (p * std::sqrt(2.0)))); }

}  // namespace

CantileverElastica::CantileverElastica(double k) : k_(k) {
  if (!(k >= 0) || !std::isfinite(k))
    throw std::invalid_argument("elastica: the load parameter k must be >= 0 and finite");
  if (k == 0) return;
  // Bisection on the tip slope theta0 in (0, pi/2): the length condition K(p) - F(phi1, p) rises
  // with theta0 (p = sqrt((1 + sin theta0) / 2)). Bisection on theta0 rather than p keeps the
  // resolution where p crowds towards 1 (large k).
  const double target = std::sqrt(k);
  double lo = 0, hi = kHalfPi;
  for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    const double p = std::sqrt(0.5 * (1 + std::sin(mid)));
    const double g = std::comp_ellint_1(p) - std::ellint_1(p, phi1Of(p));
    (g < target ? lo : hi) = mid;
  }
  theta0_ = 0.5 * (lo + hi);
  p_ = std::sqrt(0.5 * (1 + std::sin(theta0_)));
  phi1_ = phi1Of(p_);
  F1_ = std::ellint_1(p_, phi1_);
  E1_ = std::ellint_2(p_, phi1_);
}

CantileverElastica::Point CantileverElastica::at(double sOverL) const {
  if (!(sOverL >= 0 && sOverL <= 1 + 1e-12)) throw std::invalid_argument("elastica: s/L must lie in [0, 1]");
  Point pt;
  if (k_ == 0) return pt;
  const double sk = std::sqrt(k_), s = std::min(sOverL, 1.0);
  // phi at arc length s: F(phi, p) = F1 + sqrt(k) s / L, F rising in phi (bisection on [phi1, pi/2]).
  const double Fs = F1_ + sk * s;
  double lo = phi1_, hi = kHalfPi;
  for (int it = 0; it < 200 && hi - lo > 1e-15; ++it) {
    const double mid = 0.5 * (lo + hi);
    (std::ellint_1(p_, mid) < Fs ? lo : hi) = mid;
  }
  const double phi = s >= 1.0 ? kHalfPi : 0.5 * (lo + hi);
  const double x = 2 * p_ * (std::cos(phi1_) - std::cos(phi)) / sk;
  const double dF = std::ellint_1(p_, phi) - F1_, dE = std::ellint_2(p_, phi) - E1_;
  pt.u = s - x;               // the shortening of the horizontal projection
  pt.w = (dF - 2 * dE) / sk;  // downward
  const double sinTheta = std::clamp(2 * p_ * p_ * std::sin(phi) * std::sin(phi) - 1, -1.0, 1.0);
  pt.theta = std::asin(sinTheta);  // theta in [0, theta0] within (-pi/2, pi/2)
  return pt;
}

}  // namespace impm
