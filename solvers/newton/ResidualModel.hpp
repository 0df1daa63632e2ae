// What an implicit integrator gives the Newton solver: the residual R(u) of one time step over
// a Tpetra map of unknowns, and an assembled matrix P ~ dR/du. Its own header, so that the
// solver and the Thyra model evaluator depend on it, not on each other.
#pragma once

#include <Teuchos_RCP.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include "core/Types.hpp"

namespace impm {

using CrsMatrix = Tpetra::CrsMatrix<Scalar, LO, GO, Node>;

// What the implicit integrator provides: R(u) on a Tpetra map of unknowns (free grid dofs;
// the map may change from one time step to the next) and an assembled matrix P ~ dR/du
// (P = 4/dt^2 M_lumped + K) for the preconditioner or for assembled Newton.
class ResidualModel {
 public:
  virtual ~ResidualModel() = default;
  virtual Teuchos::RCP<const Map> unknownMap() const = 0;
  // R(u) on unknownMap(); must overwrite every entry of R. Collective: all ranks call it.
  virtual void residual(const Vector& u, Vector& R) = 0;
  // Assembled approximation of the Jacobian; may be recomputed each call (values change with u for
  // large deformation). Must be fill complete, with row, range and domain maps equal to unknownMap().
  // Returning the same object (refilled, with a static graph) lets the preconditioner skip its
  // symbolic setup (Ifpack2 initialize()); a new object triggers a full rebuild.
  virtual Teuchos::RCP<const CrsMatrix> jacobianMatrix(const Vector& u) = 0;
  // A number that changes whenever the values of the matrix last returned by jacobianMatrix
  // change (so that preconditioner factors can be kept); -1: unknown, always refactor.
  virtual long jacobianVersion() const { return -1; }
  // Geometry for algebraic multigrid (MueLu): the coordinates of the grid node of each unknown,
  // a MultiVector on unknownMap() with one column per direction, when the unknowns are laid out
  // as gid = unknownsPerNode() * node gid + component. Null: no such layout.
  virtual Teuchos::RCP<const MultiVector> unknownCoordinates() const { return Teuchos::null; }
  virtual int unknownsPerNode() const { return 1; }
  // The size of the terms R(u) is summed from: || |P| |u| + |b| ||_2, dof by dof, with b the part
  // of R that does not depend on u (the inertia of the step's start and the external force). R is
  // computed in floating point from terms of this size, so round-off leaves it uncertain by about
  // machine epsilon times this, and no Newton iteration can reduce it further (NewtonSolver's
  // residual magnitude test). Negative: unknown. Collective.
  virtual double residualMagnitude(const Vector& /*u*/) { return -1.0; }
};

}  // namespace impm
