#include "solvers/ExplicitStepper.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/PhaseTimer.hpp"

#include <stdexcept>

namespace impm {

template <class Shape, int Dim>
ExplicitStepper<Shape, Dim>::ExplicitStepper(ParticleSet& particles, const GridDistribution& dist,
                                             const Materials& material, GridConditions& conditions,
                                             const LoadSet& loads, const ExplicitOptions& options)
    : ps_(particles),
      dist_(dist),
      mat_(material),
      conditions_(conditions),
      loads_(loads),
      opt_(options),
      fieldCount_(conditions.fieldCount()),
      sumsStride_(fieldCount_ > 1 ? A::Count + 2 * Dim : 0),
      kinStride_(fieldCount_ > 1 ? K::Count : 0),
      geometryCol_(fieldCount_ > 1 ? A::Count : -1),
      fields_(dist, fieldCount_ > 1 ? fieldCount_ * sumsStride_ : A::Count, fieldCount_ * K::Count),
      projection_(dist) {
  if (fieldCount_ > 1 && opt_.projectionIterations > 0)
    throw std::invalid_argument(
        "the projection correction works on one velocity field; multi-field contact needs "
        "'Integrator/Explicit/Projection Iterations' = 0");
  if (carriesAffineVelocity(opt_.transfer) && opt_.projectionIterations > 0)
    throw std::invalid_argument(
        "the projection correction corrects v_p, not an affine particle velocity; APIC and TPIC need "
        "'Integrator/Explicit/Consistent Projection Iterations' = 0");
  if (carriesAffineVelocity(opt_.transfer) && !ps_.hasAffine()) ps_.allocateAffine();
  if (opt_.transfer == ParticleTransfer::Xpic) {
    if (fieldCount_ > 1)
      throw std::invalid_argument(
          "XPIC extrapolates one velocity field; multi-field contact and rigid bodies need "
          "'Integrator/Explicit/Transfer' FLIP/PIC, APIC or TPIC");
    if (opt_.projectionIterations > 0)
      throw std::invalid_argument(
          "XPIC filters the particle velocity itself; it needs "
          "'Integrator/Explicit/Consistent Projection Iterations' = 0");
    if (opt_.xpicOrder < 1) throw std::invalid_argument("the XPIC order must be at least 1");
    xpic_ = std::make_unique<XpicExtrapolation<Shape, Dim>>(dist, opt_.xpicOrder);
  }
  conditions_.useFieldColumns(sumsStride_, kinStride_);
  if (opt_.fbar) fbar_ = std::make_unique<FbarAveraging<Dim>>(dist, mat_.count());
  // Void-node cut-off relative to the heaviest particle (global), fixed for the run.
  massCutoff_ = opt_.massTolerance * heaviestParticleMass(ps_, *dist.comm());
}

// Runs f(columns) with each particle's field in a grid view whose fields are `stride` columns
// apart: SingleField without contact (the kernels' columns stay compile-time constants), or
// FieldColumns.
template <class Shape, int Dim>
template <class F>
void ExplicitStepper<Shape, Dim>::withFields(int stride, const F& f) const {
  if (fieldCount_ > 1)
    f(FieldColumns(ps_, conditions_.fieldOfBody(), stride));
  else
    f(SingleField());
}

template <class Shape, int Dim>
std::string ExplicitStepper<Shape, Dim>::name() const {
  const char* s = opt_.scheme == ExplicitScheme::USF ? "USF" : opt_.scheme == ExplicitScheme::USL ? "USL" : "MUSL";
  const std::string transfer = opt_.transfer == ParticleTransfer::Apic   ? " APIC"
                               : opt_.transfer == ParticleTransfer::Tpic ? " TPIC"
                               : opt_.transfer == ParticleTransfer::Xpic
                                   ? " XPIC(" + std::to_string(opt_.xpicOrder) + ")"
                                   : "";
  return std::string("explicit ") + Shape::name + " " + s + transfer;
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::particleToGridMomentum() {
  PhaseTimer phase("p2g");
  auto grid = fields_.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
  zeroGridRows<Exec>(grid);  // not putScalar: see zeroGridRows
  withFields(sumsStride_, [&](const auto& columns) {
    particleToGridMassMomentum<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, A::Mass, A::MomX, -1,
                                                 geometryCol_, columns, carriesAffineVelocity(opt_.transfer));
  });
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::particleToGridForces(double t, bool withMomentum) {
  PhaseTimer phase("p2g");
  auto grid = fields_.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadWrite);
  withFields(sumsStride_, [&](const auto& columns) {
    if (withMomentum) {
      zeroGridRows<Exec>(grid);  // not putScalar: see zeroGridRows
      particleToGridMomentumAndForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, A::Mass,
                                                       A::MomX, A::FintX, geometryCol_, columns,
                                                       carriesAffineVelocity(opt_.transfer));
    } else {
      accumulateInternalForce<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, ps_.stress, grid, A::FintX,
                                                columns);
    }
    loads_.template scatterParticleForces<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, A::FextX,
                                                            t, columns);
  });
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::gridUpdate(double dt, bool withForces) {
  PhaseTimer phase("grid update");
  auto acc = fields_.accumOwned->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto kinv = fields_.kinOwned->getLocalViewDevice(Tpetra::Access::OverwriteAll);
  const double cutoff = massCutoff_;
  const double damping = withForces ? opt_.massDamping : 0.0;
  const int fields = fieldCount_, ss = sumsStride_, ks = kinStride_;
  Kokkos::parallel_for(
      "grid_update", Kokkos::RangePolicy<Exec>(0, acc.extent(0)), KOKKOS_LAMBDA(int n) {
        for (int f = 0; f < fields; ++f) {
          const int s = f * ss, k = f * ks;
          const double m = acc(n, s + A::Mass);
          if (m <= cutoff) {
            for (int c = 0; c < K::Count; ++c) kinv(n, k + c) = 0.0;
            continue;
          }
          for (int d = 0; d < Dim; ++d) {
            const double v = acc(n, s + A::MomX + d) / m;
            const double a = withForces ? (acc(n, s + A::FintX + d) + acc(n, s + A::FextX + d)) / m - damping * v : 0.0;
            kinv(n, k + K::VelX + d) = v + dt * a;
            kinv(n, k + K::AccX + d) = a;
          }
        }
      });
  // Grid conditions: contact between the bodies, prescribed velocity and acceleration, and the
  // force that holds them; the walls.
  if (withForces) {
    conditions_.template afterExplicitGridUpdate<Exec>(acc, A::Mass, A::MomX, A::FextX, A::FintX, geometryCol_, kinv,
                                                       K::VelX, K::AccX, damping);
  } else {  // (update stress first: the velocity at the start of the step)
    conditions_.template onStressVelocity<Exec>(acc, A::Mass, geometryCol_, kinv, K::VelX, K::AccX, ks, false);
  }
}

