// ImplicitNewmark<Shape, Dim> as NOX's model: the residual R(u) over the free dofs, the matrix P
// that preconditions it (or is its Jacobian) and the residual's magnitude for the stopping test.
// Included by ImplicitNewmarkImpl.hpp.
#pragma once

#include "solvers/implicit/ImplicitNewmark.hpp"

#include <Tpetra_CrsMatrix.hpp>

#include <cmath>

#include "core/PhaseTimer.hpp"
#include "core/kernels/GridToParticle.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "core/kernels/Stiffness.hpp"
#include "solvers/implicit/ImplicitGridColumns.hpp"
#include "solvers/implicit/TrialInternalForce.hpp"

namespace impm {

// ---- Residual and matrix ----------------------------------------------------------------------

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::scatterUnknowns(const Vector& u) {
  using DC = implicit::DisplacementColumns<Dim>;
  dispOwned_->putScalar(0.0);
  {
    auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto uv = u.getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto node = dofs_.node();
    auto comp = dofs_.component();
    auto field = dofs_.field();
    const int ds = dispStride_;
    Kokkos::parallel_for(
        "scatter_unknowns", Kokkos::RangePolicy<Exec>(0, node.extent(0)),
        KOKKOS_LAMBDA(int k) { d(node(k), field(k) * ds + DC::UX + comp(k)) = uv(k, 0); });
    // The prescribed dofs move by their increment (they are not unknowns; zero is already there).
    if (!conditions_.isZero(PrescribedField::Increment))
      conditions_.template write<Exec>(d, DC::UX, PrescribedField::Increment, ds);
    forEachRigidDof(
        stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
        KOKKOS_LAMBDA(int n, int f, int c, const RigidFieldMotion& rigid) {
          d(n, f * ds + DC::UX + c) = rigid.increment(f, c);
        });
  }
  dispGhosted_->doImport(*dispOwned_, *dist_.importer(), Tpetra::INSERT);
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::residual(const Vector& u, Vector& R) {
  using DC = implicit::DisplacementColumns<Dim>;
  using FC = implicit::ForceColumns<Dim>;
  PhaseTimer phase("residual");
  scatterUnknowns(u);
  forceGhosted_->putScalar(0.0);
  {
    auto f = forceGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    if (fbar_) {  // the cells' volume change first (core/kernels/FbarAveraging.hpp)
      gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DC::UX);
      fbar_->template accumulate<Exec>(ps_, 1.0);
      scatterTrialInternalForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, mat_, d, DC::UX, f,
                                                  FC::ForceX, fbar_->correction(ps_));
    } else if (fields_ > 1) {
      const FieldColumns dispFields(ps_, conditions_.fieldOfBody(), dispStride_);
      const FieldColumns forceFields(ps_, conditions_.fieldOfBody(), forceStride_);
      scatterTrialInternalForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, mat_, d, DC::UX, f,
                                                  FC::ForceX, NoStrainCorrection(), dispFields, forceFields);
    } else {
      scatterTrialInternalForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, mat_, d, DC::UX, f,
                                                  FC::ForceX);
    }
    if (opt_.consistentMass)  // M_C u = sum_p m_p S_ip u_p with u_p = sum_j S_jp u_j
      particleToGridMassProduct<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DC::UX, f,
                                                  FC::MassProductX);
  }
  forceOwned_->putScalar(0.0);
  forceOwned_->doExport(*forceGhosted_, *dist_.importer(), Tpetra::ADD);
  if (fields_ > 1) addContactForces();
  if (conditions_.hasWalls()) {  // the friction of the slipping wall nodes, at these forces
    using SC = implicit::StateColumns<Dim>;
    const auto normalReaction = heldWallReaction();  // read before the friction is added
    conditions_.implicitWalls().template addFriction<Exec>(
        normalReaction, stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly), SC::FreeX,
        forceOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite), FC::ForceX, opt_.newmark.gamma, stateStride_,
        forceStride_);
  }
  const auto atNode = newmarkResidualAtNode<Dim>(stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                 forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly),
                                                 NewmarkConstants(opt_.newmark, dt_), opt_.consistentMass);
  auto uv = u.getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto r = R.getLocalViewDevice(Tpetra::Access::OverwriteAll);
  auto node = dofs_.node();
  auto comp = dofs_.component();
  auto field = dofs_.field();
  const int ss = stateStride_, fs = forceStride_;
  Kokkos::parallel_for(
      "implicit_residual", Kokkos::RangePolicy<Exec>(0, node.extent(0)),
      KOKKOS_LAMBDA(int k) { r(k, 0) = atNode(node(k), comp(k), uv(k, 0), field(k) * ss, field(k) * fs); });
  if (!conditions_.empty()) {  // forceOwned_ now holds the forces at u (recordReactions reuses them)
    if (lastResidualPoint_.is_null() || lastResidualPoint_->getMap().get() != dofs_.map().get())
      lastResidualPoint_ = Teuchos::rcp(new Vector(dofs_.map(), false));
    Tpetra::deep_copy(*lastResidualPoint_, u);
  }
}

