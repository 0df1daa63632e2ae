// Exact solution of a layered 1D rod under a step end load, by wave-front tracing (method of
// characteristics). Plain C++17, no Trilinos or Kokkos, like ExactSolutions.hpp.
//
// The rod is N bonded segments along x: segment k spans [x_k, x_{k+1}], x_0 = 0, x_N = L, with
// its own modulus E_k and density rho_k (wave speed c_k = sqrt(E_k/rho_k), impedance per unit
// area Z_k = rho_k c_k = sqrt(E_k rho_k)); the cross-section area A is common. The left end x = 0
// is fixed (u = 0); a step force F0 H(t) (tension positive, pulling in +x) acts at x = L, so the
// stress there is F0/A for t > 0. Linear small-strain theory. E_k is the modulus the comparison
// uses (E or E/(1-nu^2), see doc/method.md, "Which modulus"); the caller decides.
//
// The solution is piecewise constant in stress and velocity between straight fronts. A front in
// segment k moving in direction d (+1 right, -1 left) carries a stress jump dS and a velocity jump
// dV = -d dS / Z_k. At t = 0 a front dS = F0/A leaves x = L moving left. When a front from
// segment a reaches the interface with segment b, a front dS T(Z_a, Z_b) continues into b and a
// front dS R(Z_a, Z_b) goes back into a (T = 2 Z_b/(Z_a+Z_b), R = (Z_b-Z_a)/(Z_a+Z_b)); at the
// fixed end x = 0 it reflects as +dS, at the loaded end x = L as -dS. Fronts with
// |dS| < 1e-14 |F0/A| are dropped, so equal-impedance interfaces (R = 0) leave no reflected front.
// Each front piece (one segment crossing) is stored; pieces are generated breadth-first up to
// tMax. Without merging of coincident fronts the count grows roughly like 2^(interface crossings),
// so this is meant for a few transits of a few layers; the constructor throws
// std::runtime_error when more than maxFronts pieces would be needed.
//
// Evaluation at (x, t), 0 <= x <= L, t <= tMax, sums over the pieces in the segment owning x
// that reached x at a time tp <= t: stress = sum dS, velocity = sum dV, displacement =
// sum dV (t - tp). A piece exactly at x (tp == t) counts half, like BarStepExact's H(0) = 1/2.
// Convention: a point on an interface x_k (0 < k < N) belongs to the segment on its left
// (k - 1); x = 0 belongs to segment 0. Both sides give the same stress and velocity (including
// the half-weighted value at the instant a front crosses), so the choice only matters for which
// modulus relates stress to strain. For t <= 0 everything is zero (the unloaded initial state,
// as in BarStepExact).
#pragma once

#include <cstddef>
#include <vector>

namespace impm {

struct LayeredBarExact {
  struct Segment {
    double xBegin, xEnd, E, rho;
  };
  struct State {
    double displacement, velocity, stress;
  };

  // segments: ordered left to right, contiguous (segments[0].xBegin == 0, each xBegin equal to
  // the previous xEnd within 1e-12 L), positive lengths, E and rho; area > 0, tMax > 0, F0 finite.
  // Throws std::invalid_argument on bad input, std::runtime_error past maxFronts pieces.
  LayeredBarExact(std::vector<Segment> segments, double area, double F0, double tMax, std::size_t maxFronts = 2000000);

  // All throw std::out_of_range for x outside [0, L] or t > tMax.
  double displacement(double x, double t) const;
  double velocity(double x, double t) const;
  double stress(double x, double t) const;
  State state(double x, double t) const;  // all three in one pass

  int segmentCount() const { return int(segments_.size()); }
  int segmentOf(double x) const;  // owning segment (interfaces belong to the left segment)
  const Segment& segment(int k) const;
  double length() const { return xb_.back(); }  // L
  double area() const { return A_; }
  double force() const { return F0_; }
  double tMax() const { return tMax_; }
  double waveSpeed(int k) const;    // sqrt(E_k / rho_k)
  double impedance(int k) const;    // rho_k c_k, per unit area
  double transitTime(int k) const;  // (x_{k+1} - x_k) / c_k
  // Time the first front (the one leaving x = L at t = 0) reaches x: (x_{k+1} - x)/c_k plus the
  // transit times of the segments right of the owning segment k. Independent of tMax.
  double firstArrival(double x) const;
  std::size_t frontCount() const { return count_; }  // stored front pieces

  static double transmissionCoefficient(double Za, double Zb);  // 2 Zb / (Za + Zb), a -> b
  static double reflectionCoefficient(double Za, double Zb);    // (Zb - Za) / (Za + Zb), back into a

 private:
  struct Front {
    double tStart, dS, dV;
    int dir;
  };
  double arrival(const Front& f, int k, double x) const;
  void checkPoint(double x, double t) const;

  std::vector<Segment> segments_;
  std::vector<double> xb_, c_, Z_;  // xb_: the N + 1 segment boundaries
  double A_, F0_, tMax_;
  std::vector<std::vector<Front>> fronts_;  // per segment, sorted by tStart
  std::size_t count_ = 0;
};

}  // namespace impm
