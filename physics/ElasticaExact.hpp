// The elastica of a cantilever under a dead vertical end load (Bisshopp & Drucker 1945; tip
// values tabulated by Mattiasson 1981): an inextensible, shear-rigid Euler-Bernoulli beam of
// length L and bending stiffness EI, clamped horizontally at s = 0, with a force P of fixed
// direction (downward) at s = L; load parameter k = P L^2 / (EI).
// With theta(s) the slope (positive downward), EI theta' = P (x_L - x(s)) and theta'(L) = 0 give
//   EI theta'^2 / 2 = P (sin theta0 - sin theta),   theta0 the tip slope.
// The substitution 1 + sin theta = 2 p^2 sin^2 phi, p^2 = (1 + sin theta0) / 2, turns the length
// condition into  sqrt(k) = K(p) - F(phi1, p),  sin phi1 = 1 / (p sqrt 2),  solved for p by
// bisection (the right side rises monotonically from 0 at p = 1/sqrt 2 to infinity at p = 1), and
// the point at phi in [phi1, pi/2] lies at
//   s / L = (F(phi, p) - F(phi1, p)) / sqrt(k),
//   x / L = 2 p (cos phi1 - cos phi) / sqrt(k),
//   y / L = -(F(phi, p) - F(phi1, p) - 2 (E(phi, p) - E(phi1, p))) / sqrt(k)   (y up, the load down),
// so at the tip (phi = pi/2): u/L = 1 - 2 p cos phi1 / sqrt(k), w/L = 1 - 2 (E(p) - E(phi1, p)) / sqrt(k).
// F, E: Legendre's incomplete elliptic integrals of modulus p (std::ellint_1, std::ellint_2).
#pragma once

namespace impm {

class CantileverElastica {
 public:
  // k = P L^2 / (EI) >= 0.
  explicit CantileverElastica(double k);
  double loadParameter() const { return k_; }
  double tipSlope() const { return theta0_; }  // rad, positive downward
  // The centreline at arc length s / L in [0, 1]: displacements (u along x, w downward, both / L)
  // and the slope theta (rad, positive downward).
  struct Point {
    double u = 0, w = 0, theta = 0;
  };
  Point at(double sOverL) const;
  Point tip() const { return at(1.0); }

 private:
  double k_ = 0, p_ = 0, phi1_ = 0, theta0_ = 0, F1_ = 0, E1_ = 0;
};

}  // namespace impm