// || |P| |u| + |m (c2 v + c3 a)| + |F_ext| ||_2 over the free dofs (ResidualModel::residualMagnitude):
// with the step's assembled P when there is one (the stiffness carries the large terms of a stiff
// body's internal force), else with its lumped-mass part c1 m alone.
template <class Shape, int Dim>
double ImplicitNewmark<Shape, Dim>::residualMagnitude(const Vector& u) {
  using SC = implicit::StateColumns<Dim>;
  const auto map = dofs_.map();
  Vector absU(map, false), sum(map, false);
  absU.abs(u);
  const auto P = assembler_.matrix();
  const bool withP = !P.is_null() && P->getRowMap().get() == map.get();
  if (withP) {
    // Every assembly bumps the Jacobian version (a new P object too): |P| is taken once per P.
    if (absP_.is_null() || absPVersion_ != refresh_.jacobianVersion()) {
      absP_ = Teuchos::rcp(new CrsMatrix(*P, Teuchos::Copy));
      auto values = absP_->getLocalMatrixDevice().values;
      Kokkos::parallel_for(
          "abs_P", Kokkos::RangePolicy<Exec>(0, values.extent(0)),
          KOKKOS_LAMBDA(int k) { values(k) = std::fabs(values(k)); });
      absPVersion_ = refresh_.jacobianVersion();
    }
    absP_->apply(absU, sum);
  } else {
    sum.putScalar(0.0);
  }
  {
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto au = absU.getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto out = sum.getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto node = dofs_.node();
    auto comp = dofs_.component();
    auto field = dofs_.field();
    const int ss = stateStride_;
    const NewmarkConstants k(opt_.newmark, dt_);
    const double c1 = k.c1, c2 = k.c2, c3 = k.c3;
    Kokkos::parallel_for(
        "residual_magnitude", Kokkos::RangePolicy<Exec>(0, node.extent(0)), KOKKOS_LAMBDA(int i) {
          const int n = node(i), d = comp(i), o = field(i) * ss;
          const double m = s(n, o + SC::Mass);
          const double start = std::fabs(m * (c2 * s(n, o + SC::VelX + d) + c3 * s(n, o + SC::AccX + d))) +
                               std::fabs(s(n, o + SC::FextX + d));
          out(i, 0) = (withP ? out(i, 0) : m * c1 * au(i, 0)) + start;
        });
  }
  return sum.norm2();
}

// The stiffness kernels' blocks: the seed's overlap-integrated GIMP stiffness (cells, 2D), or one
// stencil block per particle (with the consistent mass c1 M_C in it when the residual has it).
template <class Shape, int Dim>
BlockMatrices ImplicitNewmark<Shape, Dim>::stiffnessBlocks(bool trialTangent) const {
  const StructuredGrid& g = dist_.grid();
  // With several fields, each block belongs to its particle's body's field.
  const auto withFieldOf = [&](BlockMatrices blocks, Kokkos::View<const int*, DeviceType> particle) {
    if (fields_ == 1) return blocks;
    blocks.field = Kokkos::View<int*, DeviceType>("block_field", blocks.count);
    auto out = blocks.field;
    auto body = ps_.body;
    auto fieldOf = conditions_.fieldOfBody();
    const bool perParticle = particle.extent(0) == 0;
    Kokkos::parallel_for(
        "stiffness_block_field", Kokkos::RangePolicy<Exec>(0, blocks.count),
        KOKKOS_LAMBDA(int k) { out(k) = fieldOf(body(perParticle ? k : particle(k))); });
    return blocks;
  };
  if constexpr (Dim == 2) {
    if (seedGimpStiffness_) {
      const ParticleCellPairs pairs = buildParticleCellPairs<Exec>(g, ps_, false);
      return withFieldOf(overlapStiffness<Exec>(g, pairs, ps_, mat_.law()), pairs.particle);
    }
  }
  const double massFactor = opt_.consistentMass ? opt_.newmark.c1(dt_) : 0.0;
  return withFieldOf(stencilStiffness<Exec, Shape, Dim>(g, ps_, mat_.law(), massFactor, trialTangent),
                     Kokkos::View<const int*, DeviceType>());
}

