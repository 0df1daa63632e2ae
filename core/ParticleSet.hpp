// Material points as Kokkos Views (structure of arrays), on the node's memory space, in 2D or
// 3D. The views carry the dimension at run time (x is count x dim); the kernels that read them
// are templated on the dimension (Dim), so their loops over components unroll.
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

#include <string>

#include "core/Types.hpp"

namespace impm {

// The stored stress components: xx, yy, xy, zz, then in 3D yz, xz. In 2D sigma_zz (index 3) is
// the out-of-plane stress of plane strain (zero in plane stress); the first three are in-plane.
// The tangent D acts on strains in the same (Voigt) order, with engineering shears: component v
// of a Voigt vector is stored component v, for v < voigt.
template <int Dim>
struct StressLayout {
  static constexpr int count = Dim == 2 ? 4 : 6;
  static constexpr int voigt = Dim == 2 ? 3 : 6;
  // Stored index of sigma_ij, i, j < Dim.
  KOKKOS_INLINE_FUNCTION static constexpr int index(int i, int j) {
    return i == j ? (i == 2 ? 3 : i) : (i + j == 1 ? 2 : (i + j == 3 ? 4 : 5));
  }
  // The (i, j) pair of Voigt component v.
  KOKKOS_INLINE_FUNCTION static constexpr int first(int v) {
    return v == 0 ? 0 : v == 1 ? 1 : v == 2 ? 0 : v == 3 ? 2 : v == 4 ? 1 : 0;
  }
  KOKKOS_INLINE_FUNCTION static constexpr int second(int v) {
    return v == 0 ? 0 : v == 1 ? 1 : v == 2 ? 1 : v == 3 ? 2 : 2;
  }
};

inline int stressComponents(int dim) { return dim == 2 ? 4 : 6; }

struct ParticleSet {
  using Vec = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>;   // count x dim
  using Mat = Kokkos::View<double***, Kokkos::LayoutRight, DeviceType>;  // count x dim x dim
  using Scal = Kokkos::View<double*, DeviceType>;
  using Stress = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>;  // count x 4 (2D) or 6 (3D)
  using Ids = Kokkos::View<int*, DeviceType>;
  using GlobalIds = Kokkos::View<long long*, DeviceType>;
  using Hist = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>;  // count x kHistoryCount

  int count = 0;
  int dim = 2;
  Vec x;         // current position
  Vec x0;        // reference position (displacement u = x - x0)
  Vec v;         // velocity
  Vec a;         // acceleration (implicit Newmark and output)
  Vec halfSize;  // half size of the particle domain (GIMP); uGIMP keeps it fixed
  Scal mass;
  Scal volume0;   // reference volume
  Scal volume;    // current volume, volume0 * det F
  Stress stress;  // Cauchy stress (StressLayout)
  Mat F;          // deformation gradient
  Mat gradient;   // scratch: gradient of a grid field at the particle (velocity or displacement)
  // Displacement of particles that do not move (the FE reference's Gauss points); empty
  // otherwise, where the displacement is x - x0.
  Vec u;
  // Per-particle history of path-dependent materials (J2: b_e and alpha, kHistoryCount
  // columns); empty unless a material needs it (allocateHistory).
  Hist history;
  bool historyAllocated = false;
  static constexpr int kHistoryCount = 7;
  // The affine part C_p of the particle velocity field, v(x) = v_p + C_p (x - x_p), of the APIC
  // and TPIC transfers (count x dim x dim); empty unless the transfer needs it (allocateAffine).
  Mat affine;
  bool affineAllocated = false;
  // Identity: the body and material (indices into the deck's Bodies and Materials) and a global
  // id that does not depend on the MPI decomposition (monitors and particle loads use it).
  Ids body;
  Ids material;
  GlobalIds id;

  bool fixedPositions() const { return u.extent(0) > 0; }
  // (A flag, not the view's extent: a rank may hold no particles and still receive some.)
  bool hasHistory() const { return historyAllocated; }
  // Allocates the history, every particle at the virgin state (b_e = I, alpha = 0).
  void allocateHistory() {
    historyAllocated = true;
    history = Hist("history", count, kHistoryCount);
    auto h = history;
    Kokkos::parallel_for(
        "init_history", Kokkos::RangePolicy<ExecutionSpace>(0, count), KOKKOS_LAMBDA(int p) {
          h(p, 0) = 1;
          h(p, 1) = 1;
          h(p, 3) = 1;  // b_e = I in the stored layout (xx, yy, xy, zz, yz, xz)
        });
  }
  bool hasAffine() const { return affineAllocated; }
  // Allocates the affine velocity matrices, zero.
  void allocateAffine() {
    affineAllocated = true;
    affine = Mat("affine", count, dim, dim);
  }
  int stressCount() const { return stressComponents(dim); }

