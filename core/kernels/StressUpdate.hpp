// The particle update from a displacement-gradient increment G (explicit: dt grad v; implicit:
// grad u of the step): the stress through the material law, the deformation gradient
// F <- (I + G) F and the volume V = V0 det F. Templated on the law (physics/Materials.hpp) and
// the dimension: the law sees its material id, the old stress, G and the new F. The FE
// reference keeps its Gauss points' volumes (small strain on the undeformed mesh):
// updateVolume = false.
#pragma once

#include "core/ParticleSet.hpp"
#include "core/SmallMatrix.hpp"
#include "core/StructuredGrid.hpp"

namespace impm {

// cpGIMP's domain update (ShapeFunctions.hpp, ConvectedGimp): on, and the cap on each half size
// (half a cell).
struct DomainConvection {
  bool on = false;
  double maxHalf[3] = {0, 0, 0};
  DomainConvection() = default;
  explicit DomainConvection(const StructuredGrid& g) : on(true) {
    for (int d = 0; d < g.dim; ++d) maxHalf[d] = 0.5 * g.spacing(d);
  }
};

// The stress of a law other than linear elasticity (s in place, h the history when it has one).
// Out of line and on copies of G, F and s: the hot linear-elastic path of updateParticleState
// then keeps its small matrices in registers (their address never escapes; when it did, the
// explicit G2P spent a fifth of its time in store-forwarding stalls).
template <int Dim, class Law>
KOKKOS_FUNCTION IMPM_NOINLINE void generalStress(const FixedParticleViews<Dim>& ps, const Law& law, int p, int m,
                                                 const double (&G)[Dim][Dim], const double (&Fn)[Dim][Dim], double* s) {
  if (law.hasHistory(m)) {
    double h[ParticleSet::kHistoryCount];
    for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h[i] = ps.history(p, i);
    law.template stress<Dim>(m, s, G, Fn, h, s);
    for (int i = 0; i < ParticleSet::kHistoryCount; ++i) ps.history(p, i) = h[i];
  } else {
    law.template stress<Dim>(m, s, G, Fn, nullptr, s);
  }
}

// G[i][j] = d(increment)_i / dx_j.
template <int Dim, class Law>
KOKKOS_FORCEINLINE_FUNCTION void updateParticleState(const FixedParticleViews<Dim>& ps, const Law& law, int p,
                                                     const double (&G)[Dim][Dim], bool updateVolume = true,
                                                     const DomainConvection& domain = {}) {
  constexpr int ns = StressLayout<Dim>::count;
  // F <- (I + G) F column by column, each column stored as soon as it is computed (column j of
  // the new F needs only column j of the old one). Copying a finished Fn array into the view
  // instead read it back as vectors after scalar stores, a store-forwarding stall on every particle.
  double before[Dim], Fn[Dim][Dim];
  for (int d = 0; d < Dim; ++d) before[d] = ps.F(p, d, d);
  for (int j = 0; j < Dim; ++j) {
    double column[Dim];
    for (int i = 0; i < Dim; ++i) {
      double f = ps.F(p, i, j);
      for (int k = 0; k < Dim; ++k) f += G[i][k] * ps.F(p, k, j);
      column[i] = f;
    }
    for (int i = 0; i < Dim; ++i) {
      Fn[i][j] = column[i];
      ps.F(p, i, j) = column[i];
    }
  }
  if (updateVolume) ps.volume(p) = ps.volume0(p) * determinant<Dim>(Fn);
  if (domain.on)
    for (int d = 0; d < Dim; ++d) {
      const double after = Fn[d][d];
      if (before[d] > 0.0 && after > 0.0) {
        const double l = ps.halfSize(p, d) * (after / before[d]);
        ps.halfSize(p, d) = l < domain.maxHalf[d] ? l : domain.maxHalf[d];
      }
    }
  const int m = ps.material(p);
  if (law.isLinearElastic(m)) {
    law.linearElastic(m).template updateStress<Dim>(ps.stress, p, G);
  } else {
    double Gc[Dim][Dim], Fc[Dim][Dim], sc[ns];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) {
        Gc[i][j] = G[i][j];
        Fc[i][j] = Fn[i][j];
      }
    for (int c = 0; c < ns; ++c) sc[c] = ps.stress(p, c);
    generalStress<Dim>(ps, law, p, m, Gc, Fc, sc);
    for (int c = 0; c < ns; ++c) ps.stress(p, c) = sc[c];
  }
}

// A correction of each particle's increment G before the update (core/kernels/FbarAveraging.hpp);
// this one leaves G as it is.
struct NoStrainCorrection {
  template <int Dim>
  KOKKOS_FORCEINLINE_FUNCTION void operator()(int, double (&)[Dim][Dim]) const {}
};

// Every particle with G = scale * ps.gradient (explicit: grad v and dt; implicit: grad u and 1),
// corrected by `correct`.
template <class ExecSpace, int Dim, class Law, class Correction = NoStrainCorrection>
void updateStress(const ParticleSet& set, const Law& law, double scale, bool updateVolume = true,
                  const DomainConvection& domain = {}, const Correction& correct = Correction()) {
  const FixedParticleViews<Dim> ps(set);
  auto L = ps.gradient;
  Kokkos::parallel_for(
      "stress_update", Kokkos::RangePolicy<ExecSpace>(0, set.count), KOKKOS_LAMBDA(int p) {
        double G[Dim][Dim];
        for (int i = 0; i < Dim; ++i)
          for (int j = 0; j < Dim; ++j) G[i][j] = scale * L(p, i, j);
        correct(p, G);
        updateParticleState<Dim>(ps, law, p, G, updateVolume, domain);
      });
}

}  // namespace impm