// The contact penalty's stiffness for P at u: F_c = coefficient m (v* - v_new) with
// d v_new / d u = gamma / (beta dt) (addContactForces), linearized by the law with the active set's
// states, the fields of a node coupled through the velocity they meet at. With the states held
// and the normals fixed for the step, this is the exact derivative of the contact force.
template <class Shape, int Dim>
typename StiffnessAssembler<Dim>::NodeCouplings ImplicitNewmark<Shape, Dim>::contactStiffness(const Vector& u,
                                                                                              bool scattered) {
  using SC = implicit::StateColumns<Dim>;
  if (!scattered) scatterUnknowns(u);
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const double coefficient = contactPenaltyCoefficient();
  typename StiffnessAssembler<Dim>::NodeCouplings couplings;
  couplings.values = conditions_.template linearizeImplicitContact<Exec>(s, SC::Mass, geometryCol_, stateStride_,
                                                                         trialEndVelocity(), coefficient);
  couplings.factor = coefficient * opt_.newmark.gamma / (opt_.newmark.beta * dt_);
  return couplings;
}

// P = c1 M + K over the free dofs (K over particle-cell pairs, exact over overlaps for GIMP).
// Small strain: P does not depend on u and is assembled at most once per step; the trial tangent
// (finite strain, see PreconditionerRefresh) at every Newton iterate. The consistent mass goes
// into the stencil blocks, so that P is the Jacobian of the consistent-mass residual; the seed's
// GIMP blocks (cells) cannot hold a GIMP stencil's mass coupling, so P keeps the lumped mass there.
template <class Shape, int Dim>
Teuchos::RCP<const CrsMatrix> ImplicitNewmark<Shape, Dim>::jacobianMatrix(const Vector& u) {
  using SC = implicit::StateColumns<Dim>;
  using DC = implicit::DisplacementColumns<Dim>;
  PhaseTimer phase("stiffness assembly");
  const bool trialTangent = refresh_.trialTangent(mat_.anyFiniteStrain() && !seedGimpStiffness_);
  if (PCurrent_ && !trialTangent) return assembler_.matrix();
  if (!restoredP_.empty()) {
    assembler_.restore(restoredP_, dofs_);
    restoredP_.clear();
  }
  if (trialTangent) {
    // grad u of the trial displacement at each particle, for the stiffness kernel.
    scatterUnknowns(u);
    auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DC::UX);
    if (fbar_) {  // the preconditioner's tangent at the barred state (without F-bar's cell coupling)
      fbar_->template accumulate<Exec>(ps_, 1.0);
      fbar_->template correctGradients<Exec>(ps_);
    }
  }
  // With contact P carries the active set's stiffness, so it is assembled for every solve.
  if (fields_ == 1 && refresh_.keep(!assembler_.matrix().is_null(), trialTangent)) {
    PCurrent_ = true;
    return assembler_.matrix();
  }
  const bool graphChanged = assembler_.updatePattern(*stateGhosted_, SC::FreeX, dofs_);
  const bool consistentMassInP = opt_.consistentMass && !seedGimpStiffness_;
  typename StiffnessAssembler<Dim>::NodeCouplings contact;
  if (fields_ > 1) contact = contactStiffness(u, trialTangent);
  assembler_.fill(stiffnessBlocks(trialTangent), dofs_, consistentMassInP ? nullptr : stateOwned_.get(), SC::Mass,
                  opt_.newmark.c1(dt_), fields_ > 1 ? &contact : nullptr);
  refresh_.assembled(graphChanged);
  PCurrent_ = true;
  return assembler_.matrix();
}

}  // namespace impm