// See solvers/ProjectionCorrection.hpp: v += M_L^-1 (p - M_C v) on the momentum sums.
template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::correctProjection() {
  PhaseTimer phase("projection correction");
  projection_.apply(*fields_.accumOwned, A::Mass, A::MomX, ps_, ps_.v, conditions_, PrescribedField::StartVelocity,
                    massCutoff_, opt_.projectionIterations);
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::extrapolateParticleVelocity() {
  if (!xpic_) return;
  PhaseTimer phase("xpic");
  xpic_->replaceParticleVelocity(*fields_.accumOwned, A::Mass, A::MomX, ps_, conditions_, massCutoff_);
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::stressFromGhostedVelocity(double dt, bool fromAccum) {
  PhaseTimer phase("stress update");
  if (fromAccum) {
    auto grid = fields_.accumGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    withFields(sumsStride_, [&](const auto& columns) {
      gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, A::MomX, columns);
    });
  } else {
    auto grid = fields_.kinGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    withFields(kinStride_, [&](const auto& columns) {
      gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, grid, K::VelX, columns);
    });
  }
  updateParticleStresses(dt);
}

template <class Shape, int Dim>
void ExplicitStepper<Shape, Dim>::updateParticleStresses(double dt) {
  const DomainConvection domain = ConvectsDomain<Shape>::value ? DomainConvection(dist_.grid()) : DomainConvection();
  if (fbar_) {
    fbar_->template accumulate<Exec>(ps_, dt);
    updateStress<Exec, Dim>(ps_, mat_.law(), dt, true, domain, fbar_->correction(ps_));
  } else {
    updateStress<Exec, Dim>(ps_, mat_.law(), dt, true, domain);
  }
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
  extrapolateParticleVelocity();

  {
    PhaseTimer phase("g2p");
    auto kinv = fields_.kinGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    // USL: the stress update from grad v^{n+1} runs inside g2p (after it with F-bar, which needs
    // every particle's gradient first).
    const bool usl = opt_.scheme == ExplicitScheme::USL && !fbar_;
    withFields(kinStride_, [&](const auto& columns) {
      gridToParticleExplicit<Exec, Shape, Dim>(g, gix, ps_, kinv, dt, opt_.flip, opt_.scheme != ExplicitScheme::MUSL,
                                               mat_.law(), usl, columns, opt_.transfer);
    });
  }
  if (opt_.scheme == ExplicitScheme::USL && fbar_) {
    PhaseTimer phase("stress update");
    updateParticleStresses(dt);
  }
  if (opt_.scheme == ExplicitScheme::MUSL) {
    // Re-map the updated particle momentum, then the stress from that velocity field.
    particleToGridMomentum();
    fields_.exportAccumulated();
    correctProjection();
    {
      auto acc = fields_.accumOwned->getLocalViewDevice(Tpetra::Access::ReadWrite);
      const double cutoff = massCutoff_;
      const int fields = fieldCount_, ss = sumsStride_;
      Kokkos::parallel_for(
          "musl_velocity", Kokkos::RangePolicy<Exec>(0, acc.extent(0)), KOKKOS_LAMBDA(int n) {
            for (int f = 0; f < fields; ++f) {
              const double m = acc(n, f * ss + A::Mass);
              for (int d = 0; d < Dim; ++d)
                acc(n, f * ss + A::MomX + d) = m > cutoff ? acc(n, f * ss + A::MomX + d) / m : 0.0;
            }
          });
      conditions_.template onStressVelocity<Exec>(acc, A::Mass, geometryCol_, acc, A::MomX, -1, ss, true);
    }
    fields_.importAccumulated();
    stressFromGhostedVelocity(dt, true);
    auto kinv = fields_.kinGhosted->getLocalViewDevice(Tpetra::Access::ReadOnly);
    withFields(kinStride_, [&](const auto& columns) {
      interpolateToParticles<Exec, Shape, Dim>(g, gix, ps_, kinv, K::VelX, ps_.x, dt, true, columns);
    });
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
