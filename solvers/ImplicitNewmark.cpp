#include "solvers/ImplicitNewmark.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include <algorithm>
#include <chrono>
#include <iomanip>
#include <cmath>
#include <numeric>
#include <sstream>
#include <limits>
#include <map>

#include "core/PhaseTimer.hpp"
#include "core/kernels/GridToParticle.hpp"
#include "core/kernels/InternalForce.hpp"
#include "core/kernels/ParticleToGrid.hpp"
#include "core/kernels/Stiffness.hpp"

namespace impm {

namespace {
// Columns of the implicit grid multivectors in Dim dimensions; a vector field takes Dim
// consecutive columns, named by its first (X) one.
// The grid state: mass, v, a, F_ext and a flag per free component.
template <int Dim>
struct StateColumns {
  static constexpr int Mass = 0, VelX = 1, AccX = 1 + Dim, FextX = 1 + 2 * Dim, FreeX = 1 + 3 * Dim, Count = 1 + 4 * Dim;
};
// The displacement multivector: the step's displacement, the new acceleration and the grid's
// velocity increment dt/2 (a + a_new).
template <int Dim>
struct DisplacementColumns {
  static constexpr int UX = 0, AnewX = Dim, DvX = 2 * Dim, Count = 3 * Dim;
};
// The force multivectors: the force on the nodes (internal, plus external for the initial
// acceleration) and the consistent-mass product M_C u of the residual.
template <int Dim>
struct ForceColumns {
  static constexpr int ForceX = 0, MassProductX = Dim, Count = 2 * Dim;
};
}  // namespace

template <class Shape, int Dim>
ImplicitNewmark<Shape, Dim>::ImplicitNewmark(ParticleSet& particles, const GridDistribution& dist,
                                        const Materials& material, GridConditions& conditions,
                                        const LoadSet& loads, const ImplicitOptions& options)
    : ps_(particles), dist_(dist), mat_(material), conditions_(conditions), loads_(loads), opt_(options), projection_(dist) {
  solver_ = std::make_unique<NewtonSolver>(opt_.solverParams);
  stateOwned_ = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), StateColumns<Dim>::Count));
  stateGhosted_ = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), StateColumns<Dim>::Count));
  dispOwned_ = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), DisplacementColumns<Dim>::Count));
  dispGhosted_ = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), DisplacementColumns<Dim>::Count));
  // Columns 0-1: internal force; 2-3: M_C u (consistent mass).
  forceOwned_ = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), ForceColumns<Dim>::Count));
  forceGhosted_ = Teuchos::rcp(new MultiVector(dist.ghostedNodeMap(), ForceColumns<Dim>::Count));
  // (Linear MPM: every node a particle reaches is an unknown; see ImplicitOptions::massTolerance.)
  massCutoff_ = std::is_same<Shape, LinearMpm>::value ? 0.0 : opt_.massTolerance * heaviestParticleMass(ps_, *dist.comm());
  seedGimpStiffness_ = std::is_same<Shape, UniformGimp>::value && opt_.seedGimpStiffness;
  if (seedGimpStiffness_ && Dim == 3)
    throw std::invalid_argument("'Integrator/Implicit/GIMP Stiffness' = Integrated (the seed's overlap integrals) is 2D only; use Consistent in 3D");
  blockNodes_ = seedGimpStiffness_ ? 2 : Shape::max_nodes_1d;
  blockStride_ = std::is_same<Shape, QuadraticLagrange>::value ? 2 : 1;
  if (opt_.fixedParticles) {
    gridKinematics_ = Teuchos::rcp(new MultiVector(dist.ownedNodeMap(), 2 * Dim));
    if (ps_.u.extent(0) != size_t(ps_.count)) ps_.u = ps_.newVector("u");
  }
}

template <class Shape, int Dim>
ImplicitNewmark<Shape, Dim>::~ImplicitNewmark() = default;

namespace {
std::string describe(const Teuchos::ParameterList& p) {
  const std::string jac = p.get<std::string>("Jacobian");
  if (jac == "Assembled") return "Assembled Newton, linear solver " + p.get<std::string>("Assembled Linear Solver");
  return jac + " Newton, preconditioner " + p.get<std::string>("Preconditioner");
}
}  // namespace

