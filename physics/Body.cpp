#include "physics/Body.hpp"

#include <cmath>
#include <vector>

namespace impm {

namespace {
// 1D Gauss-Legendre rule on [-1, 1].
void gaussRule(int n, std::vector<double>& xi, std::vector<double>& w) {
  if (n == 2) {
    xi = {-1.0 / std::sqrt(3.0), 1.0 / std::sqrt(3.0)};
    w = {1.0, 1.0};
  } else {
    xi = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
    w = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  }
}
}  // namespace

ParticleSet createParticles(const RectangularBody& body, const LinearElastic& mat, const GridDistribution& dist) {
  const StructuredGrid& g = dist.grid();
  const int cellI0 = (int)std::lround((body.xMin - g.x0) / g.hx), cellI1 = (int)std::lround((body.xMax - g.x0) / g.hx);
  const int cellJ0 = (int)std::lround((body.yMin - g.y0) / g.hy), cellJ1 = (int)std::lround((body.yMax - g.y0) / g.hy);
  const int iBegin = std::max(cellI0, dist.cellColumnBegin()), iEnd = std::min(cellI1, dist.cellColumnEnd());

  // Points (x, y, half sizes, volume) of this rank, in its own cell columns.
  struct Point { double x, y, lx, ly, vol; };
  std::vector<Point> points;
  if (body.placement == Placement::Lattice) {
    const int ppx = body.particlesPerCellX, ppy = body.particlesPerCellY;
    const double dx = g.hx / ppx, dy = g.hy / ppy;
    const double vol = dx * dy * body.thickness;
    for (int i = iBegin; i < iEnd; ++i)
      for (int j = cellJ0; j < cellJ1; ++j)
        for (int a = 0; a < ppx; ++a)
          for (int b = 0; b < ppy; ++b)
            points.push_back({g.nodeX(i) + (a + 0.5) * dx, g.nodeY(j) + (b + 0.5) * dy, 0.5 * dx, 0.5 * dy, vol});
  } else {
    // Elements: one cell (Q4) or 2 x 2 cells (Q9); a Gauss point belongs to the rank owning
    // the cell column it lies in (the Q9 centre line lies on a cell line: the right cell).
    const bool q9 = body.placement == Placement::GaussQ9;
    const int span = q9 ? 2 : 1;
    std::vector<double> xi, w;
    gaussRule(q9 ? 3 : 2, xi, w);
    const double ex = 0.5 * span * g.hx, ey = 0.5 * span * g.hy;  // element half sizes
    for (int i = cellI0; i < cellI1; i += span)
      for (int j = cellJ0; j < cellJ1; j += span) {
        const double cx = g.nodeX(i) + ex, cy = g.nodeY(j) + ey;
        for (size_t a = 0; a < xi.size(); ++a)
          for (size_t b = 0; b < xi.size(); ++b) {
            const double px = cx + xi[a] * ex, py = cy + xi[b] * ey;
            const int column = std::min(g.nx - 1, (int)std::floor((px - g.x0) / g.hx + 1e-9));
            if (column < dist.cellColumnBegin() || column >= dist.cellColumnEnd()) continue;
            points.push_back({px, py, 0.0, 0.0, w[a] * w[b] * ex * ey * body.thickness});
          }
      }
  }

  const int n = (int)points.size();
  ParticleSet ps(n);
  auto x = Kokkos::create_mirror_view(ps.x);
  auto hs = Kokkos::create_mirror_view(ps.halfSize);
  auto m = Kokkos::create_mirror_view(ps.mass);
  auto V0 = Kokkos::create_mirror_view(ps.volume0);
  for (int p = 0; p < n; ++p) {
    x(p, 0) = points[p].x;
    x(p, 1) = points[p].y;
    hs(p, 0) = points[p].lx;
    hs(p, 1) = points[p].ly;
    m(p) = mat.density * points[p].vol;
    V0(p) = points[p].vol;
  }
  Kokkos::deep_copy(ps.x, x);
  Kokkos::deep_copy(ps.x0, x);
  Kokkos::deep_copy(ps.halfSize, hs);
  Kokkos::deep_copy(ps.mass, m);
  Kokkos::deep_copy(ps.volume0, V0);
  Kokkos::deep_copy(ps.volume, V0);
  return ps;
}

}  // namespace impm
