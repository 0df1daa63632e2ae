// Simulation's after-step checks: the particles' divergence measure and reach (one pass over the
// particles), the CPDI domains, and the messages a failed run ends with (which particle went bad,
// what to change). Called by the run loop (Simulation.cpp).
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "core/Collective.hpp"
#include "core/CpdiDomainCheck.hpp"
#include "core/InputDeck.hpp"
#include "core/ShapeRegistry.hpp"

namespace impm {

namespace {

// Where a rank's particles may be. A rank maps its particles onto its ghosted box of nodes; after
// migration every particle is within the migration slack of its rank's box, so this catches
// particles that left the grid (or a ghost band too narrow). Between ranks, stencils reach one
// cell beyond the particle domain's cells. At the grid's own edges a particle's centre must stay
// inside: an MPM point beyond the last node line loses the partition of unity (its weights no
// longer sum to 1), and a GIMP domain is clipped to the grid, which keeps at least half of it
// (ParticleStencil).
struct ParticleReach {
  double lo[3], hi[3];
  bool lowEdge[3], highEdge[3];
  int dim;
  ParticleReach(const StructuredGrid& g, const LocalNodeIndexer& ix) : lo{}, hi{}, lowEdge{}, highEdge{}, dim(g.dim) {
    for (int d = 0; d < dim; ++d) {
      lowEdge[d] = ix.lo[d] == 0;
      highEdge[d] = ix.end(d) - 1 >= g.cells(d);
      lo[d] = lowEdge[d] ? g.origin(d) : g.origin(d) + (ix.lo[d] + 1) * g.spacing(d);
      hi[d] = highEdge[d] ? g.origin(d) + g.cells(d) * g.spacing(d) : g.origin(d) + (ix.end(d) - 2) * g.spacing(d);
    }
  }
  template <class Vec>
  KOKKOS_INLINE_FUNCTION bool contains(const Vec& x, const Vec& hs, int p) const {
    bool inside = true;
    for (int d = 0; d < dim; ++d) {
      const double a = lowEdge[d] ? x(p, d) : x(p, d) - hs(p, d);
      const double b = highEdge[d] ? x(p, d) : x(p, d) + hs(p, d);
      inside = inside && a >= lo[d] && b <= hi[d];
    }
    return inside;
  }
};

// The after-step checks in one pass over the particles (they were two, 15-17% of an explicit
// run's time): the divergence measure (largest |stress| / c11, +inf for a non-finite or inverted
// particle) and the number of particles out of the rank's reach.
struct AuditParticles {
  using value_type = Simulation::ParticleAudit;
  ParticleSet::Vec x, halfSize, v;
  ParticleSet::Stress stress;
  ParticleSet::Scal volume;
  ParticleSet::Ids material;
  MaterialLaw law;
  ParticleReach reach;
  int dim, ns;
  bool fixedVolumes;