template <class Shape, int Dim>
std::string ImplicitNewmark<Shape, Dim>::name() const {
  const std::string method = opt_.fixedParticles ? (Dim == 3 ? (Shape::max_nodes_1d == 3 ? "FE Hex27" : "FE Hex8")
                                                             : (Shape::max_nodes_1d == 3 ? "FE Q9" : "FE Q4"))
                                                  : Shape::name;
  std::string scheme = "Newmark";
  if (!opt_.newmark.averageAcceleration()) {
    std::ostringstream os;
    os << "Newmark beta " << opt_.newmark.beta << " gamma " << opt_.newmark.gamma;
    scheme = os.str();
  }
  return std::string("implicit ") + method + " " + scheme + " (" + describe(solver_->parameters()) + ")";
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::setUpStep(double t, double dt) {
  PhaseTimer phase("implicit step set-up (p2g)");
  dt_ = dt;
  conditions_.setStep(t, dt);
  const StructuredGrid& g = dist_.grid();
  // Particles to grid at t: mass, momentum, m a; particle forces at t + dt.
  stateGhosted_->putScalar(0.0);
  {
    auto grid = stateGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    particleToGridMassMomentum<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, grid, StateColumns<Dim>::Mass, StateColumns<Dim>::VelX, StateColumns<Dim>::AccX);
    loads_.template scatterParticleForces<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, grid, StateColumns<Dim>::FextX, t + dt);
  }
  stateOwned_->putScalar(0.0);
  stateOwned_->doExport(*stateGhosted_, *dist_.importer(), Tpetra::ADD);

  // Consistent initial acceleration: a(0) = M^-1 (F_ext(0) + F_int(0)) (F_int as force on nodes).
  // With Grid Acceleration = Equilibrium the lumped grid takes a(t) that way at every step.
  const bool initialAcceleration = firstStep_ && opt_.consistentInitialAcceleration;
  const bool accelerationFromForces = initialAcceleration || equilibriumAcceleration();
  if (accelerationFromForces) {
    forceGhosted_->putScalar(0.0);
    {
      auto f = forceGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
      accumulateInternalForce<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, ps_.stress, f, ForceColumns<Dim>::ForceX);
      loads_.template scatterParticleForces<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, f, ForceColumns<Dim>::ForceX, t);
    }
    forceOwned_->putScalar(0.0);
    forceOwned_->doExport(*forceGhosted_, *dist_.importer(), Tpetra::ADD);
    auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    loads_.template applyNodal<Exec>(f, ForceColumns<Dim>::ForceX, t);
  }
  firstStep_ = false;

  // Fixed particles (FE reference), lumped mass: the grid keeps its own v and a from the last
  // step (a projection from the Gauss points would smooth them by M_L^-1 M_C). With the
  // consistent mass the projection M_C v = sum_p m_p S_ip v_p is already exact.
  const bool gridCarriesState = opt_.fixedParticles && !opt_.consistentMass && !initialAcceleration;
  if (gridCarriesState) {
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto k = gridKinematics_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    Kokkos::parallel_for(
        "grid_state_from_last_step", Kokkos::RangePolicy<Exec>(0, s.extent(0)), KOKKOS_LAMBDA(int n) {
          const double m = s(n, StateColumns<Dim>::Mass);
          for (int d = 0; d < Dim; ++d) {
            s(n, StateColumns<Dim>::VelX + d) = m * k(n, d);
            s(n, StateColumns<Dim>::AccX + d) = m * k(n, Dim + d);
          }
        });
  } else if (!initialAcceleration && !opt_.consistentMass) {
    // (The consistent-mass residual works on the particle momentum sums themselves: it needs
    // no projection correction, and with one the particles were seen to leave the grid.)
    correctProjection();
  }
  {
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    loads_.template applyNodal<Exec>(s, StateColumns<Dim>::FextX, t + dt);
    auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    const double cutoff = massCutoff_;
    Kokkos::parallel_for(
        "implicit_grid_state", Kokkos::RangePolicy<Exec>(0, s.extent(0)), KOKKOS_LAMBDA(int n) {
          const double m = s(n, StateColumns<Dim>::Mass);
          const bool massive = m > cutoff;
          for (int d = 0; d < Dim; ++d) {
            s(n, StateColumns<Dim>::VelX + d) = massive ? s(n, StateColumns<Dim>::VelX + d) / m : 0.0;
            s(n, StateColumns<Dim>::AccX + d) = massive ? (accelerationFromForces ? f(n, ForceColumns<Dim>::ForceX + d) / m : s(n, StateColumns<Dim>::AccX + d) / m) : 0.0;
            s(n, StateColumns<Dim>::FreeX + d) = massive ? 1.0 : 0.0;
          }
        });
    // Grid conditions: their dofs start the step with the prescribed motion and are not unknowns.
    conditions_.template write<Exec>(s, StateColumns<Dim>::VelX, PrescribedField::StartVelocity);
    conditions_.template write<Exec>(s, StateColumns<Dim>::AccX, PrescribedField::StartAcceleration);
    conditions_.template write<Exec>(s, StateColumns<Dim>::FreeX, PrescribedField::Zero);
  }
  stateGhosted_->doImport(*stateOwned_, *dist_.importer(), Tpetra::INSERT);
  if (initialAcceleration && opt_.consistentMass) {
    // The particles start from the grid's consistent acceleration (their own Newmark update
    // needs a_p(0)).
    auto sgv = stateGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    interpolateToParticles<Exec, Shape, Dim>(g, dist_.ghostedIndexer(), ps_, sgv, StateColumns<Dim>::AccX, ps_.a, 1.0, false);
  }

  // Free dofs and the unknown map (gid = Dim node + component).
  PCurrent_ = false;
  auto s = stateOwned_->getLocalViewHost(Tpetra::Access::ReadOnly);
  const auto ownedMap = dist_.ownedNodeMap();
  std::vector<int> nodes, comps;
  const std::vector<GO> previousGids = freeGids_;
  freeGids_.clear();
  for (size_t n = 0; n < s.extent(0); ++n)
    for (int d = 0; d < Dim; ++d)
      if (s(n, StateColumns<Dim>::FreeX + d) > 0.5) {
        nodes.push_back((int)n);
        comps.push_back(d);
        freeGids_.push_back(Dim * ownedMap->getGlobalElement((LO)n) + d);
      }
  freeNode_ = Kokkos::View<int*, DeviceType>("free_node", nodes.size());
  freeComp_ = Kokkos::View<int*, DeviceType>("free_comp", comps.size());
  auto hn = Kokkos::create_mirror_view(freeNode_); auto hc = Kokkos::create_mirror_view(freeComp_);
  for (size_t k = 0; k < nodes.size(); ++k) { hn(k) = nodes[k]; hc(k) = comps[k]; }
  Kokkos::deep_copy(freeNode_, hn); Kokkos::deep_copy(freeComp_, hc);
  // Same free dofs on every rank: keep the map object (the solver and preconditioner key on it).
  const int changedHere = (unknownMap_.is_null() || previousGids != freeGids_) ? 1 : 0;
  int changed = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_MAX, changedHere, Teuchos::outArg(changed));
  if (changed) {
    const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
    unknownMap_ = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(freeGids_), 0, dist_.comm()));
    P_ = Teuchos::null;
    unknownCoords_ = Teuchos::null;
  }
}

// Node coordinates of the free dofs (gid = Dim node + component), for MueLu's near-null space.
template <class Shape, int Dim>
Teuchos::RCP<const MultiVector> ImplicitNewmark<Shape, Dim>::unknownCoordinates() const {
  if (unknownMap_.is_null()) return Teuchos::null;
  if (!unknownCoords_.is_null()) return unknownCoords_;
  const StructuredGrid& g = dist_.grid();
  auto coords = Teuchos::rcp(new MultiVector(unknownMap_, Dim));
  auto c = coords->getLocalViewHost(Tpetra::Access::OverwriteAll);
  const long long nz = g.nodesZ(), ny = g.nodesY();
  for (size_t k = 0; k < freeGids_.size(); ++k) {
    const long long node = freeGids_[k] / Dim;  // node id = (i (ny + 1) + j) nodesZ + l
    const long long l = node % nz, j = (node / nz) % ny, i = node / (nz * ny);
    c(k, 0) = g.nodeX((int)i);
    if (Dim > 1) c(k, 1) = g.nodeY((int)j);
    if (Dim > 2) c(k, Dim - 1) = g.nodeZ((int)l);
  }
  unknownCoords_ = coords;
  return unknownCoords_;
}

