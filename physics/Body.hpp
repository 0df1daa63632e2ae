// Bodies: named pieces of material, each a shape filled with particles (a lattice of
// Particles Per Cell points in each cell the shape covers, at sub-box centres or Gauss pairs,
// see LatticePoints; or the FE reference's Gauss points), or the particles of a file. Every particle carries its body
// id, its material id and a global id that does not depend on the MPI decomposition (the order of the whole fill).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/ParticleSet.hpp"
#include "physics/BodyShapes.hpp"
#include "physics/TimeFunction.hpp"
#include "physics/LatticePoints.hpp"
#include "physics/Materials.hpp"

namespace impm {

// Where the particles sit: a regular lattice per cell (MPM, GIMP), or at the Gauss points of
// the finite-element reference: 2 x 2 per cell (Q4) or 3 x 3 per element of 2 x 2 cells (Q9),
// each with its Gauss weight times the Jacobian as volume.
enum class Placement { Lattice, GaussQ4, GaussQ9 };

// An axis-aligned rectangle (3D: box) of material (its faces carry constraints and tractions).
struct RectangularBody {
  double xMin = 0, xMax = 1, yMin = 0, yMax = 1;
  int particlesPerCellX = 2, particlesPerCellY = 2;
  double thickness = 1.0;  // out of plane (2D)
  Placement placement = Placement::Lattice;
  // 3D only (last, so that 2D aggregate initialisers keep their meaning).
  double zMin = 0, zMax = 1;
  int particlesPerCellZ = 2;
  LatticePoints latticePoints = LatticePoints::Uniform;  // where a Lattice placement puts them in a cell

  double length() const { return xMax - xMin; }
  double height() const { return yMax - yMin; }
  double depth() const { return zMax - zMin; }
  double lo(int d) const { return d == 0 ? xMin : d == 1 ? yMin : zMin; }
  double hi(int d) const { return d == 0 ? xMax : d == 1 ? yMax : zMax; }
};

struct BodySpec {
  std::string name;
  std::shared_ptr<const BodyShape> shape;              // null for a Particles File body
  bool rectangle = false;                              // the shape is `rect` (faces, FE placement)
  RectangularBody rect;                                // extents and particles per cell (all shapes use its ppc)
  std::string particlesFile;                           // Particles File bodies
  int material = 0;                                    // index into the material table
  double velocityX = 0, velocityY = 0, velocityZ = 0;  // initial velocity
  // Initial rigid rotation: the particles start with velocity + omega x (x - rotationCenter).
  std::array<double, 3> angularVelocity{};  // omega (x, y, z); 2D: z only
  std::array<double, 3> rotationCenter{};
  // A rigid body moves with the velocity rigidVelocity * motion(t) (its particles start with the
  // velocity at t = 0); multi-field contact holds its field to that motion.
  bool rigid = false;
  std::array<double, 3> rigidVelocity{};
  std::array<double, 3> rigidNormal{};  // unit outward normal of a plane rigid body (0: none)
  TimeFunction motion;
  // Geostatic initial stress (Initial Stress = Geostatic): sigma_yy = -rho g (surfaceY - y),
  // sigma_xx = sigma_zz = k0 sigma_yy, with g the deck's gravity along -y.
  bool geostatic = false;
  double k0 = 0, surfaceY = 0;
};

// The particles of all bodies that lie in this rank's cell columns, in the grid's dimension (3D:
// Rectangle bodies are boxes with Z Min, Z Max; Ellipse and Polygon are 2D shapes). Where shapes overlap, a
// body's particles replace those of the bodies listed before it inside its shape (an
// inclusion is written after the plate it sits in). Throws std::invalid_argument naming the
// body when one has no particle inside the grid.
ParticleSet createParticles(const std::vector<BodySpec>& bodies, const Materials& materials,
                            const GridDistribution& dist, Placement placement, double thickness);

// Sets each particle's affine velocity (ps.affine, allocated) to its body's initial rotation, the
// skew matrix C with C r = omega x r (zero for a body that does not rotate).
void setRotationAffineVelocity(ParticleSet& ps, const std::vector<BodySpec>& bodies);

// One rectangular body of material 0 (tests and benchmarks).
ParticleSet createParticles(const RectangularBody& body, const Materials& materials, const GridDistribution& dist);

}  // namespace impm
