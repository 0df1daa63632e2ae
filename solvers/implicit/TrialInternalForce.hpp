// The internal force of an implicit step's trial state, and the Newmark residual at a node.
#pragma once

#include "core/ParticleSet.hpp"
#include "core/kernels/InternalForce.hpp"
#include "core/kernels/StressUpdate.hpp"
#include "physics/Materials.hpp"
#include "solvers/implicit/ImplicitGridColumns.hpp"
#include "solvers/implicit/NewmarkScheme.hpp"

namespace impm {

// The internal force on the nodes (-int B^T sigma) of the trial state of the step's grid
// displacement (columns uX.. of disp), into columns fX.. of f. One pass per particle: grad u from
// the grid, the trial stress and its internal force through the shared scatterInternalForce.
// Small strain: sigma_n + D sym(grad u) on the step's initial domain. Finite strain:
// F = (I + grad u) F_n and the law's stress there; a path-dependent law works on a copy of the
// history (the trial state is discarded). `correct` may replace grad u (F-bar:
// core/kernels/FbarAveraging.hpp). With several velocity fields, each particle reads and writes
// its own field's columns (dispFields in d, forceFields in f).
template <class Exec, class Shape, int Dim, class DispView, class ForceView, class Correction = NoStrainCorrection,
          class DispFields = SingleField, class ForceFields = SingleField>
void scatterTrialInternalForce(const StructuredGrid& grid, const LocalNodeIndexer& ix, const ParticleSet& ps,
                               const Materials& materials, const DispView& d, int uX, const ForceView& f, int fX,
                               const Correction& correct = Correction(), const DispFields& dispFields = DispFields(),
                               const ForceFields& forceFields = ForceFields()) {
  auto vol = ps.volume;
  auto sig = ps.stress;
  auto matId = ps.material;
  auto Fp = FixedParticleViews<Dim>(ps).F;
  auto hist = ps.history;
  const auto law = materials.law();
  scatterToGrid<Exec, Shape, Dim>(
      "implicit_internal_force", grid, ps, f, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
        double G[Dim][Dim] = {};
        const int u0 = uX + dispFields.offset(p), f0 = fX + forceFields.offset(p);
        st.forEachNode(ix, [&](int n, double, const double* dw) {
          for (int i = 0; i < Dim; ++i)
            for (int j = 0; j < Dim; ++j) G[i][j] += d(n, u0 + i) * dw[j];
        });
        correct(p, G);
        double trial[StressLayout<Dim>::count];
        loadStress<Dim>(sig, p, trial);
        const int m = matId(p);
        if (law.finiteStrain(m)) {
          double F[Dim][Dim];
          for (int i = 0; i < Dim; ++i)
            for (int j = 0; j < Dim; ++j) {
              double fij = Fp(p, i, j);
              for (int k = 0; k < Dim; ++k) fij += G[i][k] * Fp(p, k, j);
              F[i][j] = fij;
            }
          double h[ParticleSet::kHistoryCount];
          const bool withHistory = law.hasHistory(m);
          if (withHistory)
            for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h[i] = hist(p, i);
          law.template stress<Dim>(m, trial, G, F, withHistory ? h : nullptr, trial);
          scatterInternalForceDeformed(st, ix, vol(p), trial, G, out, f0);
        } else {
          law.linearElastic(m).template stress<Dim>(trial, G, trial);
          scatterInternalForce(st, ix, vol(p), trial, out, f0);
        }
      });
}

// R_i = inertia_i - m_i (c2 v_i + c3 a_i) - F_int,i - F_ext,i at a node's component, from the
// step's grid state s and forces f (StateColumns, ForceColumns). The inertia is m c1 u (lumped)
// or c1 (M_C u) (consistent mass, from the force multivector's mass product).
template <int Dim, class StateView, class ForceView>
struct NewmarkResidualAtNode {
  StateView s;
  ForceView f;
  double c1, c2, c3;
  bool consistentMass;
  // (With several velocity fields: the field's state and force columns start at so and fo.)
  KOKKOS_INLINE_FUNCTION double operator()(int n, int d, double u, int so = 0, int fo = 0) const {
    using SC = implicit::StateColumns<Dim>;
    using FC = implicit::ForceColumns<Dim>;
    const double m = s(n, so + SC::Mass);
    const double inertia = consistentMass ? c1 * f(n, fo + FC::MassProductX + d) : m * c1 * u;
    return inertia - m * (c2 * s(n, so + SC::VelX + d) + c3 * s(n, so + SC::AccX + d)) - f(n, fo + FC::ForceX + d) -
           s(n, so + SC::FextX + d);
  }
};

template <int Dim, class StateView, class ForceView>
NewmarkResidualAtNode<Dim, StateView, ForceView> newmarkResidualAtNode(const StateView& s, const ForceView& f,
                                                                       const NewmarkConstants& k, bool consistentMass) {
  return {s, f, k.c1, k.c2, k.c3, consistentMass};
}

}  // namespace impm
