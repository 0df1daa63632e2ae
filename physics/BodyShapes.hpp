// Shapes of a body (rectangle, ellipse, polygon) and the material points that fill them on the
// 2D structured grid, and particles read from (or written to) a CSV file. Plain C++17, no Kokkos
// or Trilinos: the caller turns the points into a ParticleSet.
//
// Errors in the input (a bad shape, a bad file row) throw std::invalid_argument with a message
// naming the problem and its values; the caller prefixes the deck key.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "physics/LatticePoints.hpp"

namespace impm {

// One material point: centre, half sizes of its GIMP domain, volume. z = lz = 0 in 2D.
struct ParticlePoint {
  double x = 0, y = 0, z = 0;
  double lx = 0, ly = 0, lz = 0;
  double volume = 0;
};

// The 2D structured grid: node (i, j) at (x0 + i hx, y0 + j hy), nx x ny cells.
struct GridBox {
  double x0 = 0, y0 = 0, hx = 1, hy = 1;
  int nx = 1, ny = 1;
};

// A closed region of the plane. Points exactly on the boundary may fall either way; the lattice
// fill puts candidates at sub-box centres, which lie on the boundary only by coincidence.
class BodyShape {
 public:
  virtual ~BodyShape() = default;
  virtual bool contains(double x, double y) const = 0;
  virtual double area() const = 0;  // exact area
  virtual void boundingBox(double& xlo, double& xhi, double& ylo, double& yhi) const = 0;
  virtual std::string describe() const = 0;  // for messages
};

// Axis-aligned rectangle [xMin, xMax] x [yMin, yMax] (closed).
std::unique_ptr<BodyShape> makeRectangle(double xMin, double xMax, double yMin, double yMax);

// Ellipse with centre (cx, cy) and semi-axes a (along x), b (along y); a disk when a == b. With
// inner semi-axes (both > 0, below a and b), a ring: the ellipse less the inner one of the same centre.
std::unique_ptr<BodyShape> makeEllipse(double cx, double cy, double a, double b, double innerA = 0.0,
                                       double innerB = 0.0);

// Simple polygon, vertices in either orientation, not closed (the last vertex is not a repeat of
// the first). Rejected: fewer than 3 vertices, a non-finite coordinate, repeated consecutive
// vertices, non-adjacent edges that cross or touch (checked first: a bow-tie has zero signed
// area), zero area. Inside test: even-odd rule (the same as winding for a simple polygon).
std::unique_ptr<BodyShape> makePolygon(const std::vector<std::array<double, 2>>& vertices);

// Vertices from a deck string: vertices separated by ';', the two coordinates of a vertex by ','
// or whitespace, e.g. "0, 0; 1, 0; 1, 1; 0, 1" or "0 0; 1 0; 1 1". A trailing ';' is allowed.
// A malformed vertex throws naming its 1-based index. The vertex count is makePolygon's to check.
std::vector<std::array<double, 2>> parsePolygonVertices(const std::string& text);

// Lattice fill of a shape. Each grid cell gets ppx x ppy candidates at the positions of `points`
// (Uniform: the centres of ppx x ppy sub-boxes; Gauss: the Gauss pairs of ppx/2 x ppy/2
// sub-boxes, ppx and ppy even), each with volume (hx/ppx)(hy/ppy) thickness and a domain of that
// size centred on it (half sizes hx/(2 ppx), hy/(2 ppy)); a candidate is kept if the shape
// contains it. Only cell columns [colBegin, colEnd) (an MPI rank's slab) are filled, in the order
// column, row, then x, y within the cell.
//
// Exact volume assigned: with scaleToExactArea, every kept volume is multiplied by one factor,
// area * thickness / (sum of the unscaled volumes), so that the body's total volume (and mass) is
// the shape's exact one instead of the lattice's staircase approximation. The factor is computed
// from the count over the WHOLE grid, so it is the same on every rank. A factor within 1e-12 of 1
// (the lattice already fills the shape exactly, as a rectangle on grid lines does) is taken as
// 1 exactly, so that rounding does not perturb such volumes.
//
// Throws if ppx, ppy (odd for Gauss), thickness, the grid or the column range are invalid, if the shape's
// bounding box extends beyond the grid, or if no candidate of the whole grid lies inside it.
std::vector<ParticlePoint> fillShape(const BodyShape& shape, const GridBox& grid, int ppx, int ppy, double thickness,
                                     int colBegin, int colEnd, bool scaleToExactArea,
                                     LatticePoints points = LatticePoints::Uniform);

// Particles from a CSV file: x, y, volume per row (dim 2) or x, y, z, volume (dim 3). Blank lines
// and lines starting with '#' are skipped, and so is the first other line if none of its fields
// is a number (a header). Any other bad row (wrong column count, a non-numeric or non-finite
// field, a volume not positive) throws naming the file and the 1-based line number. Volumes are
// taken as given. Half sizes: the square (2D, l = 0.5 sqrt(volume / thickness)) or cube (3D,
// l = 0.5 cbrt(volume)) of the particle's own volume. thickness is used in 2D only.
std::vector<ParticlePoint> readParticlesFile(const std::string& path, int dim, double thickness);

// Writes the CSV readParticlesFile reads: header "x,y,volume" (or "x,y,z,volume"), %.17g, so a
// round trip is bit-identical. Throws std::runtime_error if the file cannot be written.
void writeParticlesFile(const std::string& path, const std::vector<ParticlePoint>& points, int dim);

}  // namespace impm