// The lumped projection v_i = sum m_p S_ip v_p / m_i smooths the grid state every step (by
// M_L^-1 M_C), so that the grid does not carry on exactly from the Newmark update of the last
// step. Jacobi iterations towards the consistent projection remove that to O((kh)^4).
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::correctProjection() {
  if (opt_.projectionIterations <= 0) return;
  projection_.apply(*stateOwned_, StateColumns<Dim>::Mass, StateColumns<Dim>::VelX, ps_, ps_.v, conditions_,
                    PrescribedField::StartVelocity, massCutoff_, opt_.projectionIterations);
  projection_.apply(*stateOwned_, StateColumns<Dim>::Mass, StateColumns<Dim>::AccX, ps_, ps_.a, conditions_,
                    PrescribedField::StartAcceleration, massCutoff_, opt_.projectionIterations);
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::scatterUnknowns(const Vector& u) {
  dispOwned_->putScalar(0.0);
  {
    auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto uv = u.getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto node = freeNode_; auto comp = freeComp_;
    Kokkos::parallel_for(
        "scatter_unknowns", Kokkos::RangePolicy<Exec>(0, node.extent(0)),
        KOKKOS_LAMBDA(int k) { d(node(k), DisplacementColumns<Dim>::UX + comp(k)) = uv(k, 0); });
    // The prescribed dofs move by their increment (they are not unknowns; zero is already there).
    if (!conditions_.isZero(PrescribedField::Increment))
      conditions_.template write<Exec>(d, DisplacementColumns<Dim>::UX, PrescribedField::Increment);
  }
  dispGhosted_->doImport(*dispOwned_, *dist_.importer(), Tpetra::INSERT);
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::residual(const Vector& u, Vector& R) {
  PhaseTimer phase("residual");
  scatterUnknowns(u);
  forceGhosted_->putScalar(0.0);
  {
    auto f = forceGhosted_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    // One pass per particle: grad u from the grid, the trial stress sigma_p + D sym(grad u), and
    // its internal force through the shared scatterInternalForce.
    {
      auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
      const LocalNodeIndexer ix = dist_.ghostedIndexer();
      auto vol = ps_.volume; auto sig = ps_.stress; auto matId = ps_.material;
      auto Fp = FixedParticleViews<Dim>(ps_).F;
      auto hist = ps_.history;
      const auto law = mat_.law();
      scatterToGrid<Exec, Shape, Dim>(
          "implicit_internal_force", dist_.grid(), ps_, f, KOKKOS_LAMBDA(int p, const ParticleStencil<Shape, Dim>& st, auto& out) {
            double G[Dim][Dim] = {};
            st.forEachNode(ix, [&](int n, double, const double* dw) {
              for (int i = 0; i < Dim; ++i)
                for (int j = 0; j < Dim; ++j) G[i][j] += d(n, DisplacementColumns<Dim>::UX + i) * dw[j];
            });
            double trial[StressLayout<Dim>::count];
            loadStress<Dim>(sig, p, trial);
            const int m = matId(p);
            if (law.finiteStrain(m)) {
              // The trial state: F = (I + G) F_n and the law's stress there; a path-dependent law
              // works on a copy of the history (the trial state is discarded).
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
              scatterInternalForceDeformed(st, ix, vol(p), trial, G, out, ForceColumns<Dim>::ForceX);
            } else {
              // Small strain (the linear law): sigma_n + D sym(G) on the step's initial domain.
              law.linearElastic(m).template stress<Dim>(trial, G, trial);
              scatterInternalForce(st, ix, vol(p), trial, out, ForceColumns<Dim>::ForceX);
            }
          });
    }
    if (opt_.consistentMass) {
      // M_C u = sum_p m_p S_ip u_p with u_p = sum_j S_jp u_j (consistent-mass residual only).
      auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
      particleToGridMassProduct<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DisplacementColumns<Dim>::UX, f, ForceColumns<Dim>::MassProductX);
    }
  }
  forceOwned_->putScalar(0.0);
  forceOwned_->doExport(*forceGhosted_, *dist_.importer(), Tpetra::ADD);
  auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const bool consistent = opt_.consistentMass;
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto uv = u.getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto r = R.getLocalViewDevice(Tpetra::Access::OverwriteAll);
  auto node = freeNode_; auto comp = freeComp_;
  const double c1 = opt_.newmark.c1(dt_), c2 = opt_.newmark.c2(dt_), c3 = opt_.newmark.c3();
  Kokkos::parallel_for(
      "implicit_residual", Kokkos::RangePolicy<Exec>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
        const int n = node(k), d = comp(k);
        const double m = s(n, StateColumns<Dim>::Mass);
        // f holds the internal force acting on the node (-int B^T sigma).
        // m v and m a are the particle-to-grid momentum and m a sums (lumped normalisation undone).
        const double inertia = consistent ? c1 * f(n, ForceColumns<Dim>::MassProductX + d) : m * c1 * uv(k, 0);
        r(k, 0) = inertia - m * (c2 * s(n, StateColumns<Dim>::VelX + d) + c3 * s(n, StateColumns<Dim>::AccX + d)) - f(n, ForceColumns<Dim>::ForceX + d) - s(n, StateColumns<Dim>::FextX + d);
      });
  if (!conditions_.empty()) {  // forceOwned_ now holds the forces at u (recordReactions reuses them)
    if (lastResidualPoint_.is_null() || lastResidualPoint_->getMap().get() != unknownMap_.get())
      lastResidualPoint_ = Teuchos::rcp(new Vector(unknownMap_, false));
    Tpetra::deep_copy(*lastResidualPoint_, u);
  }
}

// The reaction of each grid condition: the residual of the converged step at its dofs, the
// force the condition applies so that its nodes move as prescribed. The forces at u are those of
// the last residual when it was evaluated at u (NOX's convergence check normally is), else one
// more residual evaluation provides them.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::recordReactions(const Vector& u) {
  if (conditions_.empty()) return;
  int sameHere = 0;
  if (!lastResidualPoint_.is_null() && lastResidualPoint_->getMap().get() == u.getMap().get()) {
    auto a = lastResidualPoint_->getLocalViewHost(Tpetra::Access::ReadOnly);
    auto b = u.getLocalViewHost(Tpetra::Access::ReadOnly);
    sameHere = 1;
    for (size_t k = 0; k < a.extent(0) && sameHere; ++k) sameHere = a(k, 0) == b(k, 0);
  }
  int same = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_MIN, sameHere, Teuchos::outArg(same));
  if (!same) {
    Vector R(unknownMap_, false);
    residual(u, R);
  }
  auto f = forceOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  auto disp = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
  const bool consistent = opt_.consistentMass;
  const double c1 = opt_.newmark.c1(dt_), c2 = opt_.newmark.c2(dt_), c3 = opt_.newmark.c3();
  using SC = StateColumns<Dim>;
  using FC = ForceColumns<Dim>;
  conditions_.template recordReaction<Exec>(KOKKOS_LAMBDA(int n, int d) {
    const double m = s(n, SC::Mass);
    const double inertia = consistent ? c1 * f(n, FC::MassProductX + d) : m * c1 * disp(n, DisplacementColumns<Dim>::UX + d);
    return inertia - m * (c2 * s(n, SC::VelX + d) + c3 * s(n, SC::AccX + d)) - f(n, FC::ForceX + d) - s(n, SC::FextX + d);
  });
}

