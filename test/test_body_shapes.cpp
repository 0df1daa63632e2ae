// Unit tests of the body shapes (physics/BodyShapes.hpp): the lattice fill of a disk and of an
// L-shaped polygon against independent inside tests and exact areas, the exact-volume scaling,
// the slab decomposition across ranks, polygon validation, and the particles CSV file.
#include <Teuchos_UnitTestHarness.hpp>

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <vector>

#include "physics/BodyShapes.hpp"

namespace {

using impm::GridBox;
using impm::ParticlePoint;

const double kPi = std::acos(-1.0);

// The unit square, 20 x 20 cells, 2 x 2 particles per cell: particle sub-boxes 0.025 wide, whose
// centres (0.0125 + k 0.025) lie on none of the shape edges below.
GridBox unitGrid() { return GridBox{0.0, 0.0, 0.05, 0.05, 20, 20}; }
const int kPpc = 2;
const double kThickness = 0.1;
const double kParticleArea = 0.025 * 0.025;

// L shape: [0.1, 0.83] x [0.1, 0.37] joined with [0.1, 0.42] x [0.37, 0.9], counter-clockwise.
std::vector<std::array<double, 2>> lShape() {
  return {{0.1, 0.1}, {0.83, 0.1}, {0.83, 0.37}, {0.42, 0.37}, {0.42, 0.9}, {0.1, 0.9}};
}
const double kLArea = 0.73 * 0.27 + 0.32 * 0.53;

bool inL(double x, double y) {
  return (x >= 0.1 && x <= 0.83 && y >= 0.1 && y <= 0.37) || (x >= 0.1 && x <= 0.42 && y >= 0.37 && y <= 0.9);
}

double totalVolume(const std::vector<ParticlePoint>& pts) {
  double sum = 0;
  for (const ParticlePoint& p : pts) sum += p.volume;
  return sum;
}

// A per-process file name, removed when the test ends.
struct TempFile {
  std::string path;
  explicit TempFile(const std::string& name)
      : path((std::filesystem::temp_directory_path() / ("impm_body_shapes_" + std::to_string(::getpid()) + "_" + name))
                 .string()) {}
  ~TempFile() { std::remove(path.c_str()); }
  void write(const std::string& text) const { std::ofstream(path) << text; }
};

// The message of the std::invalid_argument that f throws, or "" if it throws none.
template <class F>
std::string invalidArgumentMessage(F f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEUCHOS_UNIT_TEST(BodyShapes, DiskFillAndExactVolume) {
  const GridBox g = unitGrid();
  const double cx = 0.25, cy = 0.25, r = 0.2;
  const auto disk = impm::makeEllipse(cx, cy, r, r);
  TEST_FLOATING_EQUALITY(disk->area(), kPi * r * r, 1e-15);

  const auto raw = impm::fillShape(*disk, g, kPpc, kPpc, kThickness, 0, g.nx, false);
  const auto scaled = impm::fillShape(*disk, g, kPpc, kPpc, kThickness, 0, g.nx, true);
  TEST_EQUALITY(raw.size(), scaled.size());
  // Before scaling, the lattice approximates the area to within a few percent: the staircase
  // of a disk 8 particle spacings in radius (here 208 particles for 201.1).
  const double expectedCount = kPi * r * r / kParticleArea;
  TEST_COMPARE(std::abs((double)raw.size() - expectedCount), <=, 0.05 * expectedCount);
  TEST_FLOATING_EQUALITY(raw.front().volume, kParticleArea * kThickness, 1e-14);
  // After it, the total is the exact one.
  TEST_FLOATING_EQUALITY(totalVolume(scaled), kPi * r * r * kThickness, 1e-12);
  for (const ParticlePoint& p : scaled) {
    // Inside by the circle's own formula, not by the shape under test.
    TEST_ASSERT((p.x - cx) * (p.x - cx) + (p.y - cy) * (p.y - cy) <= r * r);
    TEST_FLOATING_EQUALITY(p.lx, 0.0125, 1e-14);
    TEST_FLOATING_EQUALITY(p.ly, 0.0125, 1e-14);
    TEST_EQUALITY(p.volume, scaled.front().volume);
  }
  // Every lattice centre inside the circle is kept: none is missing.
  int inside = 0;
  for (int k = 0; k < 40; ++k)
    for (int l = 0; l < 40; ++l) {
      const double x = 0.0125 + 0.025 * k, y = 0.0125 + 0.025 * l;
      inside += (x - cx) * (x - cx) + (y - cy) * (y - cy) <= r * r;
    }
  TEST_EQUALITY((int)raw.size(), inside);
}

TEUCHOS_UNIT_TEST(BodyShapes, LShapedPolygonFillAndExactVolume) {
  const GridBox g = unitGrid();
  const auto poly = impm::makePolygon(lShape());
  TEST_FLOATING_EQUALITY(poly->area(), kLArea, 1e-13);
  TEST_ASSERT(!poly->contains(0.6, 0.6));  // the notch
  TEST_ASSERT(poly->contains(0.3, 0.6));

  const auto raw = impm::fillShape(*poly, g, kPpc, kPpc, kThickness, 0, g.nx, false);
  const auto scaled = impm::fillShape(*poly, g, kPpc, kPpc, kThickness, 0, g.nx, true);
  TEST_EQUALITY(raw.size(), scaled.size());
  const double expectedCount = kLArea / kParticleArea;
  TEST_COMPARE(std::abs((double)raw.size() - expectedCount), <=, 0.03 * expectedCount);
  TEST_FLOATING_EQUALITY(totalVolume(scaled), kLArea * kThickness, 1e-12);
  for (const ParticlePoint& p : scaled) TEST_ASSERT(inL(p.x, p.y));
  int inside = 0;
  for (int k = 0; k < 40; ++k)
    for (int l = 0; l < 40; ++l) inside += inL(0.0125 + 0.025 * k, 0.0125 + 0.025 * l);
  TEST_EQUALITY((int)raw.size(), inside);
}

TEUCHOS_UNIT_TEST(BodyShapes, TrianglePolygonExactVolume) {
  const GridBox g = unitGrid();
  const auto tri = impm::makePolygon({{0.1, 0.1}, {0.9, 0.2}, {0.3, 0.8}});
  const double area = 0.5 * std::abs(0.8 * 0.7 - 0.1 * 0.2);
  TEST_FLOATING_EQUALITY(tri->area(), area, 1e-13);
  const auto raw = impm::fillShape(*tri, g, kPpc, kPpc, kThickness, 0, g.nx, false);
  TEST_COMPARE(std::abs((double)raw.size() - area / kParticleArea), <=, 0.03 * area / kParticleArea);
  const auto scaled = impm::fillShape(*tri, g, kPpc, kPpc, kThickness, 0, g.nx, true);
  TEST_FLOATING_EQUALITY(totalVolume(scaled), area * kThickness, 1e-12);
}

TEUCHOS_UNIT_TEST(BodyShapes, RectangleOnGridLinesIsUnscaled) {
  const GridBox g{0.0, 0.0, 0.1, 0.05, 10, 8};
  // Cells 2..6 in x, 1..4 in y; 3 x 2 particles per cell.
  const auto rect = impm::makeRectangle(0.2, 0.7, 0.05, 0.25);
  for (bool scale : {false, true}) {
    const auto pts = impm::fillShape(*rect, g, 3, 2, kThickness, 0, g.nx, scale);
    TEST_EQUALITY((int)pts.size(), 5 * 4 * 3 * 2);
    const double dx = 0.1 / 3, dy = 0.05 / 2;
    for (const ParticlePoint& p : pts) {
      TEST_EQUALITY(p.volume, dx * dy * kThickness);  // factor 1 exactly
      TEST_EQUALITY(p.lx, 0.5 * dx);
      TEST_EQUALITY(p.ly, 0.5 * dy);
    }
    // The first particle: the lower-left sub-box centre of cell (2, 1).
    TEST_EQUALITY(pts.front().x, (0.0 + 2 * 0.1) + 0.5 * dx);
    TEST_EQUALITY(pts.front().y, (0.0 + 1 * 0.05) + 0.5 * dy);
  }
}

// Particle Placement: the seed beam's depth, H = 0.5 m over 4 cells with 4 particles
// per cell. The second moment of area b H^3 / 12 sets the bending stiffness; the midpoint rule of
// the Uniform lattice (sub-cells d = H / 16) gets it low by the factor 1 - (d/H)^2, the Gauss
// pairs exactly (they integrate cubics in each half cell). Both keep the volume, so the mass.
TEUCHOS_UNIT_TEST(BodyShapes, GaussPlacementIntegratesTheSecondMomentExactly) {
  const GridBox g{0.0, 0.0, 0.25, 0.125, 8, 4};
  const double length = 2.0, depth = 0.5, yc = 0.25, xc = 1.0;
  const auto beam = impm::makeRectangle(0.0, length, 0.0, depth);
  const double exactI = kThickness * length * depth * depth * depth / 12;     // about y = yc
  const double exactIx = kThickness * depth * length * length * length / 12;  // about x = xc
  auto moments = [&](impm::LatticePoints rule, double& volume, double& iy, double& ix, double& cubic) {
    const auto pts = impm::fillShape(*beam, g, 4, 4, kThickness, 0, g.nx, false, rule);
    TEST_EQUALITY((int)pts.size(), 8 * 4 * 16);
    volume = iy = ix = cubic = 0;
    for (const ParticlePoint& p : pts) {
      TEST_EQUALITY(p.volume, (0.25 / 4) * (0.125 / 4) * kThickness);  // equal volumes
      TEST_ASSERT(beam->contains(p.x, p.y));
      volume += p.volume;
      iy += p.volume * (p.y - yc) * (p.y - yc);
      ix += p.volume * (p.x - xc) * (p.x - xc);
      cubic += p.volume * p.y * p.y * p.y;
    }
  };
  double volume, iy, ix, cubic;
  moments(impm::LatticePoints::Gauss, volume, iy, ix, cubic);
  TEST_FLOATING_EQUALITY(volume, length * depth * kThickness, 1e-14);
  TEST_FLOATING_EQUALITY(iy, exactI, 1e-13);
  TEST_FLOATING_EQUALITY(ix, exactIx, 1e-13);
  TEST_FLOATING_EQUALITY(cubic, kThickness * length * std::pow(depth, 4) / 4, 1e-13);
  moments(impm::LatticePoints::Uniform, volume, iy, ix, cubic);
  TEST_FLOATING_EQUALITY(volume, length * depth * kThickness, 1e-14);
  const double d = 0.125 / 4;
  TEST_FLOATING_EQUALITY(iy, exactI * (1 - (d / depth) * (d / depth)), 1e-13);  // 0.39% low
  TEST_COMPARE(std::abs(iy - exactI) / exactI, >, 3e-3);

  // In a cell: the pairs of the half cells, (2k + 1 +- 1/sqrt(3)) h / 4, first cell first.
  const auto pts = impm::fillShape(*beam, g, 4, 4, kThickness, 0, g.nx, false, impm::LatticePoints::Gauss);
  const double s = 1 / std::sqrt(3.0);
  const double expected[4] = {1 - s, 1 + s, 3 - s, 3 + s};
  for (int b = 0; b < 4; ++b) TEST_FLOATING_EQUALITY(pts[b].y, expected[b] * 0.125 / 4, 1e-14);
  for (int a = 0; a < 4; ++a) TEST_FLOATING_EQUALITY(pts[4 * a].x, expected[a] * 0.25 / 4, 1e-14);

  // A disk keeps its exact area with Gauss pairs too; odd counts have no pairs.
  const GridBox u = unitGrid();
  const auto disk = impm::makeEllipse(0.45, 0.5, 0.3, 0.2);
  const auto diskPts = impm::fillShape(*disk, u, 2, 4, kThickness, 0, u.nx, true, impm::LatticePoints::Gauss);
  TEST_FLOATING_EQUALITY(totalVolume(diskPts), kPi * 0.3 * 0.2 * kThickness, 1e-12);
  for (const ParticlePoint& p : diskPts) TEST_ASSERT(disk->contains(p.x, p.y));
  const std::string odd = invalidArgumentMessage(
      [&] { impm::fillShape(*disk, u, 3, 4, kThickness, 0, u.nx, true, impm::LatticePoints::Gauss); });
  TEST_ASSERT(odd.find("must be even, got 3") != std::string::npos);
}

// A ring (Inner Radius X/Y): the particles lie between the two ellipses, and the fill keeps the
// exact area pi (a b - ai bi); a hole that is not inside the outline is refused.
TEUCHOS_UNIT_TEST(BodyShapes, RingKeepsItsExactArea) {
  const GridBox g = unitGrid();
  const auto ring = impm::makeEllipse(0.5, 0.5, 0.4, 0.3, 0.25, 0.15);
  const auto pts = impm::fillShape(*ring, g, kPpc, kPpc, kThickness, 0, g.nx, true);
  TEST_FLOATING_EQUALITY(totalVolume(pts), kPi * (0.4 * 0.3 - 0.25 * 0.15) * kThickness, 1e-12);
  const auto hole = impm::makeEllipse(0.5, 0.5, 0.25, 0.15);
  for (const ParticlePoint& p : pts) {
    TEST_ASSERT(ring->contains(p.x, p.y));
    TEST_ASSERT(!hole->contains(p.x, p.y));
  }
  TEST_ASSERT(!ring->contains(0.5, 0.5));
  TEST_ASSERT(ring->contains(0.5 + 0.3, 0.5));
  const std::string wide = invalidArgumentMessage([] { impm::makeEllipse(0.5, 0.5, 0.4, 0.3, 0.4, 0.1); });
  TEST_ASSERT(wide.find("inner semi-axes must be positive and below the outer ones") != std::string::npos);
  TEST_THROW(impm::makeEllipse(0.5, 0.5, 0.4, 0.3, 0.2, 0.0), std::invalid_argument);  // one inner axis only
}

TEUCHOS_UNIT_TEST(BodyShapes, SlabsPartitionTheFill) {
  const GridBox g = unitGrid();
  const auto disk = impm::makeEllipse(0.45, 0.5, 0.3, 0.2);
  const auto poly = impm::makePolygon(lShape());
  for (const impm::BodyShape* shape : {disk.get(), poly.get()}) {
    const auto whole = impm::fillShape(*shape, g, kPpc, kPpc, kThickness, 0, g.nx, true);
    for (int k : {0, 5, 7, 13, 20}) {
      const auto left = impm::fillShape(*shape, g, kPpc, kPpc, kThickness, 0, k, true);
      const auto right = impm::fillShape(*shape, g, kPpc, kPpc, kThickness, k, g.nx, true);
      const double xCut = g.x0 + k * g.hx;
      for (const ParticlePoint& p : left) TEST_COMPARE(p.x, <, xCut);
      for (const ParticlePoint& p : right) TEST_COMPARE(p.x, >, xCut);
      // Column-major order: the union, left then right, is the whole fill, bit for bit.
      TEST_EQUALITY(left.size() + right.size(), whole.size());
      if (left.size() + right.size() != whole.size()) continue;
      for (size_t n = 0; n < whole.size(); ++n) {
        const ParticlePoint& p = n < left.size() ? left[n] : right[n - left.size()];
        TEST_EQUALITY(p.x, whole[n].x);
        TEST_EQUALITY(p.y, whole[n].y);
        TEST_EQUALITY(p.volume, whole[n].volume);  // the same scale factor on every slab
      }
    }
  }
  // A slab the shape does not reach is empty, not an error.
  const auto small = impm::makeEllipse(0.25, 0.25, 0.2, 0.2);
  TEST_EQUALITY(impm::fillShape(*small, g, kPpc, kPpc, kThickness, 15, 20, true).size(), (size_t)0);
}

TEUCHOS_UNIT_TEST(BodyShapes, PolygonOrientationDoesNotMatter) {
  const GridBox g = unitGrid();
  auto cw = lShape();
  std::reverse(cw.begin(), cw.end());
  std::rotate(cw.begin(), cw.begin() + 2, cw.end());  // and another first vertex
  const auto a = impm::fillShape(*impm::makePolygon(lShape()), g, kPpc, kPpc, kThickness, 0, g.nx, true);
  const auto b = impm::fillShape(*impm::makePolygon(cw), g, kPpc, kPpc, kThickness, 0, g.nx, true);
  TEST_EQUALITY(a.size(), b.size());
  if (a.size() != b.size()) return;
  for (size_t n = 0; n < a.size(); ++n) {
    TEST_EQUALITY(a[n].x, b[n].x);
    TEST_EQUALITY(a[n].y, b[n].y);
    // The shoelace sum runs in another order: the area may differ in the last bit.
    TEST_FLOATING_EQUALITY(a[n].volume, b[n].volume, 1e-14);
  }
}

TEUCHOS_UNIT_TEST(BodyShapes, InvalidPolygonsThrow) {
  using V = std::vector<std::array<double, 2>>;
  // Bow-tie: edges 1-2 and 3-4 cross at (0.5, 0.5).
  const std::string bowTie = invalidArgumentMessage([] { impm::makePolygon(V{{0, 0}, {1, 1}, {1, 0}, {0, 1}}); });
  TEST_ASSERT(bowTie.find("edges 1-2 and 3-4 cross") != std::string::npos);
  // A vertex touching a non-adjacent edge is not simple either: vertex 4 lies on edge 1-2.
  const std::string touch = invalidArgumentMessage([] {
    impm::makePolygon(V{{0, 0}, {4, 0}, {4, 4}, {2, 0}, {0, 4}});
  });
  TEST_ASSERT(touch.find("edges 1-2 and 3-4 cross") != std::string::npos);
  const std::string two = invalidArgumentMessage([] { impm::makePolygon(V{{0, 0}, {1, 0}}); });
  TEST_ASSERT(two.find("at least 3 vertices, got 2") != std::string::npos);
  const std::string collinear = invalidArgumentMessage([] { impm::makePolygon(V{{0, 0}, {1, 1}, {2, 2}}); });
  TEST_ASSERT(collinear.find("area is zero") != std::string::npos);
  TEST_THROW(impm::makePolygon(V{{0, 0}, {1, 0}, {1, 0}, {0, 1}}), std::invalid_argument);  // repeated vertex
  TEST_THROW(impm::makePolygon(V{{0, 0}, {1, 0}, {1, 1}, {0, 0}}), std::invalid_argument);  // closed by repeat
  TEST_THROW(impm::makePolygon(V{{0, 0}, {2, 0}, {1, 0}, {1, 1}}), std::invalid_argument);  // folds back
  TEST_THROW(impm::makePolygon(V{{0, 0}, {1, 0}, {0, NAN}}), std::invalid_argument);
  // A valid concave polygon passes.
  TEST_NOTHROW(impm::makePolygon(lShape()));
}

TEUCHOS_UNIT_TEST(BodyShapes, InvalidShapesAndFillsThrow) {
  const GridBox g = unitGrid();
  const std::string semi = invalidArgumentMessage([] { impm::makeEllipse(0.5, 0.5, 0.2, 0.0); });
  TEST_ASSERT(semi.find("semi-axes must be positive") != std::string::npos);
  TEST_THROW(impm::makeRectangle(0.5, 0.5, 0.0, 1.0), std::invalid_argument);
  TEST_THROW(impm::makeRectangle(0.0, 1.0, 0.7, 0.2), std::invalid_argument);
  // Sticking out of the grid.
  const auto outside = impm::makeEllipse(0.9, 0.5, 0.2, 0.2);
  TEST_THROW(impm::fillShape(*outside, g, kPpc, kPpc, kThickness, 0, g.nx, true), std::invalid_argument);
  // Too small to hold any lattice centre: scaling would divide by zero.
  const auto tiny = impm::makeEllipse(0.05, 0.05, 0.001, 0.001);
  TEST_THROW(impm::fillShape(*tiny, g, kPpc, kPpc, kThickness, 0, g.nx, true), std::invalid_argument);
  const auto disk = impm::makeEllipse(0.5, 0.5, 0.2, 0.2);
  TEST_THROW(impm::fillShape(*disk, g, 0, kPpc, kThickness, 0, g.nx, true), std::invalid_argument);
  TEST_THROW(impm::fillShape(*disk, g, kPpc, kPpc, 0.0, 0, g.nx, true), std::invalid_argument);
  TEST_THROW(impm::fillShape(*disk, g, kPpc, kPpc, kThickness, 5, 21, true), std::invalid_argument);
}

TEUCHOS_UNIT_TEST(BodyShapes, ParticlesFileRoundTrip) {
  // Values whose decimal form is long: the disk's scaled volumes, thirds, a subnormal.
  auto pts = impm::fillShape(*impm::makeEllipse(0.25, 0.25, 0.2, 0.2), unitGrid(), kPpc, kPpc, kThickness, 0, 20, true);
  ParticlePoint odd;
  odd.x = -1.0 / 3, odd.y = 4.9e-320, odd.volume = 2.0 / 3;
  pts.push_back(odd);

  const TempFile file2("roundtrip2.csv");
  impm::writeParticlesFile(file2.path, pts, 2);
  const auto back = impm::readParticlesFile(file2.path, 2, kThickness);
  TEST_EQUALITY(back.size(), pts.size());
  if (back.size() != pts.size()) return;
  for (size_t n = 0; n < pts.size(); ++n) {
    TEST_EQUALITY(back[n].x, pts[n].x);
    TEST_EQUALITY(back[n].y, pts[n].y);
    TEST_EQUALITY(back[n].volume, pts[n].volume);
    TEST_EQUALITY(back[n].z, 0.0);
    TEST_EQUALITY(back[n].lz, 0.0);
    // The square of the particle's own area.
    TEST_FLOATING_EQUALITY(4 * back[n].lx * back[n].ly * kThickness, pts[n].volume, 1e-14);
  }

  const TempFile file3("roundtrip3.csv");
  std::vector<ParticlePoint> pts3(2);
  pts3[0].x = 0.1, pts3[0].y = 0.2, pts3[0].z = 1.0 / 7, pts3[0].volume = 8e-3;
  pts3[1].x = -3, pts3[1].y = 1e10, pts3[1].z = -0.0, pts3[1].volume = 1.0 / 3;
  impm::writeParticlesFile(file3.path, pts3, 3);
  const auto back3 = impm::readParticlesFile(file3.path, 3, kThickness);
  TEST_EQUALITY(back3.size(), (size_t)2);
  if (back3.size() != 2) return;
  for (size_t n = 0; n < 2; ++n) {
    TEST_EQUALITY(back3[n].x, pts3[n].x);
    TEST_EQUALITY(back3[n].y, pts3[n].y);
    TEST_EQUALITY(back3[n].z, pts3[n].z);
    TEST_EQUALITY(back3[n].volume, pts3[n].volume);
  }
  TEST_FLOATING_EQUALITY(back3[0].lx, 0.1, 1e-14);  // cube of side 0.2
  TEST_FLOATING_EQUALITY(back3[0].lz, 0.1, 1e-14);
}

TEUCHOS_UNIT_TEST(BodyShapes, ParticlesFileCommentsAndHeader) {
  const TempFile file("comments.csv");
  file.write("# made by hand\n\nx, y, volume\n0.5, 0.25, 4e-4\r\n# another comment\n  1.5 ,0.75,1e-4\n");
  const auto pts = impm::readParticlesFile(file.path, 2, 1.0);
  TEST_EQUALITY(pts.size(), (size_t)2);
  if (pts.size() != 2) return;
  TEST_EQUALITY(pts[0].x, 0.5);
  TEST_EQUALITY(pts[0].volume, 4e-4);
  TEST_FLOATING_EQUALITY(pts[0].lx, 0.01, 1e-14);
  TEST_EQUALITY(pts[1].y, 0.75);
  // Without a header too.
  file.write("0.5,0.25,4e-4\n");
  TEST_EQUALITY(impm::readParticlesFile(file.path, 2, 1.0).size(), (size_t)1);
}

TEUCHOS_UNIT_TEST(BodyShapes, ParticlesFileBadRowsNameTheLine) {
  const TempFile file("bad.csv");
  // Each bad row is on line 4, after a header, a good row and a comment or blank line.
  const char* bad[] = {
      "x,y,volume\n0,0,1e-4\n# c\n0.1, 0.2\n",           // 2 columns
      "x,y,volume\n0,0,1e-4\n\n0.1, abc, 1e-4\n",        // not a number
      "x,y,volume\n0,0,1e-4\n# c\n0.1, 0.2, -1e-4\n",    // negative volume
      "x,y,volume\n0,0,1e-4\n# c\n0.1, 0.2, 0\n",        // zero volume
      "x,y,volume\n0,0,1e-4\n# c\n0.1, 0.2, inf\n",      // not finite
      "x,y,volume\n0,0,1e-4\n# c\n0.1, 0.2, 1e-4, 0\n",  // 4 columns
      "x,y,volume\n0,0,1e-4\n# c\nx,y,volume\n",         // a header that is not the first line
  };
  for (const char* text : bad) {
    file.write(text);
    const std::string message = invalidArgumentMessage([&] { impm::readParticlesFile(file.path, 2, 1.0); });
    TEST_ASSERT(message.find("line 4") != std::string::npos);
    TEST_ASSERT(message.find(file.path) != std::string::npos);
  }
  file.write("x,y,volume\n0,0,1e-4\n# c\n0.1, 0.2\n");
  const std::string columns = invalidArgumentMessage([&] { impm::readParticlesFile(file.path, 2, 1.0); });
  TEST_ASSERT(columns.find("expected 3 columns (x, y, volume), got 2") != std::string::npos);
  // A 2D file read as 3D lacks a column.
  file.write("0,0,1e-4\n");
  TEST_THROW(impm::readParticlesFile(file.path, 3, 1.0), std::invalid_argument);
  file.write("# nothing\n");
  TEST_THROW(impm::readParticlesFile(file.path, 2, 1.0), std::invalid_argument);
  TEST_THROW(impm::readParticlesFile(file.path + ".missing", 2, 1.0), std::invalid_argument);
}

TEUCHOS_UNIT_TEST(BodyShapes, ParsePolygonVertices) {
  using V = std::vector<std::array<double, 2>>;
  const V square{{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  TEST_ASSERT(impm::parsePolygonVertices("0, 0; 1, 0; 1, 1; 0, 1") == square);
  TEST_ASSERT(impm::parsePolygonVertices("0 0;1 0;  1\t1 ; 0 1;") == square);
  TEST_ASSERT(impm::parsePolygonVertices("-1.5e-1, 2.25") == (V{{-0.15, 2.25}}));
  const std::string third = invalidArgumentMessage([] { impm::parsePolygonVertices("0, 0; 1, 0; 1 x; 0, 1"); });
  TEST_ASSERT(third.find("vertex 3") != std::string::npos);
  const std::string second = invalidArgumentMessage([] { impm::parsePolygonVertices("0, 0; 1, 0, 2; 1, 1"); });
  TEST_ASSERT(second.find("vertex 2") != std::string::npos);
  TEST_THROW(impm::parsePolygonVertices("0, 0; ; 1, 1"), std::invalid_argument);   // empty vertex
  TEST_THROW(impm::parsePolygonVertices("0, 0; 1; 1, 1"), std::invalid_argument);  // one coordinate
  TEST_THROW(impm::parsePolygonVertices("0 0 0; 1 0; 1 1"), std::invalid_argument);
  TEST_THROW(impm::parsePolygonVertices(""), std::invalid_argument);
}
