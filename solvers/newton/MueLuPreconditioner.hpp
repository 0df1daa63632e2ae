// Smoothed-aggregation algebraic multigrid (MueLu) on the assembled P, for `Implicit Solver/
// Preconditioner: MUELU`: Ifpack2 smoothers, "number of equations" = the unknowns per node, the
// rigid-body modes of the unknowns' nodes as near-null space (2D: 3, 3D: 6) and the node
// coordinates handed to the aggregation. Compiled against MueLu only when CMake found it in the
// Trilinos (IMPM_HAVE_MUELU); otherwise MUELU is refused at deck validation.
#pragma once

#include "solvers/newton/PreconditionerCache.hpp"

#include <Teuchos_ParameterList.hpp>

namespace impm {

// Whether this impm was built against a Trilinos with MueLu.
bool mueLuAvailable();

// impm's defaults for the `Implicit Solver/MueLu` list; the deck's keys win.
Teuchos::ParameterList mueLuDefaults();

// A MueLu preconditioner cache for the deck's `Implicit Solver/MueLu` list (impm's defaults filled
// in). Throws std::invalid_argument with one line naming 'Implicit Solver/MueLu[/<key>]' when MueLu
// does not know a key or rejects a value: keys are checked against MueLu's master list, values by
// building a hierarchy on a small matrix over a one-process communicator (not collective). Throws too
// when this Trilinos has no MueLu.
Teuchos::RCP<PreconditionerCache> makeMueLuPreconditioner(const Teuchos::ParameterList& params);

}  // namespace impm
