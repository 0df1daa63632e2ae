#include "physics/BeamTheories.hpp"

#include <cmath>
#include <stdexcept>

namespace impm {

namespace {
const double kPi = std::acos(-1.0);

// Adds c * (modal history) to hist, for a mode of frequency W driven by g sin(w t): exact or
// Newmark in time.
void addModalHistory(std::vector<double>& hist, double c, double W, double g, double w, double dt, bool newmark) {
  const int steps = int(hist.size()) - 1;
  if (newmark) {
    const std::vector<double> q = newmarkModalHistory(W, g, w, dt, steps);
    for (int k = 0; k <= steps; ++k) hist[k] += c * q[k];
  } else {
    for (int k = 0; k <= steps; ++k) hist[k] += c * harmonicModalResponse(W, g, w, k * dt);
  }
}

void checkHistoryArgs(double dt, int steps) {
  if (!(dt > 0) || steps < 0) throw std::invalid_argument("beam history needs dt > 0 and steps >= 0");
}
}  // namespace

// ---------------------------------------------------------------- one modal coordinate

double harmonicModalResponse(double W, double g, double w, double t) {
  if (t <= 0) return 0.0;
  return g / (W * W - w * w) * (std::sin(w * t) - w / W * std::sin(W * t));
}

// Average acceleration (trapezoidal rule): u+ = u + dt v + dt^2/4 (a + a+), v+ = v + dt/2 (a + a+),
// a+ = g(t+) - W^2 u+, solved for u+.
std::vector<double> newmarkModalHistory(double W, double g, double w, double dt, int steps, double q0, double v0) {
  std::vector<double> q(steps + 1);
  double u = q0, v = v0, acc = -W * W * q0;  // g sin(0) = 0
  q[0] = u;
  const double h2 = 0.25 * dt * dt, denom = 1 + W * W * h2;
  for (int k = 1; k <= steps; ++k) {
    const double gNew = g * std::sin(w * k * dt);
    const double uNew = (u + dt * v + h2 * (acc + gNew)) / denom;
    const double aNew = gNew - W * W * uNew;
    v += 0.5 * dt * (acc + aNew);
    u = uNew;
    acc = aNew;
    q[k] = u;
  }
  return q;
}

double newmarkFrequency(double W, double dt) { return 2.0 / dt * std::atan(0.5 * W * dt); }

// ---------------------------------------------------------------- Euler-Bernoulli histories

// Mode n: sin(k x) eta_n, eta_n'' + (n^2 omega_1)^2 eta_n = (2/L) sin(k a) F0 / (rho A) sin(omega t);
// its exact response is BeamHarmonicExact's term (same series, rearranged).
static std::vector<double> ebHistory(const BeamHarmonicExact& b, double x, double dt, int steps, int terms,
                                     bool newmark) {
  checkHistoryArgs(dt, steps);
  std::vector<double> hist(steps + 1, 0.0);
  const double w1 = b.omega1();
  for (int n = 1; n <= terms; ++n) {
    const double k = n * kPi / b.L, shape = std::sin(k * x);
    const double g = 2.0 / b.L * std::sin(k * b.a) * b.F0 / b.rhoA;
    if (shape == 0.0 || g == 0.0) continue;
    addModalHistory(hist, shape, double(n) * n * w1, g, b.omega, dt, newmark);
  }
  return hist;
}

std::vector<double> deflectionHistory(const BeamHarmonicExact& b, double x, double dt, int steps, int terms) {
  return ebHistory(b, x, dt, steps, terms, false);
}
std::vector<double> deflectionHistoryNewmark(const BeamHarmonicExact& b, double x, double dt, int steps, int terms) {
  return ebHistory(b, x, dt, steps, terms, true);
}

// ---------------------------------------------------------------- Timoshenko beam

// det(K - lambda M) = m1 m2 lambda^2 - (K11 m2 + K22 m1) lambda + (K11 K22 - K12^2) = 0, with
// discriminant (K11 m2 - K22 m1)^2 + 4 K12^2 m1 m2 >= 0 (written so, it has no cancellation) and
// K11 K22 - K12^2 = kappa G A E I k^4. The larger root from the '+' formula, the smaller from the
// product of the roots (no cancellation for a slender beam either). Eigenvector from the first
// row: phi ~ (K12, lambda m1 - K11), whose entries never both vanish.
TimoshenkoBeamHarmonic::Mode TimoshenkoBeamHarmonic::mode(int n, int branch) const {
  if (n < 1 || (branch != 0 && branch != 1)) throw std::invalid_argument("Timoshenko mode needs n >= 1, branch 0 or 1");
  const double k = n * kPi / L, kGA = kappa * G * A;
  const double m1 = rho * A, m2 = rho * I;
  const double K11 = kGA * k * k, K12 = -kGA * k, K22 = E * I * k * k + kGA;
  const double b = K11 * m2 + K22 * m1, a2 = m1 * m2, c = kGA * E * I * k * k * k * k;
  const double disc = (K11 * m2 - K22 * m1) * (K11 * m2 - K22 * m1) + 4 * K12 * K12 * m1 * m2;
  const double lamHi = (b + std::sqrt(disc)) / (2 * a2);
  const double lam = branch == 1 ? lamHi : c / (a2 * lamHi);
  const double p1 = K12, p2 = lam * m1 - K11;
  return Mode{std::sqrt(lam), p1 * p1 / (m1 * p1 * p1 + m2 * p2 * p2)};
}

double TimoshenkoBeamHarmonic::deflection(double x, double t, int terms) const {
  if (t <= 0) return 0.0;
  double sum = 0;
  for (int n = 1; n <= terms; ++n) {
    const double k = n * kPi / L, f = 2.0 / L * std::sin(k * a) * F0;
    for (int br = 0; br < 2; ++br) {
      const Mode m = mode(n, br);
      // phi_w eta with eta'' + W^2 eta = phi_w f sin(omega t): weight phi_w^2 times the unit response.
      sum += std::sin(k * x) * m.weight * harmonicModalResponse(m.omega, f, forceOmega, t);
    }
  }
  return sum;
}

static std::vector<double> timoHistory(const TimoshenkoBeamHarmonic& b, double x, double dt, int steps, int terms,
                                       bool newmark) {
  checkHistoryArgs(dt, steps);
  std::vector<double> hist(steps + 1, 0.0);
  for (int n = 1; n <= terms; ++n) {
    const double k = n * kPi / b.L, shape = std::sin(k * x), f = 2.0 / b.L * std::sin(k * b.a) * b.F0;
    if (shape == 0.0 || f == 0.0) continue;
    for (int br = 0; br < 2; ++br) {
      const TimoshenkoBeamHarmonic::Mode m = b.mode(n, br);
      addModalHistory(hist, shape * m.weight, m.omega, f, b.forceOmega, dt, newmark);
    }
  }
  return hist;
}

std::vector<double> TimoshenkoBeamHarmonic::deflectionHistory(double x, double dt, int steps, int terms) const {
  return timoHistory(*this, x, dt, steps, terms, false);
}
std::vector<double> TimoshenkoBeamHarmonic::deflectionHistoryNewmark(double x, double dt, int steps, int terms) const {
  return timoHistory(*this, x, dt, steps, terms, true);
}

}  // namespace impm
