// Contact between bodies on the grid: the multi-velocity-field method of Bardenhagen, Brackbill &
// Sulsky (2000) and Bardenhagen et al. (2001), with the refinements of Uintah and NairnMPM.
//
// Every body has its own grid field (mass, momentum, forces, volume gradient). A node where two or
// more bodies have mass is a contact node. There, body a's velocity v_a is compared with the
// centre-of-mass velocity v_cm = sum_b m_b v_b / sum_b m_b (the single-field velocity):
//   - the normal n_a points out of a towards the others. The volume gradient g = sum_p V_p grad S_ip
//     of a body's particles points out of the body at the nodes around it. Larger Gradient (default,
//     Nairn's MVG): g_a / |g_a| or -g_rest / |g_rest| (g_rest of the other bodies together),
//     whichever gradient is larger; Average (AVG): (g_a - g_rest) / |g_a - g_rest|. The average
//     tilts at a body's corner, where a sliding body then plows into the other (a block on an
//     incline travelled 6% short frictionless, against 0.04% with the larger gradient). Both make the two bodies'
//     normals opposite, so a two-body contact conserves momentum;
//   - the bodies approach when dv = v_a - v_cm has dv.n_a > 0; only then is v_a corrected
//     (separating bodies are left alone), and a node where a holds less than `massScreen` of the
//     mass (or more than 1 - massScreen) is skipped: a body's far stencil edge carries too little
//     mass for a reliable normal (Nairn's pre-screen);
//   - the approach alone fires up to a cell before the surfaces meet (the nodes a body's stencil
//     reaches lie beyond its surface). Optionally (contactDistance > 0) contact also needs the
//     bodies' material to be close along the normal: the centroids of the two sides' mass seen by
//     the node (sum m_p S_ip x_p / m), x_a and x_rest, must have (x_rest - x_a).n_a below
//     contactDistance h_n, h_n the cell size along n (after Nairn 2013's position check; surfaces
//     that touch measure about 0.75 cells with two particles per cell). It keeps contact from
//     braking a rolling body ahead of its contact point (a disk on an incline rolled 27% short
//     with the approach alone, 6% with 0.8 cells), but a collision detected later is a harder one
//     (Sulsky's disks lost 11% of their energy at 16 cells per diameter with 0.8, 7% without);
//   - the correction removes the normal approach, dv.n_a n_a, and Coulomb friction removes at most
//     mu dv.n_a of the tangential slip dv_t (all of it when that suffices: stick). No slip (the
//     pair's law) sets v_a = v_cm always: the pair moves as one field.
// With three or more bodies at a node, a meets the others as one body (NairnMPM's "virtual
// other"), with the law of the pair (a, the heaviest of the others).
//
// Rigid bodies (Uintah's "specified" contact, NairnMPM's rigid materials): a rigid body's field
// takes its prescribed velocity V(t) at every node where it has mass, and counts as infinitely
// heavy: at a node it shares, v_cm = V, so the other bodies lose their approach to it (and slip
// under friction) while it keeps its motion; its particles, interpolating only V, move rigidly.
// Its contact force (the others' reaction) is the whole m_a dv_a / dt of the bodies it meets. Two
// rigid bodies pass through each other. A rigid body may give its surface's normal (a plane: a
// wall at any angle, a platen): the volume gradient of particles that fill a tilted plane is a
// staircase's, whose steps stopped a frictionless block on a 30 degree plane dead.
//
// The change m_a dv_a / dt is the contact force on a; the force of each pair of bodies on the body
// named first (summed over nodes and ranks) is reported per pair. The explicit step applies the exchange
// after the grid update (to the new velocity and the acceleration, so FLIP particles receive the
// impulse), and to the velocity the stress is computed from (USF's start, MUSL's re-mapped one).
// The implicit step applies it as a penalty force in the Newton residual, through an active set
// (ContactActiveSet) that holds each contact node's stick or slip fixed during a solve.
#pragma once

#include <Kokkos_Core.hpp>

#include <array>
#include <cmath>
#include <string>
#include <vector>

#include "core/Types.hpp"
#include "physics/TimeFunction.hpp"