  ParticleSet() = default;
  explicit ParticleSet(int n, int dimension = 2) : count(n), dim(dimension) {
    x = Vec("x", n, dim);
    x0 = Vec("x0", n, dim);
    v = Vec("v", n, dim);
    a = Vec("a", n, dim);
    halfSize = Vec("halfSize", n, dim);
    mass = Scal("mass", n);
    volume0 = Scal("volume0", n);
    volume = Scal("volume", n);
    stress = Stress("stress", n, stressCount());
    F = Mat("F", n, dim, dim);
    gradient = Mat("gradient", n, dim, dim);
    body = Ids("body", n);
    material = Ids("material", n);
    id = GlobalIds("id", n);
    auto Fv = F;
    const int d = dim;
    Kokkos::parallel_for(
        "init_F", Kokkos::RangePolicy<ExecutionSpace>(0, n), KOKKOS_LAMBDA(int p) {
          for (int i = 0; i < d; ++i)
            for (int j = 0; j < d; ++j) Fv(p, i, j) = i == j ? 1.0 : 0.0;
        });
  }

  // A vector view of this set's shape (fixed particles' u).
  Vec newVector(const std::string& label) const { return Vec(label, count, dim); }

  // --- ready for migration between ranks: every field of a particle as one row of doubles ---
  // (ids fit a double exactly below 2^53). The scratch `gradient` is not carried; the fixed
  // particles' `u` is (FE reference), the history and the affine matrix are, when present.
  int packedWidth() const {
    return 5 * dim + 3 + stressCount() + dim * dim + 3 + (fixedPositions() ? dim : 0) +
           (hasHistory() ? kHistoryCount : 0) + (hasAffine() ? dim * dim : 0);
  }
  using Packed = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>;
  // The column of a packed row that holds the position's component d.
  static constexpr int packedPositionColumn(int d) { return 5 * d; }

  // Rows of `buffer` (extent indices.extent(0) x packedWidth()) from the particles `indices`.
  void pack(const Ids& indices, const Packed& buffer) const {
    const ParticleSet ps = *this;
    const bool withU = fixedPositions(), withHistory = hasHistory(), withAffine = hasAffine();
    const int nd = dim, ns = stressCount();
    Kokkos::parallel_for(
        "particles_pack", Kokkos::RangePolicy<ExecutionSpace>(0, indices.extent(0)), KOKKOS_LAMBDA(int k) {
          const int p = indices(k);
          int c = 0;
          for (int d = 0; d < nd; ++d) {
            buffer(k, c++) = ps.x(p, d);
            buffer(k, c++) = ps.x0(p, d);
            buffer(k, c++) = ps.v(p, d);
            buffer(k, c++) = ps.a(p, d);
            buffer(k, c++) = ps.halfSize(p, d);
          }
          buffer(k, c++) = ps.mass(p);
          buffer(k, c++) = ps.volume0(p);
          buffer(k, c++) = ps.volume(p);
          for (int i = 0; i < ns; ++i) buffer(k, c++) = ps.stress(p, i);
          for (int i = 0; i < nd; ++i)
            for (int j = 0; j < nd; ++j) buffer(k, c++) = ps.F(p, i, j);
          buffer(k, c++) = ps.body(p);
          buffer(k, c++) = ps.material(p);
          buffer(k, c++) = (double)ps.id(p);
          if (withU)
            for (int d = 0; d < nd; ++d) buffer(k, c++) = ps.u(p, d);
          if (withHistory)
            for (int i = 0; i < kHistoryCount; ++i) buffer(k, c++) = ps.history(p, i);
          if (withAffine)
            for (int i = 0; i < nd; ++i)
              for (int j = 0; j < nd; ++j) buffer(k, c++) = ps.affine(p, i, j);
        });
  }

