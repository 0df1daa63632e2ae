// Unit tests of the exact solutions (physics/ExactSolutions.hpp) against the reference values of
// shared/reference/benchmarks.md and against each other (series vs closed form, series vs finite
// differences), so that a wrong formula cannot silently become the yardstick of the MPM results.
#include <Teuchos_UnitTestHarness.hpp>

#include <algorithm>
#include <cmath>
#include <initializer_list>

#include "physics/ExactSolutions.hpp"

namespace {

using impm::BarStepExact;
using impm::BeamHarmonicExact;

const double kPi = std::acos(-1.0);
const double kNu = 0.3;

// Problem 1 with the given E (plane stress / 1D) or the plane-strain bar modulus E/(1 - nu^2).
BarStepExact bar(bool planeStrain = false) {
  const double E = 200e9;
  return BarStepExact{0.03, 5e-7, planeStrain ? E / (1 - kNu * kNu) : E, 7800.0, 1.0};
}

// Problem 2 with a = L/2 and omega = 150 rad/s.
BeamHarmonicExact beam() {
  return BeamHarmonicExact{10.0, 5.0, 200e9, 0.5 * 0.5 * 0.5 / 12, 7800.0 * 0.5, -4.0, 150.0};
}

// benchmarks.md prints its reference values rounded to a unit `ulp` of the last digit, so a
// correct formula is within 0.5 ulp; 0.6 ulp leaves room for summation order and libm, while a
// wrong formula (e.g. the talk's sin(n^2 omega t) typo) misses by many ulp.
const double kUlpTol = 0.6;

}  // namespace

TEUCHOS_UNIT_TEST(ExactSolutions, BarReferenceValues) {
  const BarStepExact b = bar();
  const double L = b.L;
  TEST_COMPARE(std::abs(b.waveSpeed() - 5063.7), <=, kUlpTol * 0.1);
  // The reference values were computed with the 2000-term series (the default).
  TEST_COMPARE(std::abs(b.displacementSeries(L, 1e-5) - 5.063e-7), <=, kUlpTol * 1e-10);
  TEST_COMPARE(std::abs(b.displacementSeries(L / 2, 1e-5) - 3.000e-7), <=, kUlpTol * 1e-10);
  TEST_COMPARE(std::abs(b.displacementSeries(L, 1e-4) - 2.637e-7), <=, kUlpTol * 1e-10);
  // Static tip displacement F0 L / (E A) = 3.0e-7 (the mean of the oscillation at x = L).
  TEST_FLOATING_EQUALITY(b.F0 * L / (b.E * b.A), 3.0e-7, 1e-12);
}

TEUCHOS_UNIT_TEST(ExactSolutions, BarClosedFormStressFronts) {
  // A front of F0/A leaves x = L, doubles the stress on reflecting at x = 0, brings it back to
  // F0/A (the applied traction) on reflecting at x = L, and leaves zero after the next x = 0
  // reflection: period 4 L/c. Points at x = L/4 and 3L/4, mid-transit (a quarter L from fronts).
  struct Case {
    double x, transits, stressOverS;
  };
  const Case cases[] = {{0.75, 0.5, 1}, {0.25, 0.5, 0}, {0.75, 1.5, 1}, {0.25, 1.5, 2}, {0.75, 2.5, 1},
                        {0.25, 2.5, 2}, {0.75, 3.5, 1}, {0.25, 3.5, 0}, {0.75, 4.5, 1}, {0.25, 4.5, 0}};
  for (bool planeStrain : {false, true}) {
    const BarStepExact b = bar(planeStrain);
    const double T = b.L / b.waveSpeed(), s = b.F0 / b.A;
    for (const Case& k : cases) {
      // Sums of +-1 in double: exact.
      TEST_EQUALITY(b.stressClosed(k.x * b.L, k.transits * T), k.stressOverS * s);
    }
    // The traction end always carries F0/A once loaded (checked past 10 periods).
    TEST_EQUALITY(b.stressClosed(b.L, 43.3 * T), s);
    TEST_EQUALITY_CONST(b.displacementClosed(b.L, 0.0), 0.0);
    TEST_EQUALITY_CONST(b.stressClosed(b.L, -1e-6), 0.0);
    TEST_EQUALITY_CONST(b.displacementSeries(b.L, 0.0), 0.0);
  }
}

TEUCHOS_UNIT_TEST(ExactSolutions, BarDisplacementSeriesMatchesClosedForm) {
  // The series tail after N terms is bounded by 8/pi^2 * 2 * sum_{odd m > 2N} 1/m^2 ~
  // 16/pi^2 / (4N) = 2.0e-4 of the static tip displacement at N = 2000 (|sin (1 - cos)| <= 2).
  // It is reached at the kinks of u (the fronts), where convergence is only O(1/N): measured
  // 1.02e-4 over this grid for both moduli, so the ~1e-5 one might expect from 1/N^2 is too tight.
  const int N = 2000;
  const double tol = 16 / (kPi * kPi) / (4.0 * N);
  for (bool planeStrain : {false, true}) {
    const BarStepExact b = bar(planeStrain);
    const double uStatic = b.F0 * b.L / (b.E * b.A);
    double worst = 0;
    for (int i = 0; i <= 30; ++i) {
      for (int j = 0; j <= 100; ++j) {
        const double x = b.L * i / 30, t = 1e-4 * j / 100;
        const double err = std::abs(b.displacementSeries(x, t, N) - b.displacementClosed(x, t)) / uStatic;
        worst = std::max(worst, err);
      }
    }
    out << (planeStrain ? "E/(1-nu^2)" : "E") << ": max |series - closed| / u_static = " << worst << "\n";
    TEST_COMPARE(worst, <=, tol);
    TEST_COMPARE(worst, >, 0.0);  // guards against comparing a function with itself
  }
}