namespace impm {

struct ContactSpec {
  enum class Normals { LargerGradient, Average };
  static constexpr double kNoSlip = -1.0;  // a pair's friction that means "no slip"
  std::vector<std::string> bodies;         // one field per body, in the deck's body order
  // One entry per unordered pair of bodies (a < b), in the order (0,1), (0,2), .., (1,2), ..:
  // its name (history columns <name>_contact_<x|y|z>) and its friction coefficient (or kNoSlip).
  std::vector<std::string> pairNames;
  std::vector<double> pairFriction;
  // Per pair, +1 when its force is reported on its body a (the lower index), -1 on b (the pair
  // was named with b first); empty: all +1.
  std::vector<double> pairSign;
  Normals normals = Normals::LargerGradient;
  double massScreen = 1e-5;
  // The separation check: a body is in contact at a node only where the centroid of the others'
  // mass there lies closer along the normal than this many cell sizes to the centroid of its own
  // (0: the approach alone decides).
  double contactDistance = 0.0;
  // Per body (empty: none rigid): whether it is rigid, and its prescribed velocity
  // rigidVelocity * rigidTime(t).
  std::vector<bool> rigid;
  std::vector<std::array<double, 3>> rigidVelocity;
  std::vector<TimeFunction> rigidTime;
  // Per body (empty: none): the unit outward normal of a rigid body's contact surface (a plane: a
  // wall, a platen), used at every node it shares instead of the volume gradients; 0: gradients.
  std::vector<std::array<double, 3>> rigidNormal;
  bool enabled() const { return bodies.size() > 1; }
  // The index of the pair of bodies a != b.
  KOKKOS_INLINE_FUNCTION static int pairIndex(int a, int b, int bodyCount) {
    const int lo = a < b ? a : b, hi = a < b ? b : a;
    return lo * bodyCount - lo * (lo + 1) / 2 + (hi - lo - 1);
  }
};

// The implicit step's contact as an active set (Frozen, then Classify; see
// ImplicitNewmark::reviseContactStates). Each owned node's field is Free (no contact force), Stick
// (the law removes its whole relative velocity dv) or Slip (the approach, and friction mu dn along
// the slip direction of the last classification); the Newton solve sees that fixed set, so its
// residual is smooth: Coulomb's kink, where a node starts or stops slipping, is decided between
// solves instead. After a solve, Classify decides each contact node's state from its trial
// velocities: Free where the bodies do not approach (dn <= 0); a slipping node stays Slip while the
// slip friction leaves still runs along its direction, else sticks; any other node sticks where
// friction can hold it (|dv_t| <= mu dn), else slips along dv_t. Frictional pairs only: the
// frictionless law kinks only where the bodies start or stop approaching, which Newton's line
// search handles, and No Slip is linear in dv. Classify counts the nodes whose state changed or
// whose slip direction turned by more than about 8 degrees. Linearize writes the law's derivative
// with the set's states (the preconditioner's contact stiffness; Exchange::linearize).
struct ContactActiveSet {
  enum State : int { Free = 0, Stick = 1, Slip = 2 };
  enum class Mode { Law, Frozen, Classify, Linearize };
  Kokkos::View<int**, Kokkos::LayoutRight, DeviceType> state;         // owned node x field
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> direction;  // owned node x (3 per field)
  // Owned node x (3 per field): the contact force on each field at the end of the last converged
  // step, carried into the next as the augmented Lagrangian's multiplier (GridConditions).
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> force;
  // Owned node x (10 per field): Linearize's -d m_a (v*_a - v_a) / d v_b = m_a B_a (delta_ab - w_b),
  // with m_a B_a in columns 9 a + 3 d + e (row-major 3 x 3; zero where a is free) and w_b, field b's
  // share of the velocity the bodies meet at, in column 9 fields + b.
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> jacobian;
  Mode mode = Mode::Law;
  // Whether the set holds the nodes of a grid of `nodes` owned nodes and `fields` fields; else
  // (the first step, a new decomposition) it starts afresh with every node Free and no force.
  void fit(size_t nodes, int fields) {
    if (state.extent(0) == nodes && state.extent(1) == size_t(fields)) return;
    state = decltype(state)("contact_active_set", nodes, fields);
    direction = decltype(direction)("contact_slip_direction", nodes, 3 * fields);
    force = decltype(force)("contact_carried_force", nodes, 3 * fields);
    jacobian = decltype(jacobian)("contact_jacobian", nodes, 10 * fields);
  }
};

class MultiFieldContact {
 public:
  // The largest number of bodies (fields) a contact deck may have.
  static constexpr int kMaxFields = 16;