// || |P| |u| + |m (4/dt v + a)| + |F_ext| ||_2 over the free dofs (ResidualModel::residualMagnitude):
// with the step's assembled P when there is one (the stiffness carries the large terms of a stiff
// body's internal force), else with its lumped-mass part 4/dt^2 m alone.
template <class Shape, int Dim>
double ImplicitNewmark<Shape, Dim>::residualMagnitude(const Vector& u) {
  Vector absU(unknownMap_, false), sum(unknownMap_, false);
  absU.abs(u);
  const bool withP = !P_.is_null() && P_->getRowMap().get() == unknownMap_.get();
  if (withP) {
    // Every assembly bumps jacobianVersion_ (a new P_ object too): |P| is taken once per P.
    if (absP_.is_null() || absPVersion_ != jacobianVersion_) {
      absP_ = Teuchos::rcp(new CrsMatrix(*P_, Teuchos::Copy));
      auto values = absP_->getLocalMatrixDevice().values;
      Kokkos::parallel_for(
          "abs_P", Kokkos::RangePolicy<Exec>(0, values.extent(0)), KOKKOS_LAMBDA(int k) { values(k) = std::fabs(values(k)); });
      absPVersion_ = jacobianVersion_;
    }
    absP_->apply(absU, sum);
  } else {
    sum.putScalar(0.0);
  }
  {
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto au = absU.getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto out = sum.getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto node = freeNode_; auto comp = freeComp_;
    const double c1 = opt_.newmark.c1(dt_), c2 = opt_.newmark.c2(dt_), c3 = opt_.newmark.c3();
    Kokkos::parallel_for(
        "residual_magnitude", Kokkos::RangePolicy<Exec>(0, node.extent(0)), KOKKOS_LAMBDA(int k) {
          const int n = node(k), d = comp(k);
          const double m = s(n, StateColumns<Dim>::Mass);
          const double start = std::fabs(m * (c2 * s(n, StateColumns<Dim>::VelX + d) + c3 * s(n, StateColumns<Dim>::AccX + d))) +
                               std::fabs(s(n, StateColumns<Dim>::FextX + d));
          out(k, 0) = (withP ? out(k, 0) : m * c1 * au(k, 0)) + start;
        });
  }
  return sum.norm2();
}