TEUCHOS_UNIT_TEST(ExactSolutions, BarStressSeriesMatchesClosedFormAwayFromFronts) {
  // Stress = (4 F0 / (pi A)) sum (-1)^(r-1)/m cos(k x)(1 - cos(k c t)): three square-wave series
  // (weights 1, 1/2, 1/2) in phases k x, k (x +- c t). At phase distance pi d / (2L) from a jump
  // the tail after 2N odd harmonics is about 1 / (2N pi d / (2L)), so the error is about
  // 8 L / (pi^2 N d) F0/A: 4.1e-3 at d = L/10 and N = 2000 (measured 1.4e-3). Points within
  // L/10 of a front, or of the free end x = L where the series always gives 0, are skipped.
  const int N = 2000;
  const double margin = 0.1;
  const double tol = 8 / (kPi * kPi * N * margin);
  for (bool planeStrain : {false, true}) {
    const BarStepExact b = bar(planeStrain);
    const double L = b.L, c = b.waveSpeed();
    double worst = 0;
    int checked = 0;
    for (int i = 0; i <= 20; ++i) {
      for (int j = 1; j <= 200; ++j) {
        const double x = L * i / 20, t = 1e-4 * j / 200;
        // Fronts sit where c t + x or c t - x is L modulo 2L.
        const double d = std::min(
            {std::abs(std::remainder(c * t + x - L, 2 * L)), std::abs(std::remainder(c * t - x - L, 2 * L)), L - x});
        if (d < margin * L) continue;
        ++checked;
        worst = std::max(worst, std::abs(b.stressSeries(x, t, N) - b.stressClosed(x, t)) * b.A / b.F0);
      }
    }
    out << "checked " << checked << " points, max |series - closed| / (F0/A) = " << worst << "\n";
    TEST_COMPARE(checked, >, 1000);
    TEST_COMPARE(worst, <=, tol);
  }
}

TEUCHOS_UNIT_TEST(ExactSolutions, BeamReferenceValues) {
  const BeamHarmonicExact b = beam();
  TEST_COMPARE(std::abs(b.omega1() - 72.135), <=, kUlpTol * 1e-3);
  // The reference values were computed with the 200-term series (the default).
  TEST_COMPARE(std::abs(b.deflection(b.L / 2, 0.05) - 2.172e-8), <=, kUlpTol * 1e-11);
  TEST_COMPARE(std::abs(b.deflection(b.L / 2, 0.2) - -3.485e-8), <=, kUlpTol * 1e-11);
  TEST_COMPARE(std::abs(b.deflection(b.L / 2, 1.0) - -1.093e-8), <=, kUlpTol * 1e-11);
}

TEUCHOS_UNIT_TEST(ExactSolutions, BeamStartsAtRest) {
  // Zero initial displacement and velocity is what the corrected sin(n^2 omega_1 t) buys. The
  // forward difference w(h)/h of a function with w(0) = w'(0) = 0 vanishes with h (at the load
  // point like h^2 once h < 1/omega_200); with h = 1e-7 s it must be far below the velocity scale
  // w_static * omega ~ 6e-6 m/s: measured 5e-15 m/s at x = a, < 1e-20 elsewhere. The typo
  // sin(n^2 omega t) would give a velocity of order the scale itself.
  const BeamHarmonicExact b = beam();
  const double wStatic = std::abs(b.F0) * std::pow(b.L, 3) / (48 * b.E * b.I);
  const double vScale = wStatic * b.omega, h = 1e-7;
  for (double x : {1.0, 2.5, 5.0, 7.7}) {
    TEST_EQUALITY_CONST(b.deflection(x, 0.0), 0.0);
    TEST_COMPARE(std::abs(b.deflection(x, h) - b.deflection(x, 0.0)) / h, <=, 1e-6 * vScale);
  }
  // Nonzero afterwards, so the test above is not passing on an all-zero function.
  TEST_COMPARE(std::abs(b.deflection(b.L / 2, 0.05)), >, 0.1 * wStatic);
}

TEUCHOS_UNIT_TEST(ExactSolutions, BeamCurvatureMatchesFiniteDifference) {
  // Central second difference with hx = 1 cm, away from the load point (w''' jumps there). Its
  // truncation error hx^2/12 w'''' ~ 1e-4/12 (pi/L)^2 |w''| ~ 1e-6 of the curvature for the
  // dominant low modes and roundoff eps w / hx^2 ~ 1e-11 of it; measured 5e-7 of the scale.
  const BeamHarmonicExact b = beam();
  const double kScale = std::abs(b.F0) * b.L / (4 * b.E * b.I);  // static mid-span curvature
  const double hx = 1e-2;
  for (double x : {1.3, 2.5, 4.0, 6.2, 7.7, 9.5}) {
    for (double t : {0.01, 0.05, 0.2, 0.5, 1.0}) {
      const double fd = (b.deflection(x + hx, t) - 2 * b.deflection(x, t) + b.deflection(x - hx, t)) / (hx * hx);
      TEST_COMPARE(std::abs(b.curvature(x, t) - fd), <=, 1e-5 * kScale);
    }
  }
  // Bending stress -E y w'': positive (tension) at the bottom fibre where the beam sags (w'' > 0).
  const double k = b.curvature(b.L / 2, 0.2), y = -0.25;
  TEST_FLOATING_EQUALITY(b.bendingStress(b.L / 2, y, 0.2), -b.E * y * k, 1e-14);
}
