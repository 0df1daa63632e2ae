// The columns of the implicit step's grid multivectors in Dim dimensions. A vector field takes
// Dim consecutive columns, named by its first (X) one.
#pragma once

namespace impm::implicit {

// The grid state of the step: mass, v, a (at t), F_ext (at t + dt) and a flag per free component.
template <int Dim>
struct StateColumns {
  static constexpr int Mass = 0, VelX = 1, AccX = 1 + Dim, FextX = 1 + 2 * Dim, FreeX = 1 + 3 * Dim,
                       Count = 1 + 4 * Dim;
};

// The displacement multivector: the step's displacement, the new acceleration and the grid's
// velocity increment dt ((1 - gamma) a + gamma a_new).
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

}  // namespace impm::implicit
