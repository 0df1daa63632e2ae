// Unit tests of the layered-rod exact solution (physics/LayeredBarExact.hpp): against the
// homogeneous closed form (BarStepExact), against the textbook transmission/reflection plateaus,
// against its own displacement by finite differences, against the boundary conditions and
// against the energy balance, so that a wrong sign or coefficient cannot become a yardstick.
#include <Teuchos_UnitTestHarness.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include "physics/ExactSolutions.hpp"
#include "physics/LayeredBarExact.hpp"

namespace {

using impm::BarStepExact;
using impm::LayeredBarExact;
using Segment = LayeredBarExact::Segment;

// The benchmark bar of test_exact_solutions.cpp: L = 30 mm, A = 5e-7 m^2, F0 = 1 N.
const double kL = 0.03, kA = 5e-7, kF0 = 1.0, kS = kF0 / kA;
const double kEsteel = 200e9, kRhoSteel = 7800, kEal = 70e9, kRhoAl = 2700;

Segment steel(double x0, double x1) { return Segment{x0, x1, kEsteel, kRhoSteel}; }
Segment aluminium(double x0, double x1) { return Segment{x0, x1, kEal, kRhoAl}; }

// Steel | aluminium (the two-layer case of the brief) and steel | aluminium | steel with unequal
// lengths (two interfaces, incommensurate transit times), both loaded at x = L.
std::vector<Segment> twoLayers() { return {steel(0, 0.015), aluminium(0.015, kL)}; }
std::vector<Segment> threeLayers() { return {steel(0, 0.010), aluminium(0.010, 0.022), steel(0.022, kL)}; }

// Time the first front needs from x = L to x = 0 (the sum of the transit times).
double fullTransit(const std::vector<Segment>& segs) {
  double t = 0;
  for (const Segment& s : segs) t += (s.xEnd - s.xBegin) / std::sqrt(s.E / s.rho);
  return t;
}

}  // namespace

TEUCHOS_UNIT_TEST(LayeredBar, OneSegmentMatchesBarStepClosedForm) {
  // Both are sums of the same few ramps and steps (at most 3 transits: 4 front pieces); only the
  // rounding of the arrival times differs (~1e-16 relative), so 1e-12 of the scales is loose for a
  // correct solution and any wrong sign or speed misses by O(1). Points are >= L/160 from fronts.
  const BarStepExact b{kL, kA, kEsteel, kRhoSteel, kF0};
  const double T = kL / b.waveSpeed();
  const LayeredBarExact bar({steel(0, kL)}, kA, kF0, 3.5 * T);
  TEST_EQUALITY(bar.frontCount(), std::size_t(4));  // start times 0, T, 2T, 3T; no spurious fronts
  const double uScale = kF0 * kL / (kEsteel * kA), vScale = kS / bar.impedance(0), dt = 1e-3 * T;
  double worstU = 0, worstS = 0, worstV = 0;
  for (int i = -1; i <= 16; ++i) {
    // x = 0, the 16 cell centres (i + 1/2) L/16, and x = L.
    const double x = i < 0 ? 0.0 : (i == 16 ? kL : (i + 0.5) * kL / 16);
    for (int j = 0; j < 24; ++j) {
      // c t / L = (j + 0.3)/8 keeps c t +- x at least L/160 away from the fronts (odd/even L).
      const double t = (j + 0.3) * T / 8;
      worstU = std::max(worstU, std::abs(bar.displacement(x, t) - b.displacementClosed(x, t)) / uScale);
      worstS = std::max(worstS, std::abs(bar.stress(x, t) - b.stressClosed(x, t)) / kS);
      // The closed-form displacement is linear in t between fronts: its central difference is
      // the velocity up to rounding eps * L / (c dt) ~ 1e-13.
      const double vFd = (b.displacementClosed(x, t + dt) - b.displacementClosed(x, t - dt)) / (2 * dt);
      worstV = std::max(worstV, std::abs(bar.velocity(x, t) - vFd) / vScale);
    }
  }
  out << "max error / scale: u " << worstU << ", stress " << worstS << ", velocity (vs FD) " << worstV << "\n";
  TEST_COMPARE(worstU, <=, 1e-12);
  TEST_COMPARE(worstS, <=, 1e-12);
  TEST_COMPARE(worstV, <=, 1e-10);
  // Non-trivial: the stress doubles at the fixed end after the first reflection (c t = 1.5 L).
  TEST_FLOATING_EQUALITY(bar.stress(0.25 * kL, 1.5 * T), 2 * kS, 1e-14);
}

