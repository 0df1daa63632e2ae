// Material points as Kokkos Views (structure of arrays), on the node's memory space.
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

#include "core/Types.hpp"

namespace impm {

struct ParticleSet {
  using Vec2 = Kokkos::View<double* [2], Kokkos::LayoutRight, DeviceType>;
  using Mat2 = Kokkos::View<double* [2][2], Kokkos::LayoutRight, DeviceType>;
  using Scal = Kokkos::View<double*, DeviceType>;
  using Stress = Kokkos::View<double* [4], Kokkos::LayoutRight, DeviceType>;  // xx, yy, xy, zz
  using Ids = Kokkos::View<int*, DeviceType>;
  using GlobalIds = Kokkos::View<long long*, DeviceType>;

  int count = 0;
  Vec2 x;          // current position
  Vec2 x0;         // reference position (displacement u = x - x0)
  Vec2 v;          // velocity
  Vec2 a;          // acceleration (implicit Newmark and output)
  Vec2 halfSize;   // half size of the particle domain (GIMP); uGIMP keeps it fixed
  Scal mass;
  Scal volume0;    // reference volume
  Scal volume;     // current volume, volume0 * det F
  Stress stress;   // Cauchy stress
  Mat2 F;          // deformation gradient
  Mat2 gradient;   // scratch: gradient of a grid field at the particle (velocity or displacement)
  // Displacement of particles that do not move (the FE reference's Gauss points); empty
  // otherwise, where the displacement is x - x0.
  Vec2 u;
  // Identity: the body and material (indices into the deck's Bodies and Materials) and a global
  // id that does not depend on the MPI decomposition (monitors and particle loads use it).
  Ids body;
  Ids material;
  GlobalIds id;

  bool fixedPositions() const { return u.extent(0) > 0; }

  ParticleSet() = default;
  explicit ParticleSet(int n) : count(n) {
    x = Vec2("x", n); x0 = Vec2("x0", n); v = Vec2("v", n); a = Vec2("a", n);
    halfSize = Vec2("halfSize", n);
    mass = Scal("mass", n); volume0 = Scal("volume0", n); volume = Scal("volume", n);
    stress = Stress("stress", n); F = Mat2("F", n); gradient = Mat2("gradient", n);
    body = Ids("body", n); material = Ids("material", n); id = GlobalIds("id", n);
    auto Fv = F;
    Kokkos::parallel_for("init_F", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int p) {
      Fv(p, 0, 0) = 1.0; Fv(p, 1, 1) = 1.0; Fv(p, 0, 1) = 0.0; Fv(p, 1, 0) = 0.0;
    });
  }

  // --- ready for migration between ranks: every field of a particle as one row of doubles ---
  // (ids fit a double exactly below 2^53). The scratch `gradient` is not carried; the fixed
  // particles' `u` is (FE reference), when present.
  int packedWidth() const { return 2 * 5 + 3 + 4 + 4 + 3 + (fixedPositions() ? 2 : 0); }
  using Packed = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>;

  // Rows of `buffer` (extent indices.extent(0) x packedWidth()) from the particles `indices`.
  void pack(const Ids& indices, const Packed& buffer) const {
    const ParticleSet ps = *this;
    const bool withU = fixedPositions();
    Kokkos::parallel_for(
        "particles_pack", Kokkos::RangePolicy<ExecutionSpace>(0, indices.extent(0)), KOKKOS_LAMBDA(int k) {
          const int p = indices(k);
          int c = 0;
          for (int d = 0; d < 2; ++d) {
            buffer(k, c++) = ps.x(p, d); buffer(k, c++) = ps.x0(p, d); buffer(k, c++) = ps.v(p, d);
            buffer(k, c++) = ps.a(p, d); buffer(k, c++) = ps.halfSize(p, d);
          }
          buffer(k, c++) = ps.mass(p); buffer(k, c++) = ps.volume0(p); buffer(k, c++) = ps.volume(p);
          for (int i = 0; i < 4; ++i) buffer(k, c++) = ps.stress(p, i);
          for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) buffer(k, c++) = ps.F(p, i, j);
          buffer(k, c++) = ps.body(p); buffer(k, c++) = ps.material(p); buffer(k, c++) = (double)ps.id(p);
          if (withU) { buffer(k, c++) = ps.u(p, 0); buffer(k, c++) = ps.u(p, 1); }
        });
  }

  // Appends the rows of `buffer` (packed by a set of the same kind) as new particles.
  void unpackAppend(const Packed& buffer) {
    const int first = count;
    resize(count + (int)buffer.extent(0));
    const ParticleSet ps = *this;
    const bool withU = fixedPositions();
    Kokkos::parallel_for(
        "particles_unpack", Kokkos::RangePolicy<ExecutionSpace>(0, buffer.extent(0)), KOKKOS_LAMBDA(int k) {
          const int p = first + k;
          int c = 0;
          for (int d = 0; d < 2; ++d) {
            ps.x(p, d) = buffer(k, c++); ps.x0(p, d) = buffer(k, c++); ps.v(p, d) = buffer(k, c++);
            ps.a(p, d) = buffer(k, c++); ps.halfSize(p, d) = buffer(k, c++);
          }
          ps.mass(p) = buffer(k, c++); ps.volume0(p) = buffer(k, c++); ps.volume(p) = buffer(k, c++);
          for (int i = 0; i < 4; ++i) ps.stress(p, i) = buffer(k, c++);
          for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j) ps.F(p, i, j) = buffer(k, c++);
          ps.body(p) = (int)buffer(k, c++); ps.material(p) = (int)buffer(k, c++); ps.id(p) = (long long)buffer(k, c++);
          if (withU) { ps.u(p, 0) = buffer(k, c++); ps.u(p, 1) = buffer(k, c++); }
        });
  }

  // Keeps the first min(n, count) particles and makes room for n.
  void resize(int n) {
    Kokkos::resize(x, n); Kokkos::resize(x0, n); Kokkos::resize(v, n); Kokkos::resize(a, n);
    Kokkos::resize(halfSize, n); Kokkos::resize(mass, n); Kokkos::resize(volume0, n); Kokkos::resize(volume, n);
    Kokkos::resize(stress, n); Kokkos::resize(F, n); Kokkos::resize(gradient, n);
    Kokkos::resize(body, n); Kokkos::resize(material, n); Kokkos::resize(id, n);
    if (fixedPositions()) Kokkos::resize(u, n);
    count = n;
  }

  // Bytes held per particle by the views above.
  static constexpr size_t bytesPerParticle() {
    return sizeof(double) * (2 * 5 + 3 + 4 + 4 + 4) + 2 * sizeof(int) + sizeof(long long);
  }
};

// The heaviest particle's mass over all ranks (the reference for void grid nodes).
inline double heaviestParticleMass(const ParticleSet& ps, const Teuchos::Comm<int>& comm) {
  double local = 0.0, global = 0.0;
  auto m = ps.mass;
  Kokkos::parallel_reduce(
      "heaviest_particle", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, double& mx) { mx = m(p) > mx ? m(p) : mx; }, Kokkos::Max<double>(local));
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, local, Teuchos::outArg(global));
  return global;
}

}  // namespace impm
