#include "solvers/ExplicitStepper.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/PhaseTimer.hpp"

namespace impm {

template <class Shape, int Dim>
ExplicitStepper<Shape, Dim>::ExplicitStepper(ParticleSet& particles, const GridDistribution& dist,
                                        const Materials& material, GridConditions& conditions,
                                        const LoadSet& loads, const ExplicitOptions& options)
    : ps_(particles), dist_(dist), mat_(material), conditions_(conditions), loads_(loads), opt_(options), fields_(dist, A::Count, K::Count),
      projection_(dist) {
  // Void-node cut-off relative to the heaviest particle (global), fixed for the run.
  massCutoff_ = opt_.massTolerance * heaviestParticleMass(ps_, *dist.comm());
}

template <class Shape, int Dim>
std::string ExplicitStepper<Shape, Dim>::name() const {
  const char* s = opt_.scheme == ExplicitScheme::USF ? "USF" : opt_.scheme == ExplicitScheme::USL ? "USL" : "MUSL";
  return std::string("explicit ") + Shape::name + " " + s;
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::particleToGridMomentum() {
  PhaseTimer phase("p2g");
  auto grid = fields_.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
  zeroGridRows<Exec>(grid);  // not putScalar: see zeroGridRows
  particleToGridMassMomentum<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, A::Mass, A::MomX);
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::particleToGridForces(double t, bool withMomentum) {
  PhaseTimer phase("p2g");
  auto grid = fields_.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
  if (withMomentum) {
    zeroGridRows<Exec>(grid);  // not putScalar: see zeroGridRows
    particleToGridMomentumAndForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, A::Mass,
                                                A::MomX, A::FintX);
  } else {
    accumulateInternalForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, ps_.stress, grid, A::FintX);
  }
  loads_.template scatterParticleForces<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, A::FextX, t);
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::gridUpdate(double dt, bool withForces) {
  PhaseTimer phase("grid update");
  auto acc = fields_.accumOwned->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto kinv = fields_.kinOwned->getLocalViewDevice(Tpetra::Access::OverwriteAll);
  const double cutoff = massCutoff_;
  const double damping = withForces ? opt_.massDamping : 0.0;
  Kokkos::parallel_for(
      "grid_update", Kokkos::RangePolicy<Exec>(0, acc.extent(0)), KOKKOS_LAMBDA(int n) {
        const double m = acc(n, A::Mass);
        if (m <= cutoff) {
          for (int c = 0; c < K::Count; ++c) kinv(n, c) = 0.0;
          return;
        }
        for (int d = 0; d < Dim; ++d) {
          const double v = acc(n, A::MomX + d) / m;
          const double a = withForces ? (acc(n, A::FintX + d) + acc(n, A::FextX + d)) / m - damping * v : 0.0;
          kinv(n, K::VelX + d) = v + dt * a;
          kinv(n, K::AccX + d) = a;
        }
      });
  // Grid conditions: prescribed velocity and acceleration, and the force that holds them.
  if (withForces) {
    conditions_.template afterExplicitGridUpdate<Exec>(acc, A::Mass, A::MomX, A::FextX, A::FintX, kinv, K::VelX, K::AccX,
                                                       damping);
  } else {  // (update stress first: the velocity at the start of the step)
    conditions_.template write<Exec>(kinv, K::VelX, PrescribedField::StartVelocity);
    conditions_.template write<Exec>(kinv, K::AccX, PrescribedField::Zero);
    conditions_.template enforceWalls<Exec>(acc, A::Mass, kinv, K::VelX);
  }
}

// See solvers/ProjectionCorrection.hpp: v += M_L^-1 (p - M_C v) on the momentum sums.
template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::correctProjection() {
  PhaseTimer phase("projection correction");
  projection_.apply(*fields_.accumOwned, A::Mass, A::MomX, ps_, ps_.v, conditions_, PrescribedField::StartVelocity, massCutoff_,
                    opt_.projectionIterations);
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::stressFromGhostedVelocity(double dt, bool fromAccum) {
  PhaseTimer phase("stress update");
  if (fromAccum) {
    auto grid = fields_.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, A::MomX);
  } else {
    auto grid = fields_.kinGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, K::VelX);
  }
  updateStress<Exec, Dim>(ps_, mat_.law(), dt, true,
                          ConvectsDomain<Shape>::value ? DomainConvection(dist_.grid()) : DomainConvection());
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::step(double t, double dt) {
  const StructuredGrid& g = dist_.grid();
  const LocalNodeIndexer& gix = dist_.ghostedIndexer();
  conditions_.setStep(t, dt);

  const bool usf = opt_.scheme == ExplicitScheme::USF;
  if (usf) {
    // Stress first, from the velocity of the particle momentum.
    particleToGridMomentum();
    fields_.exportAccumulated();
    correctProjection();
    gridUpdate(dt, false);
    fields_.importKinematics();
    stressFromGhostedVelocity(dt, false);
  }
  particleToGridForces(t, !usf);
  fields_.exportAccumulated();
  correctProjection();
  {
    auto owned = fields_.accumOwned->getLocalViewDevice(Tpetra::Access::ReadWrite);
    loads_.template applyNodal<Exec>(owned, A::FextX, t);
  }
  gridUpdate(dt, true);
  fields_.importKinematics();

  {
    PhaseTimer phase("g2p");
    auto kinv = fields_.kinGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    const bool usl = opt_.scheme == ExplicitScheme::USL;
    // USL: the stress update from grad v^{n+1} runs inside g2p.
    gridToParticleExplicit<Exec, Shape, Dim>(g, gix, ps_, kinv, dt, opt_.flip, opt_.scheme != ExplicitScheme::MUSL,
                                        mat_.law(), usl);
  }
  if (opt_.scheme == ExplicitScheme::MUSL) {
    // Re-map the updated particle momentum, then the stress from that velocity field.
    particleToGridMomentum();
    fields_.exportAccumulated();
    correctProjection();
    {
      auto acc = fields_.accumOwned->getLocalViewDevice(Tpetra::Access::ReadWrite);
      const double cutoff = massCutoff_;
      Kokkos::parallel_for(
          "musl_velocity", Kokkos::RangePolicy<Exec>(0, acc.extent(0)), KOKKOS_LAMBDA(int n) {
            const double m = acc(n, A::Mass);
            for (int d = 0; d < Dim; ++d) acc(n, A::MomX + d) = m > cutoff ? acc(n, A::MomX + d) / m : 0.0;
          });
      conditions_.template write<Exec>(acc, A::MomX, PrescribedField::EndVelocity);
      conditions_.template enforceWalls<Exec>(acc, A::Mass, acc, A::MomX);
    }
    fields_.importAccumulated();
    stressFromGhostedVelocity(dt, true);
    auto kinv = fields_.kinGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    interpolateToParticles<Exec, Shape, Dim>(g, gix, ps_, kinv, K::VelX, ps_.x, dt, true);
  }
}

template class ExplicitStepper<LinearMpm, 2>;
template class ExplicitStepper<UniformGimp, 2>;
template class ExplicitStepper<QuadraticBSpline, 2>;
template class ExplicitStepper<LinearMpm, 3>;
template class ExplicitStepper<UniformGimp, 3>;
template class ExplicitStepper<ConvectedGimp, 2>;
template class ExplicitStepper<ConvectedGimp, 3>;
template class ExplicitStepper<Cpdi, 2>;
template class ExplicitStepper<Cpdi, 3>;
template class ExplicitStepper<QuadraticBSpline, 3>;
template class ExplicitStepper<CubicBSpline, 2>;
template class ExplicitStepper<CubicBSpline, 3>;

}  // namespace impm