TEUCHOS_UNIT_TEST(LayeredBar, TwoIdenticalSegmentsEqualOne) {
  // Equal impedances give R = 0 exactly, so the split bar has the same fronts, each cut in two
  // pieces; arrival times differ only by rounding (T1 + T2 vs T), hence 1e-12 of the scales.
  const double T = kL / std::sqrt(kEsteel / kRhoSteel), tMax = 3.5 * T;
  const LayeredBarExact one({steel(0, kL)}, kA, kF0, tMax);
  const LayeredBarExact two({steel(0, 0.011), steel(0.011, kL)}, kA, kF0, tMax);
  TEST_EQUALITY(two.frontCount(), 2 * one.frontCount());  // no reflected front at the interface
  const double uScale = kF0 * kL / (kEsteel * kA), vScale = kS / one.impedance(0);
  double worstU = 0, worstS = 0, worstV = 0;
  for (int i = 0; i <= 30; ++i) {
    const double x = i * kL / 30;  // includes the interface region and both ends
    for (int j = 0; j < 24; ++j) {
      const double t = (j + 0.3) * T / 8;  // away from fronts at these x (see the test above)
      const LayeredBarExact::State a = one.state(x, t), b = two.state(x, t);
      worstU = std::max(worstU, std::abs(a.displacement - b.displacement) / uScale);
      worstS = std::max(worstS, std::abs(a.stress - b.stress) / kS);
      worstV = std::max(worstV, std::abs(a.velocity - b.velocity) / vScale);
    }
  }
  out << "max |two - one| / scale: u " << worstU << ", stress " << worstS << ", velocity " << worstV << "\n";
  TEST_COMPARE(worstU, <=, 1e-12);
  TEST_COMPARE(worstS, <=, 1e-12);
  TEST_COMPARE(worstV, <=, 1e-12);
}