  MultiFieldContact() = default;
  // `spacing`: the grid's cell sizes (3; the separation check's unit).
  MultiFieldContact(const ContactSpec& spec, const double* spacing);

  bool active() const { return fields_ > 1; }
  int fieldCount() const { return fields_; }
  int pairCount() const { return pairs_; }
  // Each body's field (the identity: one field per body).
  Kokkos::View<const int*, DeviceType> fieldOfBody() const { return fieldOfBody_; }
  bool hasRigid() const { return hasRigid_; }
  // Per field: 1 if rigid; and each field's prescribed velocity V(t) (columns 0-2) and V(t + dt)
  // (3-5) for the step setStep was last given (zero for a field that is not rigid).
  Kokkos::View<const int*, DeviceType> rigidFields() const { return rigid_; }
  Kokkos::View<const double**, Kokkos::LayoutRight, DeviceType> rigidMotion() const { return rigidMotion_; }
  // The rigid bodies' velocities at the start and the end of the step [t, t + dt] (host; cheap).
  void setStep(double t, double dt);

  // The exchange at every owned node (see the file comment). Field f of the particle sums `sums`
  // has its mass in column massCol + f * sumsStride, its volume gradient in gradCol.. and its
  // mass-weighted position in gradCol + dim..; its
  // velocity (and acceleration, when accCol >= 0) in `kin` at velCol + f * kinStride (accCol..).
  // With pairForce (3 per pair), the force of each pair on its first body is written there.
  // Rigid fields take their velocity at the step's end (stepEnd) or start, and the step's change
  // of it over dt as acceleration. With an active set in Frozen mode, the set's states replace the
  // law (see ContactActiveSet); in Classify mode the states are decided anew (kin is left alone)
  // and the return value is the number of nodes whose state changed; otherwise 0.
  template <class ExecSpace, class SumsView, class KinView>
  int exchange(const SumsView& sums, int massCol, int gradCol, int sumsStride, const KinView& kin, int velCol,
               int accCol, int kinStride, int dim, double dt, bool stepEnd, std::vector<double>* pairForce,
               ContactActiveSet* activeSet = nullptr) const;

 private:
  template <class SumsView, class KinView>
  struct Exchange;

  int fields_ = 1;
  int pairs_ = 0;
  bool larger_ = true;
  double screen_ = 1e-5;
  double distance_ = 0.0;
  double spacing_[3] = {1.0, 1.0, 1.0};
  std::vector<double> pairSign_;
  bool hasRigid_ = false;
  std::vector<std::array<double, 3>> rigidVelocity_;
  std::vector<TimeFunction> rigidTime_;
  Kokkos::View<int*, DeviceType> fieldOfBody_;
  Kokkos::View<int*, DeviceType> rigid_;                                 // per field: 1 if rigid
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> rigidMotion_;  // per field: V(t) (3), V(t + dt) (3)
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> rigidNormal_;  // per field: outward normal, or 0
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> friction_;     // field x field (kNoSlip: no slip)
};

// The node kernel, a reduction of the pair forces (3 per pair) over the nodes.
template <class SumsView, class KinView>
struct MultiFieldContact::Exchange {
  using value_type = double[];
  using size_type = int;
  SumsView sums;
  KinView kin;
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> friction;
  Kokkos::View<int*, DeviceType> rigid;
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> rigidMotion, rigidNormal;
  int massCol, gradCol, sumsStride, velCol, accCol, kinStride, fields, dim;
  double dt, screen, distance, h[3];
  bool larger, hasRigid, stepEnd;
  // The implicit step's active set (mode Law: none) and its mode.
  Kokkos::View<int**, Kokkos::LayoutRight, DeviceType> state;
  Kokkos::View<double**, Kokkos::LayoutRight, DeviceType> direction, jacobian;
  ContactActiveSet::Mode mode;
  size_type value_count;  // 3 per pair, then the count of Classify's changes

