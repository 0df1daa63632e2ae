#include "physics/LayeredBarExact.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <stdexcept>
#include <string>
#include <utility>

namespace impm {

namespace {
bool positiveFinite(double v) { return std::isfinite(v) && v > 0; }
}  // namespace

double LayeredBarExact::transmissionCoefficient(double Za, double Zb) { return 2 * Zb / (Za + Zb); }
double LayeredBarExact::reflectionCoefficient(double Za, double Zb) { return (Zb - Za) / (Za + Zb); }

LayeredBarExact::LayeredBarExact(std::vector<Segment> segments, double area, double F0, double tMax,
                                 std::size_t maxFronts)
    : segments_(std::move(segments)), A_(area), F0_(F0), tMax_(tMax) {
  const std::string where = "LayeredBarExact: ";
  if (segments_.empty()) throw std::invalid_argument(where + "no segments");
  if (!positiveFinite(area)) throw std::invalid_argument(where + "area must be positive");
  if (!std::isfinite(F0)) throw std::invalid_argument(where + "F0 must be finite");
  if (!positiveFinite(tMax)) throw std::invalid_argument(where + "tMax must be positive");
  if (segments_.front().xBegin != 0.0) throw std::invalid_argument(where + "first segment must start at x = 0");
  const std::size_t n = segments_.size();
  const double L = segments_.back().xEnd;
  xb_.push_back(0.0);
  for (std::size_t k = 0; k < n; ++k) {
    Segment& s = segments_[k];
    const std::string seg = "segment " + std::to_string(k) + ": ";
    if (!std::isfinite(s.xBegin) || !std::isfinite(s.xEnd) || !(s.xEnd > s.xBegin))
      throw std::invalid_argument(where + seg + "needs xEnd > xBegin");
    if (!positiveFinite(s.E) || !positiveFinite(s.rho))
      throw std::invalid_argument(where + seg + "E and rho must be positive");
    if (k > 0) {
      if (!(std::abs(s.xBegin - xb_.back()) <= 1e-12 * L))
        throw std::invalid_argument(where + seg + "xBegin must equal the previous segment's xEnd");
      s.xBegin = xb_.back();  // snap, so the segments tile [0, L] exactly
      if (!(s.xEnd > s.xBegin)) throw std::invalid_argument(where + seg + "needs xEnd > xBegin");
    }
    xb_.push_back(s.xEnd);
    c_.push_back(std::sqrt(s.E / s.rho));
    Z_.push_back(s.rho * c_.back());
  }

  // Breadth-first front tracing. A pending front is (segment, direction, start time, dS); it
  // starts at the segment end it enters from (x_{k+1} moving left, x_k moving right) and reaches
  // the other end at tEnd, where its children start. Children are spawned only if tEnd <= tMax,
  // so every piece that can reach a point by t <= tMax is present, and a piece arriving exactly
  // at tMax comes with its reflection (both count half there).
  fronts_.assign(n, {});
  const double S = F0 / area, tiny = 1e-14 * std::abs(S);
  struct Pending {
    int k, dir;
    double tStart, dS;
  };
  std::deque<Pending> queue{{int(n) - 1, -1, 0.0, S}};
  const int last = int(n) - 1;
  while (!queue.empty()) {
    const Pending p = queue.front();
    queue.pop_front();
    if (p.dS == 0.0 || std::abs(p.dS) < tiny) continue;
    if (++count_ > maxFronts)
      throw std::runtime_error(where + "more than " + std::to_string(maxFronts) + " front pieces needed up to tMax = " +
                               std::to_string(tMax) + " s; lower tMax or raise maxFronts");
    const int k = p.k;
    fronts_[k].push_back({p.tStart, p.dS, -p.dir * p.dS / Z_[k], p.dir});
    // Same expression as arrival() at the far end, so a child's start time equals the parent's
    // arrival time there bit for bit (at the ends a piece and its reflection then cancel up to the
    // rounding of the running sum).
    const double tEnd = p.tStart + (xb_[k + 1] - xb_[k]) / c_[k];
    if (tEnd > tMax) continue;
    if (p.dir < 0) {
      if (k == 0) {
        queue.push_back({0, +1, tEnd, p.dS});  // fixed end: same sign
      } else {
        queue.push_back({k - 1, -1, tEnd, p.dS * transmissionCoefficient(Z_[k], Z_[k - 1])});
        queue.push_back({k, +1, tEnd, p.dS * reflectionCoefficient(Z_[k], Z_[k - 1])});
      }
    } else {
      if (k == last) {
        queue.push_back({k, -1, tEnd, -p.dS});  // prescribed traction: opposite sign
      } else {
        queue.push_back({k + 1, +1, tEnd, p.dS * transmissionCoefficient(Z_[k], Z_[k + 1])});
        queue.push_back({k, -1, tEnd, p.dS * reflectionCoefficient(Z_[k], Z_[k + 1])});
      }
    }
  }
  for (auto& list : fronts_)
    std::stable_sort(list.begin(), list.end(), [](const Front& a, const Front& b) { return a.tStart < b.tStart; });
}

const LayeredBarExact::Segment& LayeredBarExact::segment(int k) const { return segments_.at(k); }
double LayeredBarExact::waveSpeed(int k) const { return c_.at(k); }
double LayeredBarExact::impedance(int k) const { return Z_.at(k); }
double LayeredBarExact::transitTime(int k) const { return (xb_.at(k + 1) - xb_.at(k)) / c_.at(k); }

int LayeredBarExact::segmentOf(double x) const {
  if (!(x >= 0 && x <= length())) throw std::out_of_range("LayeredBarExact: x outside [0, L]");
  // First boundary x_j >= x among x_1..x_N; the owning segment is j - 1 (x = 0 gives segment 0).
  const auto it = std::lower_bound(xb_.begin() + 1, xb_.end(), x);
  return int(it - xb_.begin()) - 1;
}

// Accumulated from the right, in the order the tracing accumulates start times, so it equals the
// first piece's arrival time bit for bit.
double LayeredBarExact::firstArrival(double x) const {
  const int k = segmentOf(x);
  double t = 0;
  for (int j = segmentCount() - 1; j > k; --j) t += (xb_[j + 1] - xb_[j]) / c_[j];
  return t + (xb_[k + 1] - x) / c_[k];
}

double LayeredBarExact::arrival(const Front& f, int k, double x) const {
  return f.tStart + (f.dir > 0 ? x - xb_[k] : xb_[k + 1] - x) / c_[k];
}

void LayeredBarExact::checkPoint(double x, double t) const {
  if (!(x >= 0 && x <= length())) throw std::out_of_range("LayeredBarExact: x outside [0, L]");
  if (!(t <= tMax_)) throw std::out_of_range("LayeredBarExact: t beyond tMax (or NaN)");
}

LayeredBarExact::State LayeredBarExact::state(double x, double t) const {
  checkPoint(x, t);
  State s{0, 0, 0};
  if (t <= 0) return s;
  const int k = segmentOf(x);
  for (const Front& f : fronts_[k]) {
    if (f.tStart > t) break;  // sorted: no later piece has reached x either
    const double tp = arrival(f, k, x);
    if (tp > t) continue;
    const double w = tp == t ? 0.5 : 1.0;
    s.stress += w * f.dS;
    s.velocity += w * f.dV;
    s.displacement += f.dV * (t - tp);
  }
  return s;
}

double LayeredBarExact::displacement(double x, double t) const { return state(x, t).displacement; }
double LayeredBarExact::velocity(double x, double t) const { return state(x, t).velocity; }
double LayeredBarExact::stress(double x, double t) const { return state(x, t).stress; }

}  // namespace impm