  KOKKOS_INLINE_FUNCTION void init(value_type& a) const { a = value_type{}; }
  KOKKOS_INLINE_FUNCTION void join(value_type& a, const value_type& b) const {
    a.divergence = b.divergence > a.divergence ? b.divergence : a.divergence;
    a.outOfReach += b.outOfReach;
  }
  KOKKOS_INLINE_FUNCTION void join(volatile value_type& a, const volatile value_type& b) const {
    a.divergence = b.divergence > a.divergence ? b.divergence : a.divergence;
    a.outOfReach += b.outOfReach;
  }
  KOKKOS_INLINE_FUNCTION void operator()(int p, value_type& a) const {
    // Non-finite values count as infinitely large. Small strain: |stress| / c11 is the size of
    // the strain. Finite strain: stresses of order c11 are legitimate, and the end of the run is
    // an inverted particle (det F <= 0), which also counts as infinite.
    double sum = 0.0, largest = 0.0;
    for (int d = 0; d < dim; ++d) sum += v(p, d);
    for (int i = 0; i < ns; ++i) {
      sum += stress(p, i);
      largest = std::fmax(largest, std::fabs(stress(p, i)));
    }
    const int m = material(p);
    const bool finiteStrain = law.finiteStrain(m);
    // NaN and Inf propagate into the sum; NaN fails every comparison, so test finiteness.
    const bool bad = !std::isfinite(sum) || (finiteStrain && !fixedVolumes && !(volume(p) > 0.0));
    const double measure = bad ? HUGE_VAL : finiteStrain ? 0.0 : largest / law.table(m, MaterialLaw::C11);
    a.divergence = measure > a.divergence ? measure : a.divergence;
    if (!reach.contains(x, halfSize, p)) ++a.outOfReach;
  }
};

}  // namespace

Simulation::ParticleAudit Simulation::auditParticles() const {
  const AuditParticles audit{particles_.x,
                             particles_.halfSize,
                             particles_.v,
                             particles_.stress,
                             particles_.volume,
                             particles_.material,
                             materials_.law(),
                             ParticleReach(grid_, dist_->ghostedIndexer()),
                             particles_.dim,
                             particles_.stressCount(),
                             particles_.fixedPositions()};
  ParticleAudit local;
  Kokkos::parallel_reduce("particle_audit", Kokkos::RangePolicy<ExecutionSpace>(0, particles_.count), audit, local);
  ParticleAudit global;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, local.divergence, Teuchos::outArg(global.divergence));
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, local.outOfReach, Teuchos::outArg(global.outOfReach));
  return global;
}

void Simulation::checkParticlesInReach(double t) const { reportParticlesOutOfReach(auditParticles().outOfReach, t); }

void Simulation::reportParticlesOutOfReach(int total, double t) const {
  if (total > 0)
    throw ParticlesOutOfReach(
        std::to_string(total) +
            " particle(s) left the grid or the nodes their MPI rank maps at t = " + formatNumber(t) + " s",
        "use a larger grid");
  if (shapeInfo(shape_).cornerDomains) checkCpdiDomainsInReach(t);
}

// CPDI domains: at most 4 nodes per direction (CpdiStencil.hpp), inside the rank's node columns.
void Simulation::checkCpdiDomainsInReach(double t) const {
  const CpdiDomainReport r = grid_.dim == 3
                                 ? checkCpdiDomains<ExecutionSpace, 3>(grid_, dist_->ghostedIndexer(), particles_)
                                 : checkCpdiDomains<ExecutionSpace, 2>(grid_, dist_->ghostedIndexer(), particles_);
  int local[2] = {r.tooLarge, r.outOfReach}, total[2] = {0, 0};
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, 2, local, total);
  if (total[0] + total[1] == 0) return;
  const long long mine = r.firstId >= 0 ? r.firstId : std::numeric_limits<long long>::max();
  long long first = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, mine, Teuchos::outArg(first));
  throw ParticlesOutOfReach(
      "at t = " + formatNumber(t) + " s the CPDI domain of particle " + std::to_string(first) + " (global id) " +
          (total[0] > 0
               ? "spans more than 3 cells in a direction (its corners x_p +- F l0 e_i need more than 4 nodes; " +
                     std::to_string(total[0]) + " particle(s))"
               : "reaches beyond the node columns its MPI rank maps (" + std::to_string(total[1]) + " particle(s))"),
      total[0] > 0 ? "use more particles per cell or a coarser grid" : "use fewer MPI ranks");
}