  // Appends the rows of `buffer` (packed by a set of the same kind) as new particles.
  void unpackAppend(const Packed& buffer) {
    const int first = count;
    resize(count + (int)buffer.extent(0));
    const ParticleSet ps = *this;
    const bool withU = fixedPositions(), withHistory = hasHistory(), withAffine = hasAffine();
    const int nd = dim, ns = stressCount();
    Kokkos::parallel_for(
        "particles_unpack", Kokkos::RangePolicy<ExecutionSpace>(0, buffer.extent(0)), KOKKOS_LAMBDA(int k) {
          const int p = first + k;
          int c = 0;
          for (int d = 0; d < nd; ++d) {
            ps.x(p, d) = buffer(k, c++);
            ps.x0(p, d) = buffer(k, c++);
            ps.v(p, d) = buffer(k, c++);
            ps.a(p, d) = buffer(k, c++);
            ps.halfSize(p, d) = buffer(k, c++);
          }
          ps.mass(p) = buffer(k, c++);
          ps.volume0(p) = buffer(k, c++);
          ps.volume(p) = buffer(k, c++);
          for (int i = 0; i < ns; ++i) ps.stress(p, i) = buffer(k, c++);
          for (int i = 0; i < nd; ++i)
            for (int j = 0; j < nd; ++j) ps.F(p, i, j) = buffer(k, c++);
          ps.body(p) = (int)buffer(k, c++);
          ps.material(p) = (int)buffer(k, c++);
          ps.id(p) = (long long)buffer(k, c++);
          if (withU)
            for (int d = 0; d < nd; ++d) ps.u(p, d) = buffer(k, c++);
          if (withHistory)
            for (int i = 0; i < kHistoryCount; ++i) ps.history(p, i) = buffer(k, c++);
          if (withAffine)
            for (int i = 0; i < nd; ++i)
              for (int j = 0; j < nd; ++j) ps.affine(p, i, j) = buffer(k, c++);
        });
  }

  // Keeps the first min(n, count) particles and makes room for n.
  void resize(int n) {
    Kokkos::resize(x, n, dim);
    Kokkos::resize(x0, n, dim);
    Kokkos::resize(v, n, dim);
    Kokkos::resize(a, n, dim);
    Kokkos::resize(halfSize, n, dim);
    Kokkos::resize(mass, n);
    Kokkos::resize(volume0, n);
    Kokkos::resize(volume, n);
    Kokkos::resize(stress, n, stressCount());
    Kokkos::resize(F, n, dim, dim);
    Kokkos::resize(gradient, n, dim, dim);
    Kokkos::resize(body, n);
    Kokkos::resize(material, n);
    Kokkos::resize(id, n);
    if (fixedPositions()) Kokkos::resize(u, n, dim);
    if (hasHistory()) Kokkos::resize(history, n, kHistoryCount);
    if (hasAffine()) Kokkos::resize(affine, n, dim, dim);
    count = n;
  }

  // Bytes held per particle by the views above (216 in 2D, 352 in 3D).
  static size_t bytesPerParticle(int dim = 2) {
    return sizeof(double) * (5 * dim + 3 + stressComponents(dim) + 2 * dim * dim) + 2 * sizeof(int) + sizeof(long long);
  }
};

// The particle data as compile-time-shaped views for kernels of dimension Dim: the same memory
// (unmanaged, no copy) with static extents, so that indexing x(p, d) needs no run-time stride
// (the run-time-shaped views cost the 2D kernels about 4% of their speed).
template <int Dim>
struct FixedParticleViews {
  using Unmanaged = Kokkos::MemoryTraits<Kokkos::Unmanaged>;
  using Vec = Kokkos::View<double* [Dim], Kokkos::LayoutRight, DeviceType, Unmanaged>;
  using Mat = Kokkos::View<double* [Dim][Dim], Kokkos::LayoutRight, DeviceType, Unmanaged>;
  using Stress = Kokkos::View<double * [StressLayout<Dim>::count], Kokkos::LayoutRight, DeviceType, Unmanaged>;
  static Vec vec(const ParticleSet::Vec& v) { return Vec(v.data(), v.extent(0)); }

  Vec x, x0, v, a, halfSize;
  Mat F, gradient, affine;
  Stress stress;
  ParticleSet::Scal mass, volume0, volume;
  ParticleSet::Ids material;
  ParticleSet::Hist history;

  explicit FixedParticleViews(const ParticleSet& ps)
      : x(vec(ps.x)),
        x0(vec(ps.x0)),
        v(vec(ps.v)),
        a(vec(ps.a)),
        halfSize(vec(ps.halfSize)),
        F(ps.F.data(), ps.F.extent(0)),
        gradient(ps.gradient.data(), ps.gradient.extent(0)),
        affine(ps.affine.data(), ps.affine.extent(0)),
        stress(ps.stress.data(), ps.stress.extent(0)),
        mass(ps.mass),
        volume0(ps.volume0),
        volume(ps.volume),
        material(ps.material),
        history(ps.history) {}
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
