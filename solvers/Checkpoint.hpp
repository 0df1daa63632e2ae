// Checkpoint and restart (Output/Checkpoint Interval, `impm DECK --restart DIR`).
//
// A checkpoint is a directory: header.xml (a Teuchos ParameterList: format version, impm
// version, step, time, rank count, particle count, each rank file's byte size, and the deck
// without its Output sublist, Problem/Output Directory and Integrator/Number of Steps) and one
// binary file per rank (rank_NNNNN.bin: that rank's particles packed as for migration, in their
// local order, then the named arrays of the integrator's and the history's state). It is
// written into OUTPUT/checkpoint_<step>.tmp, renamed to OUTPUT/checkpoint_<step> once complete,
// and OUTPUT/checkpoint, a symbolic link, is then atomically replaced to point at it; older
// checkpoint_* directories are removed after that. A crash at any point leaves the previous
// checkpoint whole.
//
// Reading checks everything before anything is changed or written: the header's format and
// impm version, the deck, every rank file's size, magic numbers and widths. Each failure is a
// CheckpointError (a DeckError: exit 2) naming what differs. At the rank count that wrote it a
// rank reads its own file (the particles keep their order: the run continues bit for bit); at
// another rank count every rank reads every file and keeps the particles of its cells.
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>

#include <functional>
#include <map>
#include <string>
#include <vector>

#include "core/InputDeck.hpp"
#include "core/ParticleSet.hpp"
#include "solvers/Integrator.hpp"

namespace impm {

struct CheckpointError : DeckError {
  using DeckError::DeckError;
};

// State beyond the particles: NamedArrays (Integrator.hpp). Arrays whose name starts with
// kNodeArrayPrefix are per rank (e.g. owned grid nodes with their global ids) and are
// concatenated over all rank files read; the others are the same on every rank.
inline const std::string kNodeArrayPrefix = "node ";

// What a checkpoint holds for one rank.
struct CheckpointContent {
  int step = 0;
  double time = 0;
  ParticleSet::Packed particles;  // this rank's particles (ParticleSet::pack), host or device
  NamedArrays state;              // integrator and history
};

// Bumped when the binary layout or the header's meaning changes.
constexpr int kCheckpointFormatVersion = 1;

// impm's version as the checkpoint header records it (project version and git describe).
std::string impmVersion();

// The deck as a checkpoint compares it: without Output, Problem/Output Directory and
// Integrator/Number of Steps (a restart may write elsewhere, and run longer).
Teuchos::ParameterList checkpointedDeck(const Teuchos::ParameterList& deck);

// Writes the checkpoint of `step` under outputDir (see above). Collective; a failure on any rank
// throws std::runtime_error on every rank.
void writeCheckpoint(const std::string& outputDir, const Teuchos::ParameterList& deck, const CheckpointContent& mine,
                     const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

// Reads and checks the checkpoint in `dir` against `deck`. `keep(x)` says whether a particle at
// x (x[0..dim)) belongs to this rank (used when the rank count differs). `width` and
// `dim` are the particle set's packed width and dimension. Collective; throws CheckpointError on
// every rank when anything is wrong.
CheckpointContent readCheckpoint(const std::string& dir, const Teuchos::ParameterList& deck, int width, int dim,
                                 const std::function<bool(const double*)>& keep,
                                 const Teuchos::RCP<const Teuchos::Comm<int>>& comm);

}  // namespace impm