template <class Shape, int Dim>
Teuchos::RCP<const CrsMatrix> ImplicitNewmark<Shape, Dim>::jacobianMatrix(const Vector& u) {
  PhaseTimer phase("stiffness assembly");
  // P = 4/dt^2 M + K, K over particle-cell pairs (exact over overlaps for GIMP). Small strain:
  // P does not depend on u, so it is assembled once per step. Assembled Newton on finite strain:
  // K is the tangent at the trial u (material and geometric), assembled at every Newton iterate.
  const bool jacobianFree = solver_->parameters().get<std::string>("Jacobian") == "Jacobian-Free";
  const bool trialTangent =
      mat_.anyFiniteStrain() && !seedGimpStiffness_ && (!jacobianFree || opt_.preconditionerEveryNewton);
  if (PCurrent_ && !trialTangent) return P_;
  if (!restoredP_.empty()) takeRestoredP();
  if (trialTangent) {
    // grad u of the trial displacement at each particle, for the stiffness kernel.
    scatterUnknowns(u);
    auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DisplacementColumns<Dim>::UX);
  }
  // Jacobian-free: P only builds the preconditioner, so it is reassembled (and refactored) every
  // Preconditioner Refresh Interval steps, or at the step after one whose GMRES iterations per
  // Newton exceeded the threshold, or at every Newton iterate (finite strain, on request); the
  // residual carries the current physics.
  const int interval = std::max(1, opt_.preconditionerRefreshInterval);
  if (jacobianFree && !trialTangent && !P_.is_null() && !refreshRequested_ && ++stepsSinceAssembly_ < interval) {
    PCurrent_ = true;
    return P_;
  }
  stepsSinceAssembly_ = 0;
  refreshRequested_ = false;
  const StructuredGrid& g = dist_.grid();
  const LocalNodeIndexer& gix = dist_.ghostedIndexer();
  const auto ghostMap = dist_.ghostedNodeMap();
  auto sg = stateGhosted_->getLocalViewHost(Tpetra::Access::ReadOnly);
  // Blocks of the ghost region (cells, Q9 elements or GIMP 3 x 3 (x 3) node patches), numbered
  // locally x slowest; each couples the free dofs of its nodes. Along each direction the blocks
  // start at multiples of the stride and lie inside the rank's ghosted box of nodes.
  int bn[3] = {1, 1, 1};
  for (int d = 0; d < Dim; ++d) bn[d] = std::min(blockNodes_, g.cells(d) + 1);
  const int blockNodeCount = bn[0] * bn[1] * bn[2];
  const int stride = blockStride_, nd = Dim * blockNodeCount;
  int firstB[3] = {0, 0, 0}, blockCount[3] = {1, 1, 1};
  for (int d = 0; d < Dim; ++d) {
    firstB[d] = ((gix.lo[d] + stride - 1) / stride) * stride;
    blockCount[d] = gix.end(d) - bn[d] >= firstB[d] ? (gix.end(d) - bn[d] - firstB[d]) / stride + 1 : 0;
  }
  const int blockCols = blockCount[0], blockRows = blockCount[1], blockLayers = blockCount[2];
  auto blockIndex = [&](int bi, int bj, int bk) {
    return (size_t((bi - firstB[0]) / stride) * blockRows + (bj - firstB[1]) / stride) * blockLayers +
           (bk - firstB[2]) / stride;
  };
  // Visits every (local block, r, c) coupling of two free dofs of a block.
  auto forEachBlockCoupling = [&](auto&& visit) {
    std::vector<GO> gid(nd);
    std::vector<char> freeDof(nd);
    for (int ci = 0; ci < blockCols; ++ci)
      for (int cj = 0; cj < blockRows; ++cj)
        for (int ck = 0; ck < blockLayers; ++ck) {
          const int bi = firstB[0] + ci * stride, bj = firstB[1] + cj * stride, bk = firstB[2] + ck * stride;
          for (int a = 0; a < blockNodeCount; ++a) {
            const int ln = gix(bi + a % bn[0], bj + (a / bn[0]) % bn[1], bk + a / (bn[0] * bn[1]));
            for (int d = 0; d < Dim; ++d) {
              gid[Dim * a + d] = Dim * ghostMap->getGlobalElement(ln) + d;
              freeDof[Dim * a + d] = sg(ln, StateColumns<Dim>::FreeX + d) > 0.5;
            }
          }
          for (int r = 0; r < nd; ++r)
            for (int c = 0; c < nd; ++c)
              if (freeDof[r] && freeDof[c]) visit(blockIndex(bi, bj, bk), r * nd + c, gid[r], gid[c]);
        }
  };

  // The graph depends only on the free dofs a rank sees: every block of the ghost region couples
  // its free dofs (blocks without particles just hold zeros). Rebuilt when that set changes.
  std::vector<GO> key;
  for (size_t n = 0; n < sg.extent(0); ++n)
    for (int d = 0; d < Dim; ++d)
      if (sg(n, StateColumns<Dim>::FreeX + d) > 0.5) key.push_back(Dim * ghostMap->getGlobalElement((LO)n) + d);
  const int sameHere = (!P_.is_null() && key == patternKey_) ? 1 : 0;
  int same = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_MIN, sameHere, Teuchos::outArg(same));
  if (!same) {
    std::map<GO, std::vector<GO>> rows;
    forEachBlockCoupling([&](size_t, int, GO row, GO col) { rows[row].push_back(col); });
    std::vector<GO> rowGids;
    size_t maxPerRow = 1;
    for (auto& [r, cols] : rows) {
      std::sort(cols.begin(), cols.end());
      cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
      rowGids.push_back(r);
      maxPerRow = std::max(maxPerRow, cols.size());
    }
    const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
    auto overlapMap = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(rowGids), 0, dist_.comm()));
    auto overlapGraph = Teuchos::rcp(new Tpetra::CrsGraph<LO, GO, Node>(overlapMap, maxPerRow));
    for (const auto& [r, cols] : rows) overlapGraph->insertGlobalIndices(r, Teuchos::ArrayView<const GO>(cols));
    overlapGraph->fillComplete(unknownMap_, unknownMap_);
    overlapP_ = Teuchos::rcp(new CrsMatrix(overlapGraph));
    overlapP_->fillComplete(unknownMap_, unknownMap_);
    pExporter_ = Teuchos::rcp(new Export(overlapMap, unknownMap_));
    auto firstP = Teuchos::rcp(new CrsMatrix(unknownMap_, 2 * maxPerRow));
    firstP->doExport(*overlapP_, *pExporter_, Tpetra::ADD);
    firstP->fillComplete(unknownMap_, unknownMap_);
    P_ = Teuchos::rcp(new CrsMatrix(firstP->getCrsGraph()));  // static graph: values only from now on

    // Offsets in the overlap matrix's values: per local block and (r, c), and per mass diagonal.
    auto lcl = overlapP_->getLocalMatrixDevice();
    auto rowPtr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), lcl.graph.row_map);
    auto entries = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), lcl.graph.entries);
    const auto rowMap = overlapP_->getRowMap();
    const auto colMap = overlapP_->getColMap();
    auto offsetOf = [&](GO row, GO col) {
      const LO lr = rowMap->getLocalElement(row), lc = colMap->getLocalElement(col);
      size_t off = rowPtr(lr);
      while (off < rowPtr(lr + 1) && entries(off) != lc) ++off;
      return off;
    };
    const size_t none = std::numeric_limits<size_t>::max();
    blockOffsets_.assign(size_t(blockCols) * blockRows * blockLayers * nd * nd, none);
    forEachBlockCoupling(
        [&](size_t block, int rc, GO row, GO col) { blockOffsets_[block * nd * nd + rc] = offsetOf(row, col); });
    diagOffsets_.clear();
    for (GO gidFree : freeGids_) diagOffsets_.push_back(offsetOf(gidFree, gidFree));
    patternKey_ = std::move(key);
  }

  // Values: block stiffness into the block offsets, the lumped mass into the diagonal, then one
  // Export sums the ranks' overlapping rows.
  // The consistent mass goes into the stencil blocks, so that P is the Jacobian of the
  // consistent-mass residual; the seed's GIMP blocks (cells) cannot hold a GIMP stencil's
  // mass coupling, so P keeps the lumped mass there.
  const double massFactor = opt_.newmark.c1(dt_);
  const bool consistentMassInP = opt_.consistentMass && !seedGimpStiffness_;
  BlockMatrices Kb;
  if constexpr (Dim == 2) {
    if (seedGimpStiffness_) {
      const ParticleCellPairs pairs = buildParticleCellPairs<Exec>(g, ps_, false);
      Kb = overlapStiffness<Exec>(g, pairs, ps_, mat_.law());
    }
  }
  if (!seedGimpStiffness_) {
    Kb = stencilStiffness<Exec, Shape, Dim>(g, ps_, mat_.law(), consistentMassInP ? massFactor : 0.0, trialTangent);
  }
  auto O = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kb.origin);
  auto K = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kb.K);
  auto so = stateOwned_->getLocalViewHost(Tpetra::Access::ReadOnly);
  auto hn = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), freeNode_);
  const size_t none = std::numeric_limits<size_t>::max();
  overlapP_->resumeFill();
  {
    auto values = overlapP_->getLocalMatrixDevice().values;
    Kokkos::deep_copy(values, 0.0);
    for (int k = 0; k < Kb.count; ++k) {
      const size_t* off = &blockOffsets_[blockIndex(O(k, 0), O(k, 1), Dim == 3 ? O(k, Dim - 1) : 0) * nd * nd];
      for (int rc = 0; rc < nd * nd; ++rc)
        if (off[rc] != none) values(off[rc]) += K(k, rc / nd, rc % nd);
    }
    if (!consistentMassInP)
      for (size_t k = 0; k < freeGids_.size(); ++k) values(diagOffsets_[k]) += massFactor * so(hn(k), StateColumns<Dim>::Mass);
  }
  overlapP_->fillComplete(unknownMap_, unknownMap_);
  P_->resumeFill();
  P_->setAllToScalar(0.0);
  P_->doExport(*overlapP_, *pExporter_, Tpetra::ADD);
  P_->fillComplete(unknownMap_, unknownMap_);
  ++jacobianVersion_;
  if (jacobianFree || !same || jacobianVersion_ % interval == 0) ++preconditionerVersion_;
  PCurrent_ = true;
  return P_;
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::finishStep(const Vector& u) {
  PhaseTimer phase("g2p and stress update");
  recordReactions(u);
  scatterUnknowns(u);
  // Grid acceleration at t + dt on the free dofs (zero elsewhere).
  {
    auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadWrite);
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    const double c1 = opt_.newmark.c1(dt_), c2 = opt_.newmark.c2(dt_), c3 = opt_.newmark.c3();
    const double dt = dt_, gamma = opt_.newmark.gamma;
    Kokkos::parallel_for(
        "implicit_grid_acceleration", Kokkos::RangePolicy<Exec>(0, d.extent(0)), KOKKOS_LAMBDA(int n) {
          for (int c = 0; c < Dim; ++c) {
            const bool free = s(n, StateColumns<Dim>::FreeX + c) > 0.5;
            const double a = s(n, StateColumns<Dim>::AccX + c);
            const double aNew = free ? c1 * d(n, DisplacementColumns<Dim>::UX + c) - c2 * s(n, StateColumns<Dim>::VelX + c) - c3 * a : 0.0;
            d(n, DisplacementColumns<Dim>::AnewX + c) = aNew;
            d(n, DisplacementColumns<Dim>::DvX + c) = free ? dt * ((1 - gamma) * a + gamma * aNew) : 0.0;
          }
        });
    conditions_.template write<Exec>(d, DisplacementColumns<Dim>::AnewX, PrescribedField::Acceleration);
    conditions_.template write<Exec>(d, DisplacementColumns<Dim>::DvX, PrescribedField::VelocityChange);
  }
  if (opt_.fixedParticles) {  // the grid's own Newmark update, kept for the next step
    auto d = dispOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto s = stateOwned_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto k = gridKinematics_->getLocalViewDevice(Tpetra::Access::OverwriteAll);
    const double dt = dt_, gamma = opt_.newmark.gamma;
    Kokkos::parallel_for(
        "grid_newmark_update", Kokkos::RangePolicy<Exec>(0, d.extent(0)), KOKKOS_LAMBDA(int n) {
          for (int c = 0; c < Dim; ++c) {
            const double aNew = d(n, DisplacementColumns<Dim>::AnewX + c);
            k(n, c) = s(n, StateColumns<Dim>::FreeX + c) > 0.5 ? s(n, StateColumns<Dim>::VelX + c) + dt * ((1 - gamma) * s(n, StateColumns<Dim>::AccX + c) + gamma * aNew) : 0.0;
            k(n, Dim + c) = aNew;
          }
        });
    conditions_.template write<Exec>(k, 0, PrescribedField::EndVelocity);
    conditions_.template write<Exec>(k, Dim, PrescribedField::Acceleration);
  }
  dispGhosted_->doImport(*dispOwned_, *dist_.importer(), Tpetra::INSERT);
  // Stress from the converged displacement (weights at x_p(t)), then the particle update.
  {
    auto d = dispGhosted_->getLocalViewDevice(Tpetra::Access::ReadOnly);
    gridGradientAtParticles<Exec, Shape, Dim>(dist_.grid(), dist_.ghostedIndexer(), ps_, d, DisplacementColumns<Dim>::UX);
    updateStress<Exec, Dim>(ps_, mat_.law(), 1.0, /*updateVolume=*/!opt_.fixedParticles,
                            ConvectsDomain<Shape>::value ? DomainConvection(dist_.grid()) : DomainConvection());
    const StructuredGrid g = dist_.grid();
    const LocalNodeIndexer ix = dist_.ghostedIndexer();
    auto x = ps_.x; auto hs = ps_.halfSize; auto v = ps_.v; auto a = ps_.a; auto up = ps_.u;
    const auto deformation = DomainDeformation<Shape, Dim>::of(ps_);
    const double dt = dt_;
    const bool consistent = opt_.consistentMass, fixed = opt_.fixedParticles;
    const bool gridIncrement = equilibriumAcceleration();
    const double c1 = opt_.newmark.c1(dt), c2 = opt_.newmark.c2(dt), c3 = opt_.newmark.c3(), gamma = opt_.newmark.gamma;
    Kokkos::parallel_for(
        "implicit_g2p", Kokkos::RangePolicy<Exec>(0, ps_.count), KOKKOS_LAMBDA(int p) {
          const ParticleStencil<Shape, Dim> stn(g, x, hs, deformation, p);
          using DC = DisplacementColumns<Dim>;
          double u[Dim] = {}, an[Dim] = {}, dv[Dim] = {};
          stn.forEachNode(ix, [&](int n, double w, const double*) {
            for (int c = 0; c < Dim; ++c) {
              u[c] += w * d(n, DC::UX + c);
              an[c] += w * d(n, DC::AnewX + c);
              dv[c] += w * d(n, DC::DvX + c);
            }
          });
          for (int c = 0; c < Dim; ++c) {
            if (consistent) an[c] = c1 * u[c] - c2 * v(p, c) - c3 * a(p, c);  // the particle's own Newmark update
            if (fixed) up(p, c) += u[c];  // Gauss points stay; their displacement is kept apart
            else x(p, c) += u[c];
            if (gridIncrement) v(p, c) += dv[c];  // the grid's own trapezoidal increment (FLIP)
            else v(p, c) += dt * ((1 - gamma) * a(p, c) + gamma * an[c]);
            a(p, c) = an[c];
          }
        });
  }
}

