#include "physics/Body.hpp"

#include <cmath>
#include <vector>

namespace impm {

ParticleSet createParticles(const RectangularBody& body, const LinearElastic& mat, const GridDistribution& dist) {
  const StructuredGrid& g = dist.grid();
  const int cellI0 = (int)std::lround((body.xMin - g.x0) / g.hx), cellI1 = (int)std::lround((body.xMax - g.x0) / g.hx);
  const int cellJ0 = (int)std::lround((body.yMin - g.y0) / g.hy), cellJ1 = (int)std::lround((body.yMax - g.y0) / g.hy);
  const int iBegin = std::max(cellI0, dist.cellColumnBegin()), iEnd = std::min(cellI1, dist.cellColumnEnd());
  const int ppx = body.particlesPerCellX, ppy = body.particlesPerCellY;
  const int n = std::max(0, iEnd - iBegin) * (cellJ1 - cellJ0) * ppx * ppy;

  ParticleSet ps(n);
  auto x = Kokkos::create_mirror_view(ps.x);
  auto hs = Kokkos::create_mirror_view(ps.halfSize);
  auto m = Kokkos::create_mirror_view(ps.mass);
  auto V0 = Kokkos::create_mirror_view(ps.volume0);
  const double dx = g.hx / ppx, dy = g.hy / ppy;
  const double vol = dx * dy * body.thickness;
  int p = 0;
  for (int i = iBegin; i < iEnd; ++i)
    for (int j = cellJ0; j < cellJ1; ++j)
      for (int a = 0; a < ppx; ++a)
        for (int b = 0; b < ppy; ++b, ++p) {
          x(p, 0) = g.nodeX(i) + (a + 0.5) * dx;
          x(p, 1) = g.nodeY(j) + (b + 0.5) * dy;
          hs(p, 0) = 0.5 * dx;
          hs(p, 1) = 0.5 * dy;
          m(p) = mat.density * vol;
          V0(p) = vol;
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