TEUCHOS_UNIT_TEST(LayeredBar, SteelAluminiumPlateaus) {
  // Plateau values are one or two products of exact coefficients: rounding ~1e-16, so 1e-13
  // relative; the impedances are recomputed here as sqrt(E rho) independently of the class.
  TEST_FLOATING_EQUALITY(LayeredBarExact::transmissionCoefficient(1.0, 3.0), 1.5, 1e-15);
  TEST_FLOATING_EQUALITY(LayeredBarExact::reflectionCoefficient(1.0, 3.0), 0.5, 1e-15);
  TEST_FLOATING_EQUALITY(LayeredBarExact::reflectionCoefficient(3.0, 1.0), -0.5, 1e-15);

  const double Zst = std::sqrt(kEsteel * kRhoSteel), Zal = std::sqrt(kEal * kRhoAl);
  const double Tst = 0.015 / std::sqrt(kEsteel / kRhoSteel), Tal = 0.015 / std::sqrt(kEal / kRhoAl);
  const LayeredBarExact bar(twoLayers(), kA, kF0, 6 * Tal);
  TEST_FLOATING_EQUALITY(bar.impedance(0), Zst, 1e-14);
  TEST_FLOATING_EQUALITY(bar.impedance(1), Zal, 1e-14);
  const double T = LayeredBarExact::transmissionCoefficient(Zal, Zst);  // aluminium -> steel
  const double R = LayeredBarExact::reflectionCoefficient(Zal, Zst);    // back into aluminium
  TEST_COMPARE(T - 1, >, 0.4);  // steel is ~2.9x stiffer in impedance: a clear step up (T ~ 1.48)

  const double xSt = 0.0075, xAl = 0.0225;  // mid-segment points
  TEST_FLOATING_EQUALITY(bar.firstArrival(xAl), 0.5 * Tal, 1e-13);
  TEST_FLOATING_EQUALITY(bar.firstArrival(xSt), Tal + 0.5 * Tst, 1e-13);
  TEST_FLOATING_EQUALITY(bar.firstArrival(0.0), Tal + Tst, 1e-13);
  // Aluminium before the interface is reached (0.5 Tal < t < 1.5 Tal): the applied F0/A.
  TEST_EQUALITY_CONST(bar.stress(xSt, Tal), 0.0);
  TEST_FLOATING_EQUALITY(bar.stress(xAl, Tal), kS, 1e-13);
  TEST_FLOATING_EQUALITY(bar.velocity(xAl, Tal), kS / Zal, 1e-13);
  // Steel after the transmitted front, before its fixed-end reflection returns
  // (Tal + 0.5 Tst < t < Tal + 1.5 Tst): T F0/A, moving at T F0/(A Z_steel).
  TEST_FLOATING_EQUALITY(bar.stress(xSt, Tal + Tst), T * kS, 1e-13);
  TEST_FLOATING_EQUALITY(bar.velocity(xSt, Tal + Tst), T * kS / Zst, 1e-13);
  // Aluminium after the reflected front, before it returns from x = L (1.5 Tal < t < 2.5 Tal):
  // (1 + R) F0/A, and the reflected tensile front moving right slows the material to (1 - R).
  TEST_FLOATING_EQUALITY(bar.stress(xAl, 2 * Tal), (1 + R) * kS, 1e-13);
  TEST_FLOATING_EQUALITY(bar.velocity(xAl, 2 * Tal), (1 - R) * kS / Zal, 1e-13);
  // Exactly on a front (t = its arrival time, bit for bit) it counts half, like BarStepExact's
  // H(0) = 1/2: in aluminium F0/(2A); on the interface as the front crosses, the left side sees
  // half the incident plus half the reflected front, (1 + R)/2 = T/2, the same as the right side.
  TEST_FLOATING_EQUALITY(bar.stress(xAl, bar.firstArrival(xAl)), 0.5 * kS, 1e-13);
  TEST_FLOATING_EQUALITY(bar.stress(0.015, bar.firstArrival(0.015)), 0.5 * T * kS, 1e-13);
  TEST_FLOATING_EQUALITY(bar.stress(xSt, bar.firstArrival(xSt)), 0.5 * T * kS, 1e-13);
  // Stress and velocity are continuous across the interface once the front has passed.
  TEST_FLOATING_EQUALITY(bar.stress(0.015, 2 * Tal), bar.stress(0.015 + 1e-9, 2 * Tal), 1e-13);
  TEST_FLOATING_EQUALITY(bar.velocity(0.015, 2 * Tal), bar.velocity(0.015 + 1e-9, 2 * Tal), 1e-13);
}

