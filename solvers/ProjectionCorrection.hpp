// The consistent-projection correction, once for both integrators. The lumped projection of a
// particle field to the grid, f_i = sum_p m_p S_ip f_p / m_i = M_L^-1 p, smooths the field by
// M_L^-1 M_C every step: for a wave of number k on cells of size h it scales the field by about
// 1 - (kh)^2/6 (explicit: twice the lumped-mass dispersion again). Each Jacobi iteration
//   p += r,  r = p - M_C (p / m)   (on owned nodes; prescribed components of p / m take their values)
// squares that factor's deviation from 1.
#pragma once

#include "core/GridDistribution.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "physics/GridConditions.hpp"

namespace impm {

template <class Shape, int Dim>
class ProjectionCorrection {
 public:
  using Exec = ExecutionSpace;
  explicit ProjectionCorrection(const GridDistribution& dist)
      : dist_(dist),
        fieldOwned_(Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), Dim))),
        fieldGhosted_(Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), Dim))),
        residualOwned_(Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), Dim))),
        residualGhosted_(Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), Dim))) {}

  // Corrects columns momCol.. (Dim of them) of `owned` (the particle sums m f) in place, with the
  // node masses in massCol; `particleField` is f_p (ps.v or ps.a), `prescribed` its value at the
  // grid conditions' dofs.
  void apply(MultiVector& owned, int massCol, int momCol, const ParticleSet& ps, const ParticleSet::Vec& particleField,
             const GridConditions& conditions, PrescribedField prescribed, double massCutoff, int iterations) const {
    for (int it = 0; it < iterations; ++it) {
      {
        auto s = owned.getLocalViewDevice(Tpetra::Access::ReadOnly);
        auto f = fieldOwned_->getLocalViewDevice(Tpetra::Access::OverwriteAll);
        const double cutoff = massCutoff;
        Kokkos::parallel_for(
            "projection_field", Kokkos::RangePolicy<Exec>(0, s.extent(0)), KOKKOS_LAMBDA(int n) {
              const double m = s(n, massCol);
              for (int d = 0; d < Dim; ++d) f(n, d) = m > cutoff ? s(n, momCol + d) / m : 0.0;
            });
        conditions.template write<Exec>(f, 0, prescribed);
      }
      fieldGhosted_->doImport(*fieldOwned_, *dist_.importer(), Tpetra::INSERT);
      residualGhosted_->putScalar(0.0);
      {
        auto f = fieldGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
        auto r = residualGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
        particleToGridProjectionResidual<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps, f, 0, r, 0,
                                                           particleField);
      }
      residualOwned_->putScalar(0.0);
      residualOwned_->doExport(*residualGhosted_, *dist_.importer(), Tpetra::ADD);
      auto s = owned.getLocalViewDevice(Tpetra::Access::ReadWrite);
      auto r = residualOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
      Kokkos::parallel_for(
          "projection_correction", Kokkos::RangePolicy<Exec>(0, s.extent(0)), KOKKOS_LAMBDA(int n) {
            for (int d = 0; d < Dim; ++d) s(n, momCol + d) += r(n, d);
          });
    }
  }

 private:
  const GridDistribution& dist_;
  Teuchos::RCP<MultiVector> fieldOwned_, fieldGhosted_, residualOwned_, residualGhosted_;
};

}  // namespace impm
