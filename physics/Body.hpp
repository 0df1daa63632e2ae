// The material body: a rectangle of the grid filled with particles, and how to create them.
#pragma once

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "physics/LinearElastic.hpp"

namespace impm {

// Where the particles sit: a regular lattice per cell (MPM, GIMP), or at the Gauss points of
// the finite-element reference: 2 x 2 per cell (Q4) or 3 x 3 per element of 2 x 2 cells (Q9),
// each with its Gauss weight times the Jacobian as volume.
enum class Placement { Lattice, GaussQ4, GaussQ9 };

struct RectangularBody {
  double xMin = 0, xMax = 1, yMin = 0, yMax = 1;
  int particlesPerCellX = 2, particlesPerCellY = 2;
  double thickness = 1.0;  // out of plane
  Placement placement = Placement::Lattice;

  double length() const { return xMax - xMin; }
  double height() const { return yMax - yMin; }
};

// Particles of the body in the cell columns this rank owns: a regular ppcx x ppcy lattice per
// cell, each particle the centre of its own sub-box (its GIMP domain), or Gauss points.
ParticleSet createParticles(const RectangularBody& body, const LinearElastic& mat, const GridDistribution& dist);

}  // namespace impm