  KOKKOS_INLINE_FUNCTION void init(double* f) const {
    for (int k = 0; k < value_count; ++k) f[k] = 0.0;
  }
  KOKKOS_INLINE_FUNCTION void join(double* f, const double* g) const {
    for (int k = 0; k < value_count; ++k) f[k] += g[k];
  }

  KOKKOS_INLINE_FUNCTION void operator()(int n, double* force) const {
    if (mode != ContactActiveSet::Mode::Classify) {
      exchangeAt(n, force, nullptr);
      return;
    }
    // Classify: every field Free unless exchangeAt finds it in contact; the changes counted.
    int old[kMaxFields];
    for (int f = 0; f < fields; ++f) {
      old[f] = state(n, f);
      state(n, f) = ContactActiveSet::Free;
    }
    exchangeAt(n, force, old);
    for (int f = 0; f < fields; ++f) force[value_count - 1] += state(n, f) != old[f] ? 1.0 : 0.0;
  }

  // The exchange at node n (see the file comment); in Classify mode (old: each field's state before)
  // the contact fields' states instead.
  KOKKOS_INLINE_FUNCTION void exchangeAt(int n, double* force, const int* old) const {
    double mass[kMaxFields], total = 0.0;
    int present = 0;
    for (int f = 0; f < fields; ++f) {
      mass[f] = sums(n, massCol + f * sumsStride);
      if (!(mass[f] > 0.0)) continue;
      ++present;
      total += mass[f];
    }
    const int rigidField = hasRigid ? moveRigidFields(n, mass, total) : -1;
    if (present < 2) return;
    // The mass screen, one comparison per field (the same for both sides of a contact): a field
    // below it takes no part, and a node with fewer than two fields above it is no contact node.
    int screened = 0;
    for (int f = 0; f < fields; ++f) screened += mass[f] > 0.0 && !(mass[f] < screen * total) ? 1 : 0;
    if (screened < 2) return;
    double vcm[3] = {0.0, 0.0, 0.0};
    centreOfMassVelocity(n, mass, rigidField, vcm);
    if (mode == ContactActiveSet::Mode::Linearize) writeShares(n, mass, rigidField);
    for (int a = 0; a < fields; ++a) {
      if (!(mass[a] > 0.0) || mass[a] < screen * total || (hasRigid && rigid(a))) continue;
      int other = rigidField;  // a rigid body, else the heaviest other body: its pair's law
      if (other < 0)
        for (int f = 0; f < fields; ++f)
          if (f != a && mass[f] > 0.0 && !(hasRigid && rigid(f)) && (other < 0 || mass[f] > mass[other])) other = f;
      if (other < 0) continue;
      double normal[3] = {0.0, 0.0, 0.0};
      if (!contactNormal(n, a, other, normal)) continue;
      const double mu = friction(a, other);
      if (mu >= 0.0 && distance > 0.0 && !close(n, a, mass, normal)) continue;
      double dv[3] = {0.0, 0.0, 0.0}, dn = 0.0;
      for (int d = 0; d < dim; ++d) {
        dv[d] = kin(n, velCol + a * kinStride + d) - vcm[d];
        dn += dv[d] * normal[d];
      }
      double change[3] = {0.0, 0.0, 0.0};
      if (mode == ContactActiveSet::Mode::Classify) {
        if (mu > 0.0) force[value_count - 1] += classify(n, a, mu, dv, dn, normal, old[a]);
        continue;
      }
      if (mode == ContactActiveSet::Mode::Linearize) {
        linearize(n, a, mu, dn, normal, mass[a]);
        continue;
      }
      if (mu < 0.0) {  // no slip
        for (int d = 0; d < dim; ++d) change[d] = -dv[d];
      } else if (mode == ContactActiveSet::Mode::Frozen && mu > 0.0) {
        if (!frozenChange(n, a, mu, dv, dn, normal, change)) continue;
      } else {
        if (!(dn > 0.0)) continue;  // separating (or sliding along): no contact
        double slip = 0.0;
        for (int d = 0; d < dim; ++d) slip += (dv[d] - dn * normal[d]) * (dv[d] - dn * normal[d]);
        slip = std::sqrt(slip);
        const double removed = slip > 0.0 ? (mu * dn < slip ? mu * dn / slip : 1.0) : 0.0;
        for (int d = 0; d < dim; ++d) change[d] = -dn * normal[d] - removed * (dv[d] - dn * normal[d]);
      }
      const int pair = ContactSpec::pairIndex(a, other, fields);
      // The force on the pair's first body: half from each side, or all of it from a's when the
      // other is rigid (a rigid field takes no correction).
      const double share = other == rigidField ? 1.0 : 0.5;
      const double sign = a < other ? share : -share;
      for (int d = 0; d < dim; ++d) {
        kin(n, velCol + a * kinStride + d) += change[d];
        if (accCol >= 0) kin(n, accCol + a * kinStride + d) += change[d] / dt;
        force[3 * pair + d] += sign * mass[a] * change[d] / dt;
      }
    }
  }