std::string Simulation::describeBadParticle() const {
  // The lowest global id among the particles with a non-finite state or det F <= 0, over all
  // ranks; then its owner describes it.
  auto v = particles_.v;
  auto stress = particles_.stress;
  auto V = particles_.volume;
  auto id = particles_.id;
  const int dim = particles_.dim, ns = particles_.stressCount();
  const bool fixedVolumes = particles_.fixedPositions();
  long long localFirst = std::numeric_limits<long long>::max();
  Kokkos::parallel_reduce(
      "find_bad_particle", Kokkos::RangePolicy<ExecutionSpace>(0, particles_.count),
      KOKKOS_LAMBDA(int p, long long& first) {
        double sum = 0.0;
        for (int d = 0; d < dim; ++d) sum += v(p, d);
        for (int i = 0; i < ns; ++i) sum += stress(p, i);
        const bool bad = !std::isfinite(sum) || (!fixedVolumes && !(V(p) > 0.0));
        if (bad && id(p) < first) first = id(p);
      },
      Kokkos::Min<long long>(localFirst));
  long long first = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, localFirst, Teuchos::outArg(first));
  std::string here;
  if (first == localFirst && first != std::numeric_limits<long long>::max()) {
    auto hid = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.id);
    auto hx = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x);
    auto hx0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x0);
    auto hV = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.volume);
    auto hV0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.volume0);
    auto hb = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.body);
    for (int p = 0; p < particles_.count; ++p) {
      if (hid(p) != first) continue;
      std::ostringstream os;
      auto point = [&](const auto& view) {
        std::string s = "(";
        for (int d = 0; d < dim; ++d) s += (d ? ", " : "") + formatNumber(view(p, d));
        return s + ")";
      };
      os << "particle " << first << " of body '" << bodies_[hb(p)].name << "' (reference position " << point(hx0)
         << ", now at " << point(hx) << ")";
      if (!fixedVolumes && !(hV(p) > 0.0))
        os << " is inverted: det F = " << formatNumber(hV(p) / hV0(p));
      else
        os << " has a velocity or stress that is not finite";
      here = os.str();
    }
  }
  // The owner's description to every rank (rank of the owner is the one with a non-empty string).
  int length = (int)here.size(), longest = 0;
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, length, Teuchos::outArg(longest));
  std::vector<int> mine(longest + 1, 0), all(longest + 1, 0);
  std::copy(here.begin(), here.end(), mine.begin());
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, longest + 1, mine.data(), all.data());
  return std::string(all.begin(), std::find(all.begin(), all.end(), 0));
}

std::string Simulation::timeStepAdvice() const {
  const std::string step = "'Integrator/Time Step' = " + formatNumber(dt_) + " s";
  if (criticalStep_ <= 0) return "reduce " + step;
  if (dt_ > criticalStep_)
    return "reduce " + step + ": it is " + formatNumber(dt_ / criticalStep_) + " times the stable step " +
           formatNumber(criticalStep_) +
           " s of these cells and particles, allowed by 'Integrator/Explicit/Stability Factor' = " +
           formatNumber(settings_.stabilityFactor) + " (keep it at most 1)";
  std::string advice =
      "reduce " + step + " (the stable step of these cells and particles is " + formatNumber(criticalStep_) + " s)";
  // Within the stable step, linear MPM with USL still inverts a particle that crosses alone into
  // a cell (ShapeInfo::crossingInverts): a smaller step only makes that rarer.
  if (shapeInfo(shape_).crossingInverts && settings_.updateSchemeUsl)
    advice +=
        ", or, if a particle crossed a cell line alone (impact, a moving free surface), use 'Method/Shape Function' = "
        "GIMP (or cpGIMP, CPDI, a B-spline) or 'Integrator/Explicit/Update Scheme' = MUSL: linear MPM with USL "
        "can invert such a particle at any time step";
  return advice;
}

// Why the state of `step` is bad: a non-finite or inverted particle (named), or a strain of order one.
std::string Simulation::divergenceMessage(double divergence, int step, double t) const {
  std::string why;
  if (std::isinf(divergence)) {
    const std::string which = describeBadParticle();
    why = which.empty() ? std::string("a particle velocity or stress is not finite") : which;
  } else {
    why = "a particle stress is " + formatNumber(divergence) +
          " times its material's P-wave modulus (a strain of order one)";
  }
  return "the run diverged at step " + std::to_string(step) + " (t = " + formatNumber(t) + " s): " + why;
}

}  // namespace impm
