// XPIC(m), the extended PIC particle update (Hammerquist & Nairn 2017, CMAME 318:724).
//
// FLIP updates v_p by the grid's velocity change and so keeps whatever the particles carry,
// the grid's null-space noise included; PIC replaces v_p by the grid velocity and damps every
// motion the grid cannot hold. XPIC(m) replaces the particles' old velocity by
//   v*_i = sum_{k=1}^{m} (-1)^(k+1) C(m, k) T^(k-1) v_i^n,    T = M_L^-1 M_C = M_L^-1 S^T M_p S,
// a grid field that approximates the particles' velocity with the null-space part removed, and
// then updates like FLIP:
//   v_p <- sum_i S_ip (v*_i + dt a_i).
// m = 1 is PIC (v* = v^n); m -> infinity tends to FLIP without the null-space noise. Each order
// above one costs one pass over the particles (M_C w gathers and scatters) and one ghost exchange.
// Prescribed velocity components hold their value in every term, so v* holds it too (the
// binomial coefficients sum to one).
#pragma once

#include "core/GridDistribution.hpp"
#include "core/kernels/FieldColumns.hpp"
#include "core/kernels/GridToParticle.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "physics/GridConditions.hpp"

namespace impm {

template <class Shape, int Dim>
class XpicExtrapolation {
 public:
  using Exec = ExecutionSpace;
  XpicExtrapolation(const GridDistribution& dist, int order)
      : dist_(dist),
        order_(order),
        termOwned_(Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), Dim))),
        termGhosted_(Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), Dim))),
        sumOwned_(Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), Dim))),
        sumGhosted_(Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), Dim))) {}

  int order() const { return order_; }

  // Sets ps.v = sum_i S_ip v*_i from the owned grid columns `owned`: node masses in massCol and,
  // in col.., the momenta p (v^n = p / m; the explicit step's sums) or, with `velocity`, v^n
  // itself (the implicit step's state), on nodes heavier than massCutoff.
  void replaceParticleVelocity(const MultiVector& owned, int massCol, int col, const ParticleSet& ps,
                               const GridConditions& conditions, double massCutoff, bool velocity = false) const {
    {
      auto s = owned.getLocalViewDevice(Tpetra::Access::ReadOnly);
      auto term = termOwned_->getLocalViewDevice(Tpetra::Access::OverwriteAll);
      Kokkos::parallel_for(
          "xpic_start", Kokkos::RangePolicy<Exec>(0, s.extent(0)), KOKKOS_LAMBDA(int n) {
            const double m = s(n, massCol);
            for (int d = 0; d < Dim; ++d)
              term(n, d) = m > massCutoff ? (velocity ? s(n, col + d) : s(n, col + d) / m) : 0.0;
          });
      conditions.template write<Exec>(term, 0, PrescribedField::StartVelocity);
    }
    // sum = C(m, 1) v^n; then term <- T term and sum += (-1)^(k+1) C(m, k) term for k = 2..m.
    sumOwned_->update(double(order_), *termOwned_, 0.0);
    double binomial = order_;
    for (int k = 2; k <= order_; ++k) {
      applyProjection(owned, massCol, ps, conditions, massCutoff);
      binomial *= double(order_ - k + 1) / k;
      sumOwned_->update(k % 2 == 0 ? -binomial : binomial, *termOwned_, 1.0);
    }
    sumGhosted_->doImport(*sumOwned_, *dist_.importer(), Tpetra::INSERT);
    auto vstar = sumGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    interpolateToParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps, vstar, 0, ps.v, 1.0, false);
  }

 private:
  // term <- M_L^-1 M_C term on owned nodes (void nodes 0, prescribed components their value).
  void applyProjection(const MultiVector& owned, int massCol, const ParticleSet& ps, const GridConditions& conditions,
                       double massCutoff) const {
    termGhosted_->doImport(*termOwned_, *dist_.importer(), Tpetra::INSERT);
    // The product is scattered into the ghosted sum vector, free until the end.
    sumGhosted_->putScalar(0.0);
    {
      auto w = termGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
      auto out = sumGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
      particleToGridMassProduct<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps, w, 0, out, 0);
    }
    termOwned_->putScalar(0.0);
    termOwned_->doExport(*sumGhosted_, *dist_.importer(), Tpetra::ADD);
    auto s = owned.getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto term = termOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    Kokkos::parallel_for(
        "xpic_projection", Kokkos::RangePolicy<Exec>(0, s.extent(0)), KOKKOS_LAMBDA(int n) {
          const double m = s(n, massCol);
          for (int d = 0; d < Dim; ++d) term(n, d) = m > massCutoff ? term(n, d) / m : 0.0;
        });
    conditions.template write<Exec>(term, 0, PrescribedField::StartVelocity);
  }

  const GridDistribution& dist_;
  int order_;
  Teuchos::RCP<MultiVector> termOwned_, termGhosted_, sumOwned_, sumGhosted_;
};

}  // namespace impm
