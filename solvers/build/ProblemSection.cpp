// Deck sections Problem and Output: the run's name, where its outputs go and what is written;
// the output directory and the run's estimated size are checked before anything is allocated.
#include "solvers/Simulation.hpp"

#include <Teuchos_CommHelpers.hpp>

#include "core/Collective.hpp"
#include "core/DeckSchema.hpp"
#include "core/ShapeRegistry.hpp"
#include "solvers/build/Sections.hpp"

#include <stdlib.h>
#include <unistd.h>

#include <cerrno>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

namespace impm {

using build::kParticlePlacementDoc;
using build::onGridLine;
using build::timeFunctionKeys;
using schema::choice;
using schema::number;
using schema::positive;
using schema::positiveInt;
using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

namespace {

// The output directory can be created and written: it is a directory, or its nearest existing
// ancestor is one, in which a probe directory can be made (and is removed at once, so that a
// deck that fails later leaves nothing behind). A real probe, not access(): root passes
// access() on /proc and on read-only mounts. `key` names where the path came from.
void checkOutputDirectory(const std::string& dir, const std::string& key) {
  namespace fs = std::filesystem;
  const std::string what = key + " = '" + dir + "'";
  std::error_code ec;
  const fs::path target = fs::absolute(dir, ec).lexically_normal();
  if (ec) throw DeckError(what + ": " + ec.message());
  fs::path existing = target;
  fs::file_status status = fs::status(existing, ec);
  while (status.type() == fs::file_type::not_found && existing.has_relative_path()) {
    existing = existing.parent_path();
    status = fs::status(existing, ec);
  }
  if (!fs::is_directory(status)) {
    if (existing == target) throw DeckError(what + " exists and is not a directory");
    throw DeckError(what + " cannot be created: '" + existing.string() + "' is not a directory");
  }
  std::string probe = (existing / ".impm-write-test-XXXXXX").string();
  if (!mkdtemp(probe.data()))
    throw DeckError(what + (existing == target ? " is not writable" : " cannot be created") +
                    ": no directory can be made in '" + existing.string() + "' (" + std::strerror(errno) + ")");
  rmdir(probe.c_str());
}

// A grid of nx x ny cells and nodes per rank must fit impm's 32-bit local indices with two
// unknowns per node (Tpetra's LO is int).
constexpr long long kMaxGridNodes = std::numeric_limits<int>::max() / 2;

// Memory measured with /usr/bin/time (maximum resident set, OMP_NUM_THREADS=1, 2026-11): a
// rank's libraries and runtimes; per grid node, explicit (the Tpetra fields and maps) and
// implicit (plus matrix, preconditioner and Krylov space, for nodes the bodies cover); per
// particle, the views plus, on every rank, the fill of all bodies over the whole grid that
// numbers the particles independently of the decomposition.
constexpr double kBytesPerRank = 50e6;
constexpr double kBytesPerNodeExplicit = 320, kBytesPerNodeImplicitVoid = 450, kBytesPerNodeImplicitActive = 5000;
constexpr double kFillBytesPerParticlePerRank = 80;

// MemAvailable of /proc/meminfo in bytes (0 when unknown).
double availableMemoryBytes() {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kB = 0;
  std::string unit;
  while (meminfo >> key >> kB >> unit)
    if (key == "MemAvailable:") return kB * 1024.0;
  return 0.0;
}

}  // namespace

void addProblemSchema(ParameterList& valid) {
  ParameterList& p = valid.sublist("Problem", false, "what is run and where its outputs go");
  p.set("Name", "impm run", "a name for the run, copied to summary.yaml");
  p.set("Output Directory", "impm-output", "directory for history.csv, summary.yaml, VTU/PVD and plot.png");
  number(p, "Memory Limit GB", 0.0,
         "a deck whose estimated memory (grid and particles, over all ranks) exceeds this is rejected before "
         "anything is allocated; 0: the MemAvailable of the machine rank 0 runs on (/proc/meminfo)");
}

void addOutputSchema(ParameterList& valid) {
  ParameterList& p = valid.sublist("Output", false, "what is written");
  p.set("History Interval", 10, "steps between rows of history.csv");
  p.set("History Digits", 10,
        "significant digits of the values in history.csv (1 to 17; 17 writes every double exactly)");
  p.set("VTK Interval", 0, "steps between VTU particle files (0: first and last step only)");
  p.set("Plot", true, "write plot.png (computed against exact) with python3-matplotlib");
  p.set("Progress", true, "print a progress line with ETA on runs longer than a few seconds");
  p.set("Checkpoint Interval", 0,
        "steps between checkpoints (0: none): every particle field, the integrator's state and the history rows "
        "so far, in OUTPUT/checkpoint (a link to OUTPUT/checkpoint_<step>; only the latest is kept, written to a "
        "temporary directory and renamed when complete). `impm DECK --restart OUTPUT/checkpoint` continues from it: "
        "the deck must be the same except Output, Decomposition, Problem/Output Directory and Integrator/Number of "
        "Steps; "
        "history.csv is rewritten from the checkpoint's rows and continued, and equals the uninterrupted run's "
        "(bit for bit at the same rank and thread count, except assembled Newton with an iterative linear solver "
        "whose preconditioner is refreshed less often than every step: the restart builds a fresh one). "
        "Independent of History and VTK Interval (a checkpoint holds every history row written before it)");
  p.set("Energy And Momentum", false,
        "add kinetic, strain and total energy and linear momentum columns to history.csv, and their drift to "
        "summary.yaml (Energy, Momentum)");
}

void Simulation::readProblem(const std::string& outputOverride) {
  const ParameterList& problem = deck_.sublist("Problem");
  settings_.problemName = problem.get<std::string>("Name");
  outputDir_ = outputOverride.empty() ? problem.get<std::string>("Output Directory") : outputOverride;
  outputKey_ = outputOverride.empty() ? "'Problem/Output Directory'" : "--output";
  if (outputDir_.empty()) throw DeckError(outputKey_ + " must not be empty");
  // Before any work, on rank 0 (which creates it), the verdict shared by every rank.
  rethrowOnEveryRank(*comm_, comm_->getRank() == 0, [&] { checkOutputDirectory(outputDir_, outputKey_); });
}

// The output intervals: History Interval counts steps between rows (the last step is always
// written), so it is at least 1; 0 has a meaning for VTK (first and last step only) and for
// checkpoints (none); a negative value has none.
void Simulation::readOutputSettings() {
  const ParameterList& out = deck_.sublist("Output");
  const int historyInterval = out.get<int>("History Interval");
  if (historyInterval < 1)
    throw DeckError("'Output/History Interval' must be at least 1 (steps between rows of history.csv), got " +
                    std::to_string(historyInterval));
  const int digits = out.get<int>("History Digits");
  if (digits < 1 || digits > 17)
    throw DeckError("'Output/History Digits' must be from 1 to 17 (significant digits in history.csv), got " +
                    std::to_string(digits));
  if (out.get<int>("VTK Interval") < 0)
    throw DeckError("'Output/VTK Interval' must be 0 (first and last step only) or positive, got " +
                    std::to_string(out.get<int>("VTK Interval")));
  if (out.get<int>("Checkpoint Interval") < 0)
    throw DeckError("'Output/Checkpoint Interval' must be 0 (no checkpoints) or positive, got " +
                    std::to_string(out.get<int>("Checkpoint Interval")));
  settings_.historyInterval = historyInterval;
  settings_.historyDigits = digits;
  settings_.vtkInterval = out.get<int>("VTK Interval");
  settings_.checkpointInterval = out.get<int>("Checkpoint Interval");
  settings_.progress = out.get<bool>("Progress");
}

void Simulation::checkProblemSize(bool implicit) const {
  const bool solid = grid_.dim == 3;
  const std::string cells = std::string(solid ? "'Grid/Cells X' x 'Grid/Cells Y' x 'Grid/Cells Z' = "
                                              : "'Grid/Cells X' x 'Grid/Cells Y' = ") +
                            std::to_string(grid_.nx) + " x " + std::to_string(grid_.ny) +
                            (solid ? " x " + std::to_string(grid_.nz) : std::string());
  const double nodes = (grid_.nx + 1.0) * (grid_.ny + 1.0) * (solid ? grid_.nz + 1.0 : 1.0);
  if (nodes * grid_.dim / 2 > kMaxGridNodes)
    throw DeckError(cells + " makes " + formatNumber(nodes) +
                    " grid nodes, more than impm's 32-bit local indices hold with " + std::to_string(grid_.dim) +
                    " unknowns per node");
  double particles = 0, coveredCells = 0;
  size_t largest = 0;
  for (size_t b = 0; b < bodies_.size(); ++b) {
    particles += estimatedBodyParticles_[b];
    coveredCells += estimatedBodyCells_[b];
    if (estimatedBodyParticles_[b] > estimatedBodyParticles_[largest]) largest = b;
  }
  // The keys that set the largest body's particle count.
  const BodySpec& big = bodies_[largest];
  const std::string key = "'Bodies/" + big.name;
  const std::string source =
      !big.particlesFile.empty() ? key + "/File'"
      : placement_ != Placement::Lattice
          ? key + "' (the Gauss points of 'Method/Shape Function' = " + shape_ + ")"
          : key + "/Particles Per Cell X' x 'Particles Per Cell Y' = " + std::to_string(big.rect.particlesPerCellX) +
                " x " + std::to_string(big.rect.particlesPerCellY);
  if (particles > std::numeric_limits<int>::max())
    throw DeckError("the bodies make an estimated " + formatNumber(particles) + " particles (" + source +
                    "), more than the " + std::to_string(std::numeric_limits<int>::max()) +
                    " that a particle index holds");

  const double limitGB = deck_.sublist("Problem").get<double>("Memory Limit GB");
  if (!(limitGB >= 0)) throw DeckError("'Problem/Memory Limit GB' must not be negative, got " + formatNumber(limitGB));
  const int ranks = comm_->getSize();
  // The implicit figures were measured in 2D; in 3D a node's matrix row couples dim / 2 times
  // more components with (reach)^3 / (reach)^2 more nodes (reach 3 cells for MPM and FE Q4, 5
  // for GIMP, cpGIMP, quadratic B-splines and FE Q9, 7 for cubic B-splines and CPDI), and each particle's
  // dense stiffness block holds (dim x nodes)^2 values (24^2 for MPM, 81^2 for GIMP, quadratic B-splines
  // and Hex27, 192^2 for cubic B-splines and CPDI, 4 nodes per direction; the 2D constants include their blocks).
  const double blockNodes = shapeInfo(shape_).stencilNodes1d, reach = 2.0 * blockNodes - 1.0;
  const double activeScale = solid ? 1.5 * 1.5 * reach : 1.0;
  const double blockBytesPerParticle =
      implicit && solid ? 8.0 * std::pow(grid_.dim * std::pow(blockNodes, grid_.dim), 2) : 0.0;
  const double gridBytes = implicit ? nodes * kBytesPerNodeImplicitVoid +
                                          std::min(nodes, 2 * coveredCells) * kBytesPerNodeImplicitActive * activeScale
                                    : nodes * kBytesPerNodeExplicit;
  const double particleBytes = particles * (ParticleSet::bytesPerParticle(grid_.dim) + blockBytesPerParticle +
                                            kFillBytesPerParticlePerRank * ranks);
  const double needed = ranks * kBytesPerRank + gridBytes + particleBytes;
  auto gigabytes = [](double bytes) { return formatNumber(std::max(0.01, std::round(bytes / 1e7) / 100)) + " GB"; };
  // The machine's memory is read on rank 0 only: every rank takes its verdict.
  rethrowOnEveryRank(*comm_, comm_->getRank() == 0, [&] {
    const double limit = limitGB > 0 ? limitGB * 1e9 : availableMemoryBytes();
    if (limit > 0 && needed > limit)
      throw DeckError("the run needs an estimated " + gigabytes(needed) + " (grid " + gigabytes(gridBytes) + ": " +
                      cells + "; particles " + gigabytes(particleBytes) + ": " + formatNumber(particles) +
                      " particles, the most from " + source + "), more than " +
                      (limitGB > 0 ? "'Problem/Memory Limit GB' = " + formatNumber(limitGB)
                                   : "the " + gigabytes(limit) +
                                         " available (MemAvailable; 'Problem/Memory Limit GB' sets a limit)"));
  });
}

}  // namespace impm
