// The Newmark family on the grid:
//   u     = dt v + dt^2 ((1/2 - beta) a + beta a_new)   ->  a_new = c1 u - c2 v - c3 a
//   v_new = v + dt ((1 - gamma) a + gamma a_new)
// Average acceleration (beta = 1/4, gamma = 1/2, the default) conserves energy; gamma > 1/2 damps
// the highest frequencies (most with beta = (gamma + 1/2)^2 / 4).
#pragma once

#include <Kokkos_Macros.hpp>

namespace impm {

struct NewmarkScheme {
  double beta = 0.25, gamma = 0.5;
  double c1(double dt) const { return 1.0 / (beta * (dt * dt)); }
  double c2(double dt) const { return 1.0 / (beta * dt); }
  double c3() const { return 0.5 / beta - 1.0; }
  bool averageAcceleration() const { return beta == 0.25 && gamma == 0.5; }
};

// The constants of one step, captured by value in the kernels.
struct NewmarkConstants {
  double c1, c2, c3, dt, gamma;
  NewmarkConstants(const NewmarkScheme& s, double stepSize)
      : c1(s.c1(stepSize)), c2(s.c2(stepSize)), c3(s.c3()), dt(stepSize), gamma(s.gamma) {}
  // a_new of a component that moved by u over the step from v, a.
  KOKKOS_INLINE_FUNCTION double newAcceleration(double u, double v, double a) const { return c1 * u - c2 * v - c3 * a; }
  // v_new - v = dt ((1 - gamma) a + gamma a_new).
  KOKKOS_INLINE_FUNCTION double velocityChange(double a, double aNew) const {
    return dt * ((1 - gamma) * a + gamma * aNew);
  }
};

}  // namespace impm