TEUCHOS_UNIT_TEST(LayeredBar, StressAndVelocityMatchFiniteDifferences) {
  // Between fronts u is exactly linear in x and t, so central differences are exact up to
  // rounding: eps * (sum of |dV| t terms) / h relative to the strain, ~1e-12 with h = L/2000 and
  // ~100s of pieces (measured 4e-12); 1e-9 leaves margin while a wrong dV sign or Z gives O(1).
  // Points whose stencil straddles a front (stress or velocity not identical at the 5 points) or
  // an interface are skipped; at least half the points must remain.
  for (const std::vector<Segment>& segs : {twoLayers(), threeLayers()}) {
    const double tau = fullTransit(segs);
    const LayeredBarExact bar(segs, kA, kF0, 3.5 * tau);
    const double h = kL / 2000, dt = 1e-3 * tau / segs.size();
    double worstS = 0, worstV = 0;
    int checked = 0, total = 0;
    for (double f : {0.37, 0.81, 1.23, 1.77, 2.41, 3.13}) {
      const double t = f * tau;
      for (int i = 0; i < 60; ++i) {
        const double x = (i + 0.5) * kL / 60;
        ++total;
        const int k = bar.segmentOf(x);
        if (bar.segmentOf(x - h) != k || bar.segmentOf(x + h) != k) continue;
        const LayeredBarExact::State c = bar.state(x, t), xm = bar.state(x - h, t), xp = bar.state(x + h, t),
                                     tm = bar.state(x, t - dt), tp = bar.state(x, t + dt);
        bool plateau = true;
        for (const LayeredBarExact::State& s : {xm, xp, tm, tp})
          plateau = plateau && s.stress == c.stress && s.velocity == c.velocity;
        if (!plateau) continue;
        ++checked;
        const double E = bar.segment(k).E, vScale = kS / bar.impedance(k);
        worstS = std::max(worstS, std::abs(E * (xp.displacement - xm.displacement) / (2 * h) - c.stress) / kS);
        worstV = std::max(worstV, std::abs((tp.displacement - tm.displacement) / (2 * dt) - c.velocity) / vScale);
      }
    }
    out << segs.size() << " segments, " << bar.frontCount() << " pieces: checked " << checked << "/" << total
        << ", max |E du/dx - stress| / (F0/A) = " << worstS << ", max |du/dt - v| / (F0/(A Z)) = " << worstV << "\n";
    TEST_COMPARE(2 * checked, >=, total);
    TEST_COMPARE(worstS, <=, 1e-9);
    TEST_COMPARE(worstV, <=, 1e-9);
  }
}

TEUCHOS_UNIT_TEST(LayeredBar, BoundaryConditions) {
  // At x = 0 every arriving piece meets its reflection (same dS, opposite dV, same arrival time),
  // at x = L every arriving piece meets its -dS reflection; the sums cancel up to rounding of a
  // few hundred terms of size <= scale (measured < 1e-15): 1e-13 of the scale. A wrong end rule
  // misses by O(1).
  for (const std::vector<Segment>& segs : {twoLayers(), threeLayers()}) {
    const double tau = fullTransit(segs), tMax = 3.5 * tau;
    const LayeredBarExact bar(segs, kA, kF0, tMax);
    const double Zmin = std::min(bar.impedance(0), bar.impedance(1));
    const double uScale = kS * kL / std::min(kEsteel, kEal), vScale = kS / Zmin;
    double worstU = 0, worstV = 0, worstS = 0, maxTip = 0;
    for (int j = 1; j <= 500; ++j) {
      const double t = tMax * j / 500;
      const LayeredBarExact::State left = bar.state(0.0, t), right = bar.state(kL, t);
      worstU = std::max(worstU, std::abs(left.displacement) / uScale);
      worstV = std::max(worstV, std::abs(left.velocity) / vScale);
      worstS = std::max(worstS, std::abs(right.stress - kS) / kS);
      maxTip = std::max(maxTip, std::abs(right.displacement) / uScale);
    }
    out << segs.size() << " segments: max |u(0)| " << worstU << ", |v(0)| " << worstV << ", |stress(L) - F0/A| "
        << worstS << " (scaled); max |u(L)| / scale " << maxTip << "\n";
    TEST_COMPARE(worstU, <=, 1e-13);
    TEST_COMPARE(worstV, <=, 1e-13);
    TEST_COMPARE(worstS, <=, 1e-13);
    TEST_COMPARE(maxTip, >, 0.5);  // the rod does move
    // The fixed end carries stress (it doubles there on the first reflection, times T's).
    TEST_COMPARE(std::abs(bar.stress(0.0, 1.2 * tau)), >, kS);
    TEST_EQUALITY_CONST(bar.displacement(kL, 0.0), 0.0);
  }
}

