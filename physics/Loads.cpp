#include "physics/Loads.hpp"

#include <cmath>

#include "physics/Constraints.hpp"

namespace impm {

double TimeFunction::operator()(double t) const {
  switch (kind) {
    case Kind::Step: return t >= startTime ? 1.0 : 0.0;
    case Kind::Sine: return std::sin(omega * t);
    case Kind::Constant: return 1.0;
  }
  return 0.0;
}

namespace {
// int over [lo, hi] of the 1D tent of node c (spacing h, at position xc), divided by (hi - lo):
// the share of a uniform traction on [lo, hi] that the node receives.
double tentShare(double xc, double h, double lo, double hi) {
  auto integral = [&](double s) {  // int_{-inf}^{s} N(x) dx, N(x) = max(0, 1 - |x - xc| / h)
    const double r = (s - xc) / h;
    if (r <= -1) return 0.0;
    if (r <= 0) return 0.5 * h * (1 + r) * (1 + r);
    if (r <= 1) return h * (1.0 - 0.5 * (1 - r) * (1 - r));
    return h;
  };
  return (integral(hi) - integral(lo)) / (hi - lo);
}
}  // namespace

LoadSet::LoadSet(const std::vector<LoadSpec>& specs, const GridDistribution& dist, const std::vector<long long>& particleIds,
                 int bodyCount)
    : specs_(specs), bodyCount_(bodyCount) {
  const StructuredGrid& g = dist.grid();
  const LocalNodeIndexer& owned = dist.ownedIndexer();
  std::vector<int> nodes, loads;
  std::vector<double> weights;
  for (size_t l = 0; l < specs.size(); ++l) {
    const LoadSpec& s = specs[l];
    if (s.type == "Face Traction") {
      const RectangularBody& body = s.body;
      const bool vertical = (s.face == "x-" || s.face == "x+");
      for (auto [i, j] : faceNodes(g, body, s.face)) {
        const double w = vertical ? tentShare(g.nodeY(j), g.hy, body.yMin, body.yMax)
                                  : tentShare(g.nodeX(i), g.hx, body.xMin, body.xMax);
        if (owned.contains(i, j) && w > 0) { nodes.push_back(owned(i, j)); loads.push_back((int)l); weights.push_back(w); }
      }
    } else if (s.type == "Node Force") {
      const int i = (int)std::lround((s.x - g.x0) / g.hx), j = (int)std::lround((s.y - g.y0) / g.hy);
      if (owned.contains(i, j)) { nodes.push_back(owned(i, j)); loads.push_back((int)l); weights.push_back(1.0); }
    } else if (s.type == "Particle Force") {
      if (l < particleIds.size() && particleIds[l] >= 0) particleLoadIds_.emplace_back(particleIds[l], (int)l);
    } else if (s.type == "Body Force") {
      bodyForceLoads_.push_back((int)l);
      hasBodyForces_ = true;
    }
  }
  node_ = Kokkos::View<int*, DeviceType>("load_nodes", nodes.size());
  load_ = Kokkos::View<int*, DeviceType>("load_ids", loads.size());
  weight_ = Kokkos::View<double*, DeviceType>("load_weights", weights.size());
  auto hn = Kokkos::create_mirror_view(node_); auto hl = Kokkos::create_mirror_view(load_);
  auto hw = Kokkos::create_mirror_view(weight_);
  for (size_t k = 0; k < nodes.size(); ++k) { hn(k) = nodes[k]; hl(k) = loads[k]; hw(k) = weights[k]; }
  Kokkos::deep_copy(node_, hn); Kokkos::deep_copy(load_, hl); Kokkos::deep_copy(weight_, hw);
  nodalForce_ = decltype(nodalForce_)("load_force", specs.size());
  bodyAcceleration_ = decltype(bodyAcceleration_)("body_acceleration", bodyCount);
}

void LoadSet::locateParticles(const ParticleSet& ps) {
  std::vector<int> parts;
  particleLoad_.clear();
  if (!particleLoadIds_.empty()) {
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id);
    for (int p = 0; p < ps.count; ++p)
      for (const auto& [gid, load] : particleLoadIds_)
        if (id(p) == gid) { parts.push_back(p); particleLoad_.push_back(load); }
  }
  particle_ = Kokkos::View<int*, DeviceType>("load_particles", parts.size());
  auto hp = Kokkos::create_mirror_view(particle_);
  for (size_t k = 0; k < parts.size(); ++k) hp(k) = parts[k];
  Kokkos::deep_copy(particle_, hp);
  particleForce_ = decltype(particleForce_)("particle_force", parts.size());
}

Kokkos::View<double* [2], Kokkos::LayoutRight, DeviceType> LoadSet::bodyAccelerations(double t) const {
  auto h = Kokkos::create_mirror_view(bodyAcceleration_);
  Kokkos::deep_copy(h, 0.0);
  for (int l : bodyForceLoads_) {
    const LoadSpec& s = specs_[l];
    const double f = s.time(t);
    for (int b = 0; b < bodyCount_; ++b)
      if (s.bodyIndex < 0 || s.bodyIndex == b) {
        h(b, 0) += s.accelerationX * f;
        h(b, 1) += s.accelerationY * f;
      }
  }
  Kokkos::deep_copy(bodyAcceleration_, h);
  return bodyAcceleration_;
}

void LoadSet::updateMagnitudes(double t) const {
  auto h = Kokkos::create_mirror_view(nodalForce_);
  for (size_t l = 0; l < specs_.size(); ++l) {
    const double f = specs_[l].time(t);
    h(l, 0) = specs_[l].forceX * f;
    h(l, 1) = specs_[l].forceY * f;
  }
  Kokkos::deep_copy(nodalForce_, h);
}

Kokkos::View<double* [2], Kokkos::LayoutRight, DeviceType> LoadSet::particleForces(double t) const {
  auto h = Kokkos::create_mirror_view(particleForce_);
  for (size_t k = 0; k < particleLoad_.size(); ++k) {
    const LoadSpec& s = specs_[particleLoad_[k]];
    const double f = s.time(t);
    h(k, 0) = s.forceX * f;
    h(k, 1) = s.forceY * f;
  }
  Kokkos::deep_copy(particleForce_, h);
  return particleForce_;
}

}  // namespace impm
