#include "physics/Loads.hpp"

#include <algorithm>
#include <cmath>

#include "physics/Constraints.hpp"

namespace impm {

namespace {
// The share of a uniform traction on [lo, hi] that node `node` (at xc) receives: the integral of
// its 1D shape function over [lo, hi] divided by (hi - lo), the consistent nodal force. Tents for
// MPM, GIMP and FE Q4; the quadratic Lagrange functions for FE Q9, whose element edge gives
// 1/6, 2/3, 1/6 (tent shares there would load the mid-side node like a corner node and break
// the patch test). Both are polynomials of degree <= 2 between grid lines, so 3-point Gauss-
// Legendre on each grid interval of [lo, hi] is exact.
double faceShare(bool quadratic, int node, double xc, double h, double lo, double hi) {
  auto shape = [&](double x) {
    return quadratic ? QuadraticLagrange::value(x - xc, h, 0.0, node) : LinearMpm::value(x - xc, h, 0.0);
  };
  const double gaussPoint[3] = {-0.7745966692414834, 0.0, 0.7745966692414834};
  const double gaussWeight[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  const double reach = quadratic ? 2.0 * h : h;
  const double a = std::max(lo, xc - reach), b = std::min(hi, xc + reach);
  double integral = 0.0;
  for (double s = a; s < b;) {
    const double e = std::min(b, xc + (std::floor((s - xc) / h + 1e-12) + 1.0) * h);  // next grid line
    for (int q = 0; q < 3; ++q)
      integral += 0.5 * (e - s) * gaussWeight[q] * shape(0.5 * (s + e) + 0.5 * (e - s) * gaussPoint[q]);
    s = e;
  }
  return integral / (hi - lo);
}
}  // namespace

LoadSet::LoadSet(const std::vector<LoadSpec>& specs, const GridDistribution& dist,
                 const std::vector<long long>& particleIds, int bodyCount, bool quadraticElements)
    : specs_(specs), bodyCount_(bodyCount), dim_(dist.grid().dim) {
  const StructuredGrid& g = dist.grid();
  const LocalNodeIndexer& owned = dist.ownedIndexer();
  std::vector<int> nodes, loads;
  std::vector<double> weights;
  for (size_t l = 0; l < specs.size(); ++l) {
    const LoadSpec& s = specs[l];
    if (s.type == "Face Traction") {
      const RectangularBody& body = s.body;
      const int normal = s.face[0] - 'x';
      for (auto [i, j, k] : faceNodes(g, body, s.face)) {
        // The product of the 1D shares along the face's directions.
        const int index[3] = {i, j, k};
        double w = 1.0;
        for (int d = 0; d < g.dim; ++d)
          if (d != normal)
            w *= faceShare(quadraticElements, index[d], g.origin(d) + index[d] * g.spacing(d), g.spacing(d), body.lo(d),
                           body.hi(d));
        if (owned.contains(i, j, k) && w > 0) {
          nodes.push_back(owned(i, j, k));
          loads.push_back((int)l);
          weights.push_back(w);
        }
      }
    } else if (s.type == "Node Force") {
      const int i = (int)std::lround((s.x - g.x0) / g.hx), j = (int)std::lround((s.y - g.y0) / g.hy);
      const int k = g.dim == 3 ? (int)std::lround((s.z - g.z0) / g.hz) : 0;
      if (owned.contains(i, j, k)) {
        nodes.push_back(owned(i, j, k));
        loads.push_back((int)l);
        weights.push_back(1.0);
      }
    } else if (s.type == "Particle Force") {
      if (l < particleIds.size() && particleIds[l] >= 0) particleLoadIds_.emplace_back(particleIds[l], (int)l);
    } else if (s.type == "Body Force") {
      bodyForceLoads_.push_back((int)l);
      hasBodyForces_ = true;
    } else if (s.type == "Manufactured Body Force") {
      manufacturedLoads_.push_back((int)l);
    }
  }
  node_ = Kokkos::View<int*, DeviceType>("load_nodes", nodes.size());
  load_ = Kokkos::View<int*, DeviceType>("load_ids", loads.size());
  weight_ = Kokkos::View<double*, DeviceType>("load_weights", weights.size());
  auto hn = Kokkos::create_mirror_view(node_);
  auto hl = Kokkos::create_mirror_view(load_);
  auto hw = Kokkos::create_mirror_view(weight_);
  for (size_t k = 0; k < nodes.size(); ++k) {
    hn(k) = nodes[k];
    hl(k) = loads[k];
    hw(k) = weights[k];
  }
  Kokkos::deep_copy(node_, hn);
  Kokkos::deep_copy(load_, hl);
  Kokkos::deep_copy(weight_, hw);
  nodalForce_ = decltype(nodalForce_)("load_force", specs.size(), dim_);
  bodyAcceleration_ = decltype(bodyAcceleration_)("body_acceleration", bodyCount, dim_);
}

void LoadSet::locateParticles(const ParticleSet& ps) {
  std::vector<int> parts;
  particleLoad_.clear();
  if (!particleLoadIds_.empty()) {
    auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.id);
    for (int p = 0; p < ps.count; ++p)
      for (const auto& [gid, load] : particleLoadIds_)
        if (id(p) == gid) {
          parts.push_back(p);
          particleLoad_.push_back(load);
        }
  }
  particle_ = Kokkos::View<int*, DeviceType>("load_particles", parts.size());
  auto hp = Kokkos::create_mirror_view(particle_);
  for (size_t k = 0; k < parts.size(); ++k) hp(k) = parts[k];
  Kokkos::deep_copy(particle_, hp);
  particleForce_ = decltype(particleForce_)("particle_force", parts.size(), dim_);
}

Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> LoadSet::bodyAccelerations(double t) const {
  auto h = Kokkos::create_mirror_view(bodyAcceleration_);
  Kokkos::deep_copy(h, 0.0);
  for (int l : bodyForceLoads_) {
    const LoadSpec& s = specs_[l];
    const double f = s.time(t);
    for (int b = 0; b < bodyCount_; ++b)
      if (s.bodyIndex < 0 || s.bodyIndex == b) {
        for (int d = 0; d < dim_; ++d) h(b, d) += s.acceleration(d) * f;
      }
  }
  Kokkos::deep_copy(bodyAcceleration_, h);
  return bodyAcceleration_;
}

void LoadSet::updateMagnitudes(double t) const {
  auto h = Kokkos::create_mirror_view(nodalForce_);
  for (size_t l = 0; l < specs_.size(); ++l) {
    const double f = specs_[l].time(t);
    for (int d = 0; d < dim_; ++d) h(l, d) = specs_[l].force(d) * f;
  }
  Kokkos::deep_copy(nodalForce_, h);
}

Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> LoadSet::particleForces(double t) const {
  auto h = Kokkos::create_mirror_view(particleForce_);
  for (size_t k = 0; k < particleLoad_.size(); ++k) {
    const LoadSpec& s = specs_[particleLoad_[k]];
    const double f = s.time(t);
    for (int d = 0; d < dim_; ++d) h(k, d) = s.force(d) * f;
  }
  Kokkos::deep_copy(particleForce_, h);
  return particleForce_;
}

}  // namespace impm