  // Frozen: the correction of field a at node n by its state (false: Free, none).
  KOKKOS_INLINE_FUNCTION bool frozenChange(int n, int a, double mu, const double* dv, double dn, const double* normal,
                                           double* change) const {
    const int current = state(n, a);
    if (current == ContactActiveSet::Free) return false;
    for (int d = 0; d < dim; ++d)
      change[d] = current == ContactActiveSet::Stick ? -dv[d] : -dn * normal[d] - mu * dn * direction(n, 3 * a + d);
    return true;
  }

  // Linearize: -d m_a (v*_a - v_a) / d v_b = m_a B_a (delta_ab - w_b) at node n, with
  // dv_a = v_a - sum_b w_b v_b: B_a is the identity where a sticks (or the pair does not slip),
  // n n^T + mu s n^T where it slips along s, n n^T for a frictionless approach, and zero where a is
  // free; writes m_a B_a (`mass` = m_a).
  KOKKOS_INLINE_FUNCTION void linearize(int n, int a, double mu, double dn, const double* normal, double mass) const {
    int current = mu < 0.0 ? ContactActiveSet::Stick : ContactActiveSet::Slip;
    if (mu > 0.0) current = state(n, a);
    if (current == ContactActiveSet::Free || (mu == 0.0 && !(dn > 0.0))) return;
    for (int d = 0; d < dim; ++d)
      for (int e = 0; e < dim; ++e) {
        const double slip = normal[d] * normal[e] + (mu > 0.0 ? mu * direction(n, 3 * a + d) * normal[e] : 0.0);
        jacobian(n, 9 * a + 3 * d + e) = mass * (current == ContactActiveSet::Stick ? (d == e ? 1.0 : 0.0) : slip);
      }
  }

  // Linearize: each field's share w_b of the velocity the bodies meet at, at node n: m_b / m over
  // the deformable bodies (centreOfMassVelocity), none where a rigid body sets it.
  KOKKOS_INLINE_FUNCTION void writeShares(int n, const double* mass, int rigidField) const {
    double m = 0.0;
    for (int f = 0; f < fields; ++f)
      if (mass[f] > 0.0 && !(hasRigid && rigid(f))) m += mass[f];
    for (int f = 0; f < fields; ++f) {
      const bool shares = rigidField < 0 && mass[f] > 0.0 && !(hasRigid && rigid(f));
      jacobian(n, 9 * fields + f) = shares ? mass[f] / m : 0.0;
    }
  }