TEUCHOS_UNIT_TEST(LayeredBar, EnergyBalance) {
  // Work F0 u(L, t) equals strain plus kinetic energy A * sum_k int (s^2/(2 E_k) + rho_k v^2/2).
  // Midpoint rule with M cells per segment: exact except in the cells holding a front, each off
  // by at most h times the energy-density jump, so the relative error is <~ (fronts in the rod) /
  // M, a few 1e-3 at M = 4000 (measured 2.3e-4); 5e-3 keeps margin, while a wrong T or R (energy
  // not conserved) misses by more.
  for (const std::vector<Segment>& segs : {twoLayers(), threeLayers()}) {
    const double tau = fullTransit(segs);
    const LayeredBarExact bar(segs, kA, kF0, 3 * tau);
    const int M = 4000;
    double worst = 0;
    for (double f : {0.3, 0.9, 1.6, 2.2, 2.9}) {
      const double t = f * tau;
      double energy = 0;
      for (int k = 0; k < bar.segmentCount(); ++k) {
        const Segment& s = bar.segment(k);
        const double h = (s.xEnd - s.xBegin) / M;
        for (int i = 0; i < M; ++i) {
          const LayeredBarExact::State st = bar.state(s.xBegin + (i + 0.5) * h, t);
          energy += kA * h * (st.stress * st.stress / (2 * s.E) + s.rho * st.velocity * st.velocity / 2);
        }
      }
      const double work = kF0 * bar.displacement(kL, t);
      worst = std::max(worst, std::abs(energy - work) / work);
    }
    out << segs.size() << " segments: max |energy - work| / work = " << worst << "\n";
    TEST_COMPARE(worst, <=, 5e-3);
  }
}

TEUCHOS_UNIT_TEST(LayeredBar, RejectsBadInput) {
  // Exceptions, no tolerance involved.
  TEST_THROW(LayeredBarExact({}, kA, kF0, 1e-5), std::invalid_argument);
  TEST_THROW(LayeredBarExact({steel(0.001, kL)}, kA, kF0, 1e-5), std::invalid_argument);                   // not at 0
  TEST_THROW(LayeredBarExact({steel(0, 0.01), steel(0.012, kL)}, kA, kF0, 1e-5), std::invalid_argument);   // gap
  TEST_THROW(LayeredBarExact({steel(0, 0.01), steel(0.01, 0.01)}, kA, kF0, 1e-5), std::invalid_argument);  // empty
  TEST_THROW(LayeredBarExact({Segment{0, kL, -1.0, 7800}}, kA, kF0, 1e-5), std::invalid_argument);
  TEST_THROW(LayeredBarExact({Segment{0, kL, 200e9, 0.0}}, kA, kF0, 1e-5), std::invalid_argument);
  TEST_THROW(LayeredBarExact({steel(0, kL)}, 0.0, kF0, 1e-5), std::invalid_argument);
  TEST_THROW(LayeredBarExact({steel(0, kL)}, kA, kF0, 0.0), std::invalid_argument);
  TEST_THROW(LayeredBarExact({steel(0, kL)}, kA, kF0, std::nan("")), std::invalid_argument);
  // Too many pieces for the cap: two layers over ~170 transits would need far more than 1000.
  TEST_THROW(LayeredBarExact(twoLayers(), kA, kF0, 1e-3, 1000), std::runtime_error);
  const LayeredBarExact bar(twoLayers(), kA, kF0, 1e-5);
  TEST_THROW(bar.stress(-1e-9, 1e-6), std::out_of_range);
  TEST_THROW(bar.stress(kL * 1.01, 1e-6), std::out_of_range);
  TEST_THROW(bar.stress(0.01, 2e-5), std::out_of_range);  // beyond tMax
  TEST_EQUALITY_CONST(bar.stress(0.01, -1e-6), 0.0);      // before the load
  TEST_EQUALITY(bar.segmentOf(0.0), 0);
  TEST_EQUALITY(bar.segmentOf(0.015), 0);  // an interface belongs to the left segment
  TEST_EQUALITY(bar.segmentOf(0.0150001), 1);
  TEST_EQUALITY(bar.segmentOf(kL), 1);
}
