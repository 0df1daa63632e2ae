// Where a lattice fill puts the particles of a cell along one direction, and the 1D
// Gauss-Legendre rules behind it (shared with the FE reference's Gauss points). Plain C++17.
#pragma once

#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

namespace impm {

// Per body (deck: Bodies/<name>/Particle Placement), for n particles per cell in a direction.
// Both give every particle the same volume, 1/n of the cell per direction.
enum class LatticePoints {
  // The cell split into n equal sub-boxes, a particle at each centre: the midpoint rule, which
  // integrates linear functions exactly per sub-box (a rectangle's second moment of area I comes
  // out low by the factor 1 - (d/H)^2, d the sub-box size across the depth H).
  Uniform,
  // The cell split into n/2 equal sub-boxes (n even), the 2-point Gauss-Legendre pair (the
  // sub-box centre +- its half width / sqrt(3), equal weights) in each: cubics exactly per
  // sub-box, so I exactly; and with n = 4 the sub-boxes are the half cells, the pieces on which
  // quadratic B-splines are polynomials.
  Gauss
};

// 1D Gauss-Legendre rule on [-1, 1]: n = 2 or 3 points xi with weights w.
inline void gaussLegendre(int n, std::vector<double>& xi, std::vector<double>& w) {
  if (n == 2) {
    xi = {-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)};
    w = {1.0, 1.0};
  } else if (n == 3) {
    xi = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  } else {
    throw std::invalid_argument("Gauss-Legendre rule of " + std::to_string(n) +
                                " points: only 2 and 3 are implemented");
  }
}

// The n particle positions of a cell along one direction, increasing, in units of the
// particle's share d = h / n of the cell (position = cell's first node + offset * d). Uniform
// gives a + 0.5 exactly, so that its positions are bit for bit those of the plain lattice.
// Throws for Gauss with an odd n.
inline std::vector<double> latticeOffsets(LatticePoints rule, int n) {
  std::vector<double> offsets;
  if (rule == LatticePoints::Uniform) {
    for (int a = 0; a < n; ++a) offsets.push_back(a + 0.5);
    return offsets;
  }
  if (n < 2 || n % 2)
    throw std::invalid_argument(
        "Gauss placement puts 2-point Gauss-Legendre pairs in sub-cells: particles per cell must "
        "be even, got " +
        std::to_string(n));
  std::vector<double> xi, w;
  gaussLegendre(2, xi, w);
  for (int k = 0; k < n / 2; ++k)  // sub-box k spans [2k, 2k + 2] shares, half width 1 share
    for (double x : xi) offsets.push_back(2 * k + 1 + x);
  return offsets;
}

}  // namespace impm