  // Classify: field a's state at node n from its trial relative velocity dv (dn along the normal)
  // and its state before, `old`; 1 when it slips on with its direction turned.
  KOKKOS_INLINE_FUNCTION int classify(int n, int a, double mu, const double* dv, double dn, const double* normal,
                                      int old) const {
    int next = ContactActiveSet::Free;
    double left[3] = {0.0, 0.0, 0.0}, length = 0.0;
    if (dn > 0.0) {
      for (int d = 0; d < dim; ++d) left[d] = dv[d] - dn * normal[d];  // the tangential slip dv_t
      if (old == ContactActiveSet::Slip) {
        double along = 0.0;  // the slip friction leaves, along the frozen direction
        for (int d = 0; d < dim; ++d) {
          left[d] -= mu * dn * direction(n, 3 * a + d);
          along += left[d] * direction(n, 3 * a + d);
        }
        next = along > 0.0 ? ContactActiveSet::Slip : ContactActiveSet::Stick;
      } else {
        double slip2 = 0.0;
        for (int d = 0; d < dim; ++d) slip2 += left[d] * left[d];
        next = slip2 <= mu * mu * dn * dn ? ContactActiveSet::Stick : ContactActiveSet::Slip;
      }
      for (int d = 0; d < dim; ++d) length += left[d] * left[d];
      length = std::sqrt(length);
    }
    int changed = 0;
    if (next == ContactActiveSet::Slip && length > 0.0) {
      double cosine = 0.0;
      for (int d = 0; d < dim; ++d) cosine += left[d] / length * direction(n, 3 * a + d);
      if (old == ContactActiveSet::Slip && cosine < 0.99) changed = 1;
      for (int d = 0; d < dim; ++d) direction(n, 3 * a + d) = left[d] / length;
    }
    state(n, a) = next;
    return changed;
  }

  // Writes each rigid field's prescribed motion at node n (where it has mass) and returns the
  // heaviest rigid field above the mass screen there (-1: none).
  KOKKOS_INLINE_FUNCTION int moveRigidFields(int n, const double* mass, double total) const {
    int heaviest = -1;
    for (int f = 0; f < fields; ++f) {
      if (!rigid(f) || !(mass[f] > 0.0)) continue;
      for (int d = 0; d < dim; ++d) {
        kin(n, velCol + f * kinStride + d) = rigidMotion(f, (stepEnd ? 3 : 0) + d);
        if (accCol >= 0) kin(n, accCol + f * kinStride + d) = (rigidMotion(f, 3 + d) - rigidMotion(f, d)) / dt;
      }
      if (!(mass[f] < screen * total) && (heaviest < 0 || mass[f] > mass[heaviest])) heaviest = f;
    }
    return heaviest;
  }

  // The velocity the bodies at node n meet at: a rigid body's, else the centre of mass's.
  KOKKOS_INLINE_FUNCTION void centreOfMassVelocity(int n, const double* mass, int rigidField, double* vcm) const {
    if (rigidField >= 0) {
      for (int d = 0; d < dim; ++d) vcm[d] = kin(n, velCol + rigidField * kinStride + d);
      return;
    }
    double p[3] = {0.0, 0.0, 0.0}, m = 0.0;
    for (int f = 0; f < fields; ++f) {
      if (!(mass[f] > 0.0) || (hasRigid && rigid(f))) continue;  // (a rigid field below the screen)
      m += mass[f];
      for (int d = 0; d < dim; ++d) p[d] += mass[f] * kin(n, velCol + f * kinStride + d);
    }
    for (int d = 0; d < dim; ++d) vcm[d] = m > 0.0 ? p[d] / m : 0.0;
  }

  // The sum over the fields other than a of columns col.. of `sums` (with two fields, exactly the
  // other field's values, so that both sides of a contact see the same numbers).
  KOKKOS_INLINE_FUNCTION void othersSum(int n, int a, int col, double* out) const {
    for (int d = 0; d < dim; ++d) out[d] = 0.0;
    for (int f = 0; f < fields; ++f)
      if (f != a)
        for (int d = 0; d < dim; ++d) out[d] += sums(n, col + f * sumsStride + d);
  }

  // Whether the others' material lies within `distance` cells of a's along the normal at node n.
  KOKKOS_INLINE_FUNCTION bool close(int n, int a, const double* mass, const double* normal) const {
    double rest[3], mrest = 0.0, gap = 0.0, hn = 0.0;
    othersSum(n, a, gradCol + dim, rest);
    for (int f = 0; f < fields; ++f)
      if (f != a && mass[f] > 0.0) mrest += mass[f];
    for (int d = 0; d < dim; ++d) {
      const double xa = sums(n, gradCol + a * sumsStride + dim + d);
      gap += (rest[d] / mrest - xa / mass[a]) * normal[d];
      hn += normal[d] * normal[d] * h[d] * h[d];
    }
    return gap < distance * std::sqrt(hn);
  }

