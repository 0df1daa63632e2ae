// Explicit MPM/GIMP time stepping (update stress first, update stress last, modified USL)
// with a FLIP/PIC blend or an affine transfer (APIC, TPIC), built from the shared kernels in core/kernels.
#pragma once

#include <Teuchos_Comm.hpp>

#include "core/GridDistribution.hpp"
#include <memory>

#include "core/kernels/FbarAveraging.hpp"
#include "core/kernels/GridToParticle.hpp"
#include "core/kernels/InternalForce.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "physics/GridConditions.hpp"
#include "physics/Materials.hpp"
#include "physics/Loads.hpp"
#include "solvers/Integrator.hpp"
#include "solvers/ProjectionCorrection.hpp"
#include "solvers/XpicExtrapolation.hpp"

namespace impm {

enum class ExplicitScheme { USF, USL, MUSL };

// The explicit step impm accepts: Stability Factor (<= 1) x kTransferStabilityFraction x the
// critical step of lumped bilinear cells, 1 / (c_p sqrt(1/hx^2 + 1/hy^2)) (3D: + 1/hz^2). The particle
// transfers and the projection correction lower the real limit below the cells' own (which is
// 1.09-1.12 times that formula): measured by apps/stability_study.py over every scheme impm
// offers (USF, USL, MUSL; 0 or 1 projection iterations; 1, 2, 4 particles per cell; 2:1 and
// square cells) the smallest critical fraction is 0.775 (USL, 1 particle per cell, 2:1 cells; doc/stability.md);
// 0.7 keeps a 10% margin below it. (USF and MUSL were stable past 1.47.)
constexpr double kTransferStabilityFraction = 0.7;

struct ExplicitOptions {
  ExplicitScheme scheme = ExplicitScheme::USL;
  double flip = 1.0;  // 1 = pure FLIP, 0 = pure PIC
  // FlipPic: the `flip` blend; Apic, Tpic: the particles carry an affine velocity
  // (core/kernels/AffineTransfer.hpp), with the lumped projection only (projectionIterations 0);
  // Xpic: XPIC(xpicOrder), FLIP from an extrapolated old velocity (solvers/XpicExtrapolation.hpp).
  ParticleTransfer transfer = ParticleTransfer::FlipPic;
  int xpicOrder = 5;
  double massTolerance = 1e-12;  // nodes lighter than this fraction of the heaviest node are void
  // Jacobi iterations towards the consistent-mass projection of particle momentum to grid
  // velocity (0: the classic lumped projection v = p / m).
  int projectionIterations = 0;
  // Mass-proportional damping c (1/s): the grid acceleration gets -c v_i, a force -c m_i v_i,
  // for dynamic relaxation to a quasi-static state (critical for a mode omega at c = 2 omega).
  double massDamping = 0.0;
  // F-bar volumetric-locking control (core/kernels/FbarAveraging.hpp).
  bool fbar = false;
};

template <class Shape, int Dim = 2>
class ExplicitStepper : public Integrator {
 public:
  ExplicitStepper(ParticleSet& particles, const GridDistribution& dist, const Materials& material,
                  GridConditions& conditions, const LoadSet& loads, const ExplicitOptions& options);

  void step(double t, double dt) override;
  std::string name() const override;

 private:
  using Exec = ExecutionSpace;
  using A = AccumColumns<Dim>;
  using K = KinColumns<Dim>;
  // Velocity (and acceleration when withForces) on owned nodes from the summed grid fields.
  void gridUpdate(double dt, bool withForces);
  void particleToGridMomentum();
  void particleToGridForces(double t, bool withMomentum);
  void stressFromGhostedVelocity(double dt, bool fromAccum);
  // The stress update from dt x the particles' gradient view (with F-bar when on).
  void updateParticleStresses(double dt);
  void correctProjection();
  // XPIC: v_p <- sum_i S_ip v*_i before the FLIP update (solvers/XpicExtrapolation.hpp).
  void extrapolateParticleVelocity();
  template <class F>
  void withFields(int stride, const F& f) const;

  ParticleSet& ps_;
  const GridDistribution& dist_;
  Materials mat_;
  GridConditions& conditions_;
  const LoadSet& loads_;
  ExplicitOptions opt_;
  // Velocity fields (one per body with multi-field contact): field f's particle sums sit
  // f * sumsStride_ columns after field 0's (with its contact geometry, volume gradient and
  // mass-weighted position, at geometryCol_), its kinematics f * kinStride_ (strides 0, no
  // geometry: one field).
  int fieldCount_ = 1, sumsStride_ = 0, kinStride_ = 0, geometryCol_ = -1;
  GridFields fields_;
  ProjectionCorrection<Shape, Dim> projection_;
  std::unique_ptr<XpicExtrapolation<Shape, Dim>> xpic_;
  std::unique_ptr<FbarAveraging<Dim>> fbar_;
  double massCutoff_ = 0.0;
};

}  // namespace impm