template <class Shape, int Dim>
bool ImplicitNewmark<Shape, Dim>::solveStep(double t, double dt) {
  using clock = std::chrono::steady_clock;
  auto t0 = clock::now();
  setUpStep(t, dt);
  Vector u(unknownMap_, true);
  auto t1 = clock::now();
  const NewtonResult result = [&] {
    PhaseTimer phase("Newton solve (NOX)");
    return solver_->solve(*this, u);
  }();
  auto t2 = clock::now();
  secondsSetUp_ += std::chrono::duration<double>(t1 - t0).count();
  secondsSolve_ += std::chrono::duration<double>(t2 - t1).count();
  secondsSolverSetUp_ += result.setupSeconds;
  residualEvaluations_ += result.residualEvaluations;
  if (!result.converged) {
    lastFailure_ = result.reason;
    return false;
  }
  finishStep(u);
  secondsFinish_ += std::chrono::duration<double>(clock::now() - t2).count();
  newtonPerStep_.push_back(result.newtonIterations);
  if (opt_.preconditionerRefreshKrylov > 0 && !result.krylovIterations.empty()) {
    const double mean = std::accumulate(result.krylovIterations.begin(), result.krylovIterations.end(), 0.0) /
                        result.krylovIterations.size();
    if (mean > opt_.preconditionerRefreshKrylov) refreshRequested_ = true;
  }
  if (result.newtonIterations > hardestStepIterations_) {
    hardestStepIterations_ = result.newtonIterations;
    hardestStepNorms_ = result.residualNorms;
  }
  krylovPerNewton_.insert(krylovPerNewton_.end(), result.krylovIterations.begin(), result.krylovIterations.end());
  return true;
}

