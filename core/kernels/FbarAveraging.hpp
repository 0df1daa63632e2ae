// F-bar volumetric-locking control (de Souza Neto et al. 1996; in MPM, Coombs et al. 2018).
// Low-order interpolation with several particles per cell asks each particle to keep its own
// volume under isochoric plastic flow: more constraints than the grid has velocities, and the
// grid locks. F-bar keeps one volumetric constraint per cell. Each particle's step increment of
// the deformation gradient dF = I + G is replaced by
//   dF_bar = (dJ_cell / dJ_p)^(1/Dim) dF,   dJ_p = det dF,
//   dJ_cell = sum_q V_q dJ_q / sum_q V_q   over the particles q of the same material in p's cell,
// with V the volumes at the step's start: the volume change is the cell's (so the cell's
// particles keep its total volume change exactly), the isochoric part the particle's own. In 2D
// the determinant is the in-plane one and the exponent 1/2 (plane strain: the out-of-plane
// stretch stays 1). Everything downstream of G -- the law, F, the volume, cpGIMP's domain, the
// implicit residual's deformed gradients -- sees G_bar = dF_bar - I. For a uniform G the
// correction is the identity.
//
// A cell's sums sit on its lowest corner node (a bijection between cells and those nodes), in
// 2 x materials columns of a node multivector. A particle's corner node is in its stencil, so it
// is among the rank's ghosted nodes; the grid's Export (ADD) and Import then gather a cell's
// particles from every rank, as they do for p2g sums. The scatter is a ScatterView over the
// particles' static partition: bit-for-bit reproducible at a given thread count.
#pragma once

#include <Kokkos_ScatterView.hpp>

#include <cmath>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "core/SmallMatrix.hpp"
#include "core/StructuredGrid.hpp"
#include "core/kernels/Interpolation.hpp"

namespace impm {

// The corner node (ghosted row) of a point's cell.
template <int Dim>
KOKKOS_INLINE_FUNCTION int cellCornerRow(const StructuredGrid& g, const LocalNodeIndexer& ix, const double* x) {
  return ix(cellIndexOf(g, 0, x[0]), cellIndexOf(g, 1, x[1]), Dim == 3 ? cellIndexOf(g, 2, x[2]) : 0);
}

// G <- (dJ_cell / det(I + G))^(1/Dim) (I + G) - I, from the summed cell columns (ghosted).
template <int Dim, class SumView>
struct FbarCorrection {
  SumView sums;
  StructuredGrid grid;
  LocalNodeIndexer ix;
  typename FixedParticleViews<Dim>::Vec x;
  ParticleSet::Ids material;

  KOKKOS_INLINE_FUNCTION void operator()(int p, double (&G)[Dim][Dim]) const {
    double pos[Dim];
    for (int d = 0; d < Dim; ++d) pos[d] = x(p, d);
    const int row = cellCornerRow<Dim>(grid, ix, pos), c = 2 * material(p);
    double dF[Dim][Dim];
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) dF[i][j] = G[i][j] + (i == j ? 1.0 : 0.0);
    const double dJ = determinant<Dim>(dF), volume = sums(row, c + 1);
    if (!(dJ > 0.0) || !(volume > 0.0)) return;  // (an inverted particle: the law reports it)
    const double dJcell = sums(row, c) / volume;
    if (!(dJcell > 0.0)) return;
    const double scale = Dim == 2 ? std::sqrt(dJcell / dJ) : std::cbrt(dJcell / dJ);
    for (int i = 0; i < Dim; ++i)
      for (int j = 0; j < Dim; ++j) G[i][j] = scale * dF[i][j] - (i == j ? 1.0 : 0.0);
  }
};

template <int Dim>
class FbarAveraging {
 public:
  FbarAveraging(const GridDistribution& dist, int materialCount)
      : dist_(dist),
        owned_(Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), 2 * materialCount))),
        ghosted_(dist.comm()->getSize() == 1
                     ? owned_
                     : Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), 2 * materialCount))) {}

  // The cell sums of V_p det(I + scale L_p) and V_p, L = the particles' gradient view (explicit:
  // grad v, scale dt; implicit: grad u, scale 1), gathered over the ranks. Collective.
  template <class Exec>
  void accumulate(const ParticleSet& ps, double scale) {
    {
      auto sums = ghosted_->getLocalViewDevice(Tpetra::Access::OverwriteAll);
      Kokkos::deep_copy(sums, 0.0);
      const FixedParticleViews<Dim> pv(ps);
      auto x = pv.x;
      auto L = pv.gradient;
      auto V = ps.volume;
      auto mat = ps.material;
      const StructuredGrid g = dist_.grid();
      const LocalNodeIndexer ix = dist_.ghostedIndexer();
      auto scatter = Kokkos::Experimental::create_scatter_view(sums);
      Kokkos::parallel_for(
          "fbar_cell_sums", scatterPolicy<Exec>(ps.count), KOKKOS_LAMBDA(int p) {
            double pos[Dim], dF[Dim][Dim];
            for (int d = 0; d < Dim; ++d) pos[d] = x(p, d);
            for (int i = 0; i < Dim; ++i)
              for (int j = 0; j < Dim; ++j) dF[i][j] = scale * L(p, i, j) + (i == j ? 1.0 : 0.0);
            const int row = cellCornerRow<Dim>(g, ix, pos), c = 2 * mat(p);
            auto access = scatter.access();
            access(row, c) += V(p) * determinant<Dim>(dF);
            access(row, c + 1) += V(p);
          });
      Kokkos::Experimental::contribute(sums, scatter);
    }
    if (ghosted_ != owned_) {
      owned_->putScalar(0.0);
      owned_->doExport(*ghosted_, *dist_.importer(), Tpetra::ADD);
      ghosted_->doImport(*owned_, *dist_.importer(), Tpetra::INSERT);
    }
  }

  // Replaces each particle's gradient view L by G_bar (scale 1: the implicit grad u), after
  // accumulate.
  template <class Exec>
  void correctGradients(const ParticleSet& ps) const {
    const auto correct = correction(ps);
    auto L = FixedParticleViews<Dim>(ps).gradient;
    Kokkos::parallel_for(
        "fbar_correct_gradients", Kokkos::RangePolicy<Exec>(0, ps.count), KOKKOS_LAMBDA(int p) {
          double G[Dim][Dim];
          for (int i = 0; i < Dim; ++i)
            for (int j = 0; j < Dim; ++j) G[i][j] = L(p, i, j);
          correct(p, G);
          for (int i = 0; i < Dim; ++i)
            for (int j = 0; j < Dim; ++j) L(p, i, j) = G[i][j];
        });
  }

  // The correction for the particles as accumulated (valid until the next accumulate).
  auto correction(const ParticleSet& ps) const {
    auto sums = ghosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    return FbarCorrection<Dim, decltype(sums)>{sums, dist_.grid(), dist_.ghostedIndexer(),
                                               FixedParticleViews<Dim>(ps).x, ps.material};
  }

 private:
  const GridDistribution& dist_;
  Teuchos::RCP<MultiVector> owned_, ghosted_;
};

}  // namespace impm