  // The unit normal out of field a at node n (false where it is undefined): a rigid other's
  // given surface normal, reversed, or from the volume gradients.
  KOKKOS_INLINE_FUNCTION bool contactNormal(int n, int a, int other, double* normal) const {
    if (hasRigid && rigid(other) &&
        (rigidNormal(other, 0) != 0.0 || rigidNormal(other, 1) != 0.0 || rigidNormal(other, 2) != 0.0)) {
      for (int d = 0; d < dim; ++d) normal[d] = -rigidNormal(other, d);
      return true;
    }
    double ga[3] = {0.0, 0.0, 0.0}, rest[3], la = 0.0, lr = 0.0;
    othersSum(n, a, gradCol, rest);
    for (int d = 0; d < dim; ++d) {
      ga[d] = sums(n, gradCol + a * sumsStride + d);
      la += ga[d] * ga[d];
      lr += rest[d] * rest[d];
    }
    // Equal gradients (mirror-image bodies) go to the lower field on both sides, so that the two
    // normals stay opposite.
    const bool ownLarger = la > lr || (la == lr && a < other);
    double len = 0.0;
    for (int d = 0; d < dim; ++d) {
      // (sum_p V_p grad S_ip points out of a body at a node beside it.) Average: g_a - g_rest;
      // Larger Gradient: g_a or -g_rest, whichever is longer.
      normal[d] = !larger ? ga[d] - rest[d] : (ownLarger ? ga[d] : -rest[d]);
      len += normal[d] * normal[d];
    }
    len = std::sqrt(len);
    if (!(len > 0.0)) return false;
    for (int d = 0; d < dim; ++d) normal[d] /= len;
    return true;
  }
};

template <class ExecSpace, class SumsView, class KinView>
int MultiFieldContact::exchange(const SumsView& sums, int massCol, int gradCol, int sumsStride, const KinView& kin,
                                int velCol, int accCol, int kinStride, int dim, double dt, bool stepEnd,
                                std::vector<double>* pairForce, ContactActiveSet* activeSet) const {
  if (!active()) return 0;
  const ContactActiveSet::Mode mode = activeSet ? activeSet->mode : ContactActiveSet::Mode::Law;
  if (activeSet) activeSet->fit(kin.extent(0), fields_);
  Exchange<SumsView, KinView> op{sums,
                                 kin,
                                 friction_,
                                 rigid_,
                                 rigidMotion_,
                                 rigidNormal_,
                                 massCol,
                                 gradCol,
                                 sumsStride,
                                 velCol,
                                 accCol,
                                 kinStride,
                                 fields_,
                                 dim,
                                 dt,
                                 screen_,
                                 distance_,
                                 {spacing_[0], spacing_[1], spacing_[2]},
                                 larger_,
                                 hasRigid_,
                                 stepEnd,
                                 activeSet ? activeSet->state : decltype(activeSet->state)(),
                                 activeSet ? activeSet->direction : decltype(activeSet->direction)(),
                                 activeSet ? activeSet->jacobian : decltype(activeSet->jacobian)(),
                                 mode,
                                 3 * pairs_ + 1};
  std::vector<double> sumsOut(3 * pairs_ + 1, 0.0);
  Kokkos::View<double*, Kokkos::HostSpace, Kokkos::MemoryTraits<Kokkos::Unmanaged>> result(sumsOut.data(),
                                                                                           sumsOut.size());
  Kokkos::parallel_reduce("multi_field_contact", Kokkos::RangePolicy<ExecSpace>(0, kin.extent(0)), op, result);
  const int changes = int(sumsOut.back());
  if (pairForce) {
    sumsOut.pop_back();
    for (int k = 0; k < pairs_; ++k)
      for (int d = 0; d < 3; ++d) sumsOut[3 * k + d] *= pairSign_[k];
    *pairForce = sumsOut;
  }
  return changes;
}

}  // namespace impm
