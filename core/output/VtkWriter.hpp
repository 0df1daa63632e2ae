// ParaView output: particles as VTU (one piece per MPI rank) and a PVD index over time.
#pragma once

#include <string>
#include <vector>

#include "core/ParticleSet.hpp"

namespace impm {

// Writes the rank's particles to `path` (ASCII VTU): positions, displacement, velocity,
// acceleration, stress (xx, yy, xy, zz), mass and volume.
void writeParticlesVtu(const std::string& path, const ParticleSet& ps);

// Appends `value` as printf's "%.10g" writes it (std::to_chars with that precision: the same
// text, without the stream and locale machinery, which cost about ten times as much per number).
// A subnormal number is written as a signed zero while subnormals are flushed (impm's state holds
// none: core/FloatingPoint.hpp).
void appendNumber(std::string& text, double value);

// The .pvd index: one DataSet per (time, rank piece). Rewritten whole on every add so that a
// run that stops early still leaves a readable index.
class PvdIndex {
 public:
  PvdIndex(std::string path, int numRanks) : path_(std::move(path)), ranks_(numRanks) {}
  // `fileStem`: name relative to the index's directory without the "_r<rank>.vtu" suffix.
  void add(double time, const std::string& fileStem);
  static std::string pieceName(const std::string& fileStem, int rank);

 private:
  std::string path_;
  int ranks_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace impm