template <class Shape, int Dim>
bool ImplicitNewmark<Shape, Dim>::trySteps(double t, double dt, int depth) {
  if (solveStep(t, dt)) return true;
  if (depth >= opt_.maxStepHalvings) return false;
  ++halvings_;
  return trySteps(t, 0.5 * dt, depth + 1) && trySteps(t + 0.5 * dt, 0.5 * dt, depth + 1);
}

// Uintah ImpMPM's policy on the Newton count n of the last sub-step: n > 12 -> h *= 0.6,
// n < 4 -> h *= 2 (at most the deck's dt), failure -> h /= 2 and retry. (Uintah also restarts a
// step above 25 iterations; here NOX's own iteration limit fails it.) The sub-steps end exactly
// on the deck's step, so that the outputs keep their times.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::stepAdaptive(double t, double dt) {
  const double hMin = opt_.minimumTimeStep > 0 ? opt_.minimumTimeStep : dt / std::pow(2.0, opt_.maxStepHalvings);
  if (subStep_ <= 0) subStep_ = dt;
  const double tEnd = t + dt;
  double tc = t;
  while (tc < tEnd - 1e-12 * dt) {
    const double h = std::min(subStep_, tEnd - tc);
    if (!solveStep(tc, h)) {
      ++rejectedSubSteps_;
      ++halvings_;
      if (0.5 * h < hMin * (1 - 1e-12)) {
        std::ostringstream msg;
        msg << "Newton did not converge in the sub-step from t = " << tc << " s (dt = " << h
            << " s), and half of it is below the smallest sub-step " << hMin
            << " s ('Integrator/Implicit/Minimum Time Step' or Time Step / 2^Maximum Step Halvings); the last attempt "
            << lastFailure_;
        throw NewtonNotConverged(msg.str());
      }
      subStep_ = 0.5 * h;
      continue;
    }
    ++subSteps_;
    smallestSubStep_ = smallestSubStep_ > 0 ? std::min(smallestSubStep_, h) : h;
    largestSubStep_ = std::max(largestSubStep_, h);
    tc += h;
    const int n = newtonPerStep_.back();
    // (A sub-step cut short by the end of the deck step does not shrink the carried size.)
    if (n > 12) subStep_ = 0.6 * h;
    else if (n < 4) subStep_ = std::min(2.0 * std::max(h, subStep_), dt);
  }
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::step(double t, double dt) {
  if (opt_.adaptiveTimeStep) {
    stepAdaptive(t, dt);
    return;
  }
  if (!trySteps(t, dt, 0)) {
    std::ostringstream msg;
    msg << "Newton did not converge in the step from t = " << t << " s (dt = " << dt << " s), even with dt halved "
        << opt_.maxStepHalvings << " times; the last attempt " << lastFailure_;
    throw NewtonNotConverged(msg.str());
  }
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::addStatistics(Teuchos::ParameterList& summary) const {
  Teuchos::ParameterList& s = summary.sublist("Solver");
  const auto& n = newtonPerStep_;
  const auto& k = krylovPerNewton_;
  s.set("Newton Iterations Mean", n.empty() ? 0.0 : std::accumulate(n.begin(), n.end(), 0.0) / n.size());
  s.set("Newton Iterations Max", n.empty() ? 0 : *std::max_element(n.begin(), n.end()));
  s.set("Krylov Iterations Per Newton Mean", k.empty() ? 0.0 : std::accumulate(k.begin(), k.end(), 0.0) / k.size());
  s.set("Krylov Iterations Per Newton Max", k.empty() ? 0 : *std::max_element(k.begin(), k.end()));
  s.set("Step Halvings", halvings_);
  s.set("Stiffness Assemblies", (int)jacobianVersion_);
  {
    // ||R||_2 at each Newton iterate of the step that took the most iterations: the convergence
    // rate (quadratic for Assembled Newton with the exact tangent; linear-ish for JFNK's inexact solves).
    std::ostringstream norms;
    norms << std::setprecision(3);
    for (size_t k = 0; k < hardestStepNorms_.size(); ++k) norms << (k ? " " : "") << hardestStepNorms_[k];
    s.set("Residual Norms Of Hardest Step", norms.str());
  }
  if (opt_.adaptiveTimeStep) {
    Teuchos::ParameterList& a = s.sublist("Adaptive Time Step");
    a.set("Sub-Steps", (int)subSteps_);
    a.set("Rejected Sub-Steps", (int)rejectedSubSteps_);
    a.set("Smallest Sub-Step", smallestSubStep_);
    a.set("Largest Sub-Step", largestSubStep_);
  }
  s.set("Residual Evaluations", (int)residualEvaluations_);
  s.set("Seconds Step Set-Up", secondsSetUp_);
  s.set("Seconds Newton Solve", secondsSolve_);
  s.set("Seconds NOX Set-Up", secondsSolverSetUp_);
  s.set("Seconds Particle Update", secondsFinish_);
  s.set("Configuration", describe(solver_->parameters()));
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::saveState(NamedArrays& state) const {
  state["implicit scalars"] = {double(firstStep_), subStep_, double(stepsSinceAssembly_), double(refreshRequested_),
                               double(jacobianVersion_), double(preconditionerVersion_), double(halvings_),
                               double(hardestStepIterations_), smallestSubStep_, largestSubStep_, double(subSteps_),
                               double(rejectedSubSteps_), double(residualEvaluations_), secondsSetUp_, secondsSolve_,
                               secondsSolverSetUp_, secondsFinish_};
  state["implicit newton per step"].assign(newtonPerStep_.begin(), newtonPerStep_.end());
  state["implicit krylov per newton"].assign(krylovPerNewton_.begin(), krylovPerNewton_.end());
  state["implicit hardest step norms"] = hardestStepNorms_;
  // A Jacobian-free run reuses P (and its preconditioner) for later steps: kept, per rank.
  const bool jacobianFree = solver_->parameters().get<std::string>("Jacobian") == "Jacobian-Free";
  state["implicit ranks"] = {double(dist_.comm()->getSize())};
  if (jacobianFree && !P_.is_null()) {
    auto& rows = state["node implicit P"];
    const auto rowMap = P_->getRowMap(), colMap = P_->getColMap();
    typename CrsMatrix::local_inds_host_view_type cols;
    typename CrsMatrix::values_host_view_type values;
    for (LO r = 0; r < (LO)P_->getNodeNumRows(); ++r) {
      P_->getLocalRowView(r, cols, values);
      rows.push_back(double(rowMap->getGlobalElement(r)));
      rows.push_back(double(cols.extent(0)));
      for (size_t k = 0; k < cols.extent(0); ++k) {
        rows.push_back(double(colMap->getGlobalElement(cols(k))));
        rows.push_back(values(k));
      }
    }
  }
  if (opt_.fixedParticles) {
    // The grid's own v and a (owned nodes) with their global ids: per rank.
    auto k = gridKinematics_->getLocalViewHost(Tpetra::Access::ReadOnly);
    const auto map = dist_.ownedNodeMap();
    auto& gids = state["node implicit grid kinematics gids"];
    auto& values = state["node implicit grid kinematics"];
    for (size_t n = 0; n < k.extent(0); ++n) {
      gids.push_back(double(map->getGlobalElement((LO)n)));
      for (int c = 0; c < 2 * Dim; ++c) values.push_back(k(n, c));
    }
  }
}

template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::restoreState(const NamedArrays& state) {
  const std::vector<double>& s = state.at("implicit scalars");
  firstStep_ = s.at(0) != 0;
  subStep_ = s.at(1);
  stepsSinceAssembly_ = int(s.at(2));
  refreshRequested_ = s.at(3) != 0;
  jacobianVersion_ = long(s.at(4));
  preconditionerVersion_ = long(s.at(5));
  halvings_ = int(s.at(6));
  hardestStepIterations_ = int(s.at(7));
  smallestSubStep_ = s.at(8);
  largestSubStep_ = s.at(9);
  subSteps_ = (long long)s.at(10);
  rejectedSubSteps_ = (long long)s.at(11);
  residualEvaluations_ = long(s.at(12));
  secondsSetUp_ = s.at(13); secondsSolve_ = s.at(14); secondsSolverSetUp_ = s.at(15); secondsFinish_ = s.at(16);
  const auto& newton = state.at("implicit newton per step");
  newtonPerStep_.assign(newton.begin(), newton.end());
  const auto& krylov = state.at("implicit krylov per newton");
  krylovPerNewton_.assign(krylov.begin(), krylov.end());
  hardestStepNorms_ = state.at("implicit hardest step norms");
  const auto ranks = state.find("implicit ranks"), P = state.find("node implicit P");
  if (ranks != state.end() && P != state.end() && int(ranks->second.at(0)) == dist_.comm()->getSize())
    restoredP_ = P->second;
  if (opt_.fixedParticles) {
    const auto& gids = state.at("node implicit grid kinematics gids");
    const auto& values = state.at("node implicit grid kinematics");
    auto k = gridKinematics_->getLocalViewHost(Tpetra::Access::OverwriteAll);
    const auto map = dist_.ownedNodeMap();
    for (size_t i = 0; i < gids.size(); ++i) {
      const LO n = map->getLocalElement((GO)gids[i]);
      if (n == Teuchos::OrdinalTraits<LO>::invalid()) continue;
      for (int c = 0; c < 2 * Dim; ++c) k(n, c) = values[i * 2 * Dim + c];
    }
  }
}

// The checkpoint's P in place of an assembly, when its rows are this step's free dofs on every
// rank (the restart's first step has the checkpoint's particles, so they are); the graph is
// rebuilt at the next assembly (patternKey_ is empty), which refreshes the preconditioner.
template <class Shape, int Dim>
void ImplicitNewmark<Shape, Dim>::takeRestoredP() {
  std::vector<GO> rowGids;
  std::vector<std::vector<GO>> cols;
  std::vector<std::vector<double>> values;
  size_t longest = 1;
  for (size_t i = 0; i < restoredP_.size();) {
    rowGids.push_back(GO(restoredP_[i]));
    const size_t n = size_t(restoredP_[i + 1]);
    i += 2;
    cols.emplace_back(n);
    values.emplace_back(n);
    for (size_t k = 0; k < n; ++k, i += 2) {
      cols.back()[k] = GO(restoredP_[i]);
      values.back()[k] = restoredP_[i + 1];
    }
    longest = std::max(longest, n);
  }
  restoredP_.clear();
  const int sameHere = rowGids == freeGids_ ? 1 : 0;
  int same = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_MIN, sameHere, Teuchos::outArg(same));
  if (!same) return;
  P_ = Teuchos::rcp(new CrsMatrix(unknownMap_, longest));
  for (size_t r = 0; r < rowGids.size(); ++r)
    P_->insertGlobalValues(rowGids[r], Teuchos::ArrayView<const GO>(cols[r]), Teuchos::ArrayView<const double>(values[r]));
  P_->fillComplete(unknownMap_, unknownMap_);
}

template class ImplicitNewmark<LinearMpm, 2>;
template class ImplicitNewmark<UniformGimp, 2>;
template class ImplicitNewmark<QuadraticLagrange, 2>;
template class ImplicitNewmark<QuadraticBSpline, 2>;
template class ImplicitNewmark<LinearMpm, 3>;
template class ImplicitNewmark<UniformGimp, 3>;
template class ImplicitNewmark<ConvectedGimp, 2>;
template class ImplicitNewmark<ConvectedGimp, 3>;
template class ImplicitNewmark<Cpdi, 2>;
template class ImplicitNewmark<Cpdi, 3>;
template class ImplicitNewmark<QuadraticLagrange, 3>;
template class ImplicitNewmark<QuadraticBSpline, 3>;
template class ImplicitNewmark<CubicBSpline, 2>;
template class ImplicitNewmark<CubicBSpline, 3>;

}  // namespace impm
