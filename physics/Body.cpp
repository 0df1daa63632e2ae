#include "physics/Body.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

namespace impm {

namespace {
// Gauss points of the elements of a rectangle (3D: box) on grid lines: one cell (Q4, Hex8) or
// 2 x 2 (x 2) cells (Q9, Hex27).
std::vector<ParticlePoint> gaussPoints(const RectangularBody& body, const StructuredGrid& g, bool q9,
                                       double thickness) {
  const int cellI0 = (int)std::lround((body.xMin - g.x0) / g.hx), cellI1 = (int)std::lround((body.xMax - g.x0) / g.hx);
  const int cellJ0 = (int)std::lround((body.yMin - g.y0) / g.hy), cellJ1 = (int)std::lround((body.yMax - g.y0) / g.hy);
  const bool solid = g.dim == 3;
  const int cellK0 = solid ? (int)std::lround((body.zMin - g.z0) / g.hz) : 0;
  const int cellK1 = solid ? (int)std::lround((body.zMax - g.z0) / g.hz) : 1;
  const int span = q9 ? 2 : 1;
  std::vector<double> xi, w;
  gaussLegendre(q9 ? 3 : 2, xi, w);
  const double ex = 0.5 * span * g.hx, ey = 0.5 * span * g.hy, ez = 0.5 * span * g.hz;  // element half sizes
  const size_t nzq = solid ? xi.size() : 1;
  std::vector<ParticlePoint> points;
  for (int i = cellI0; i < cellI1; i += span)
    for (int j = cellJ0; j < cellJ1; j += span)
      for (int k = cellK0; k < cellK1; k += span) {
        const double cx = g.nodeX(i) + ex, cy = g.nodeY(j) + ey, cz = solid ? g.nodeZ(k) + ez : 0.0;
        for (size_t a = 0; a < xi.size(); ++a)
          for (size_t b = 0; b < xi.size(); ++b)
            for (size_t c = 0; c < nzq; ++c) {
              const double weight = solid ? w[a] * w[b] * w[c] * ex * ey * ez : w[a] * w[b] * ex * ey * thickness;
              points.push_back(
                  {cx + xi[a] * ex, cy + xi[b] * ey, solid ? cz + xi[c] * ez : 0.0, 0.0, 0.0, 0.0, weight});
            }
      }
  return points;
}

// Lattice fill of a box on a 3D grid: each cell the box covers gets ppx x ppy x ppz particles
// at the positions of the body's LatticePoints (sub-box centres or Gauss pairs), each with
// volume hx hy hz / (ppx ppy ppz); those inside the box are kept (in the order column, row,
// layer, then x, y, z within the cell).
std::vector<ParticlePoint> fillBox(const RectangularBody& body, const StructuredGrid& g) {
  const int px = body.particlesPerCellX, py = body.particlesPerCellY, pz = body.particlesPerCellZ;
  if (px < 1 || py < 1 || pz < 1)
    throw std::invalid_argument("particles per cell must be at least 1, got " + std::to_string(px) + " x " +
                                std::to_string(py) + " x " + std::to_string(pz));
  const std::vector<double> ox = latticeOffsets(body.latticePoints, px), oy = latticeOffsets(body.latticePoints, py),
                            oz = latticeOffsets(body.latticePoints, pz);
  const double dx = g.hx / px, dy = g.hy / py, dz = g.hz / pz;
  auto range = [](double lo, double hi, double origin, double h, int n, int& b, int& e) {
    b = std::max(0, (int)std::floor((lo - origin) / h) - 1);
    e = std::min(n, (int)std::floor((hi - origin) / h) + 2);
  };
  int i0, i1, j0, j1, k0, k1;
  range(body.xMin, body.xMax, g.x0, g.hx, g.nx, i0, i1);
  range(body.yMin, body.yMax, g.y0, g.hy, g.ny, j0, j1);
  range(body.zMin, body.zMax, g.z0, g.hz, g.nz, k0, k1);
  std::vector<ParticlePoint> points;
  for (int i = i0; i < i1; ++i)
    for (int j = j0; j < j1; ++j)
      for (int k = k0; k < k1; ++k)
        for (int a = 0; a < px; ++a)
          for (int b = 0; b < py; ++b)
            for (int c = 0; c < pz; ++c) {
              ParticlePoint p;
              p.x = g.nodeX(i) + ox[a] * dx;
              p.y = g.nodeY(j) + oy[b] * dy;
              p.z = g.nodeZ(k) + oz[c] * dz;
              if (p.x < body.xMin || p.x > body.xMax || p.y < body.yMin || p.y > body.yMax || p.z < body.zMin ||
                  p.z > body.zMax)
                continue;
              p.lx = 0.5 * dx;
              p.ly = 0.5 * dy;
              p.lz = 0.5 * dz;
              p.volume = dx * dy * dz;
              points.push_back(p);
            }
  return points;
}

// omega x r as the skew matrix of omega: C r = omega x r.
void rotationMatrix(const std::array<double, 3>& omega, double (&C)[3][3]) {
  C[0][0] = 0.0;
  C[0][1] = -omega[2];
  C[0][2] = omega[1];
  C[1][0] = omega[2];
  C[1][1] = 0.0;
  C[1][2] = -omega[0];
  C[2][0] = -omega[1];
  C[2][1] = omega[0];
  C[2][2] = 0.0;
}

struct TaggedPoint {
  ParticlePoint point;
  int body;
};

// One body's particles: from its Particles File, the elements' Gauss points (FE reference), a 3D
// lattice box, or a 2D lattice of its shape.
std::vector<ParticlePoint> bodyPoints(const BodySpec& body, const StructuredGrid& g, Placement placement,
                                      double thickness) {
  try {
    if (!body.particlesFile.empty()) return readParticlesFile(body.particlesFile, g.dim, thickness);
    if (placement != Placement::Lattice) return gaussPoints(body.rect, g, placement == Placement::GaussQ9, thickness);
    if (g.dim == 3) {
      if (!body.rectangle)
        throw std::invalid_argument("a 3D grid fills Rectangle (box) bodies and Particles Files only");
      return fillBox(body.rect, g);
    }
    // Rectangles on grid lines need no volume scaling; other shapes get their exact area.
    const GridBox box{g.x0, g.y0, g.hx, g.hy, g.nx, g.ny};
    return fillShape(*body.shape, box, body.rect.particlesPerCellX, body.rect.particlesPerCellY, thickness, 0, g.nx,
                     !body.rectangle, body.rect.latticePoints);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument("'Bodies/" + body.name + "': " + e.what());
  }
}

// Every body's particles over the whole grid, in deck order: the global id of a particle is its
// position in this list, whatever the decomposition.
std::vector<TaggedPoint> fillBodies(const std::vector<BodySpec>& bodies, const StructuredGrid& g, Placement placement,
                                    double thickness) {
  std::vector<TaggedPoint> all;
  for (int b = 0; b < (int)bodies.size(); ++b) {
    const BodySpec& body = bodies[b];
    const std::vector<ParticlePoint> pts = bodyPoints(body, g, placement, thickness);
    // A later body's shape takes the place of the earlier bodies' particles inside it.
    if (body.shape && b > 0) {
      std::vector<TaggedPoint> kept;
      for (const auto& tp : all) {
        const bool insideZ = g.dim == 2 || (tp.point.z >= body.rect.zMin && tp.point.z <= body.rect.zMax);
        if (!(insideZ && body.shape->contains(tp.point.x, tp.point.y))) kept.push_back(tp);
      }
      all.swap(kept);
    }
    const double tol = 1e-9 * std::min(g.hx, g.hy);
    const double tolZ = 1e-9 * g.hz;
    int inside = 0;
    for (const auto& p : pts)
      if (p.x >= g.x0 - tol && p.x <= g.xMax() + tol && p.y >= g.y0 - tol && p.y <= g.yMax() + tol &&
          (g.dim == 2 || (p.z >= g.z0 - tolZ && p.z <= g.zMax() + tolZ))) {
        all.push_back({p, b});
        ++inside;
      }
    if (inside == 0) throw std::invalid_argument("'Bodies/" + body.name + "' has no particle inside the grid");
    if (inside != (int)pts.size())
      throw std::invalid_argument("'Bodies/" + body.name + "/File': " + std::to_string(pts.size() - inside) +
                                  " particle(s) lie outside the grid");
  }
  return all;
}

// The particle set of the points `mine` (global ids `ids`): position, half size, the body's
// velocity (with its rotation about its centre), mass, volume, body and material.
ParticleSet particleSetOf(const std::vector<const TaggedPoint*>& mine, const std::vector<long long>& ids,
                          const std::vector<BodySpec>& bodies, const Materials& materials, int dim) {
  const int n = (int)mine.size();
  ParticleSet ps(n, dim);
  auto x = Kokkos::create_mirror_view(ps.x);
  auto hs = Kokkos::create_mirror_view(ps.halfSize);
  auto v = Kokkos::create_mirror_view(ps.v);
  auto m = Kokkos::create_mirror_view(ps.mass);
  auto V0 = Kokkos::create_mirror_view(ps.volume0);
  auto bodyId = Kokkos::create_mirror_view(ps.body);
  auto matId = Kokkos::create_mirror_view(ps.material);
  auto gid = Kokkos::create_mirror_view(ps.id);
  for (int p = 0; p < n; ++p) {
    const ParticlePoint& pt = mine[p]->point;
    const BodySpec& body = bodies[mine[p]->body];
    x(p, 0) = pt.x;
    x(p, 1) = pt.y;
    hs(p, 0) = pt.lx;
    hs(p, 1) = pt.ly;
    v(p, 0) = body.velocityX;
    v(p, 1) = body.velocityY;
    if (dim == 3) {
      x(p, 2) = pt.z;
      hs(p, 2) = pt.lz;
      v(p, 2) = body.velocityZ;
    }
    if (body.angularVelocity != std::array<double, 3>{}) {
      double C[3][3];
      rotationMatrix(body.angularVelocity, C);
      const double r[3] = {pt.x - body.rotationCenter[0], pt.y - body.rotationCenter[1],
                           dim == 3 ? pt.z - body.rotationCenter[2] : 0.0};
      for (int i = 0; i < dim; ++i)
        for (int j = 0; j < 3; ++j) v(p, i) += C[i][j] * r[j];
    }
    m(p) = materials.density(body.material) * pt.volume;
    V0(p) = pt.volume;
    bodyId(p) = mine[p]->body;
    matId(p) = body.material;
    gid(p) = ids[p];
  }
  Kokkos::deep_copy(ps.x, x);
  Kokkos::deep_copy(ps.x0, x);
  Kokkos::deep_copy(ps.halfSize, hs);
  Kokkos::deep_copy(ps.v, v);
  Kokkos::deep_copy(ps.mass, m);
  Kokkos::deep_copy(ps.volume0, V0);
  Kokkos::deep_copy(ps.volume, V0);
  Kokkos::deep_copy(ps.body, bodyId);
  Kokkos::deep_copy(ps.material, matId);
  Kokkos::deep_copy(ps.id, gid);
  return ps;
}
}  // namespace

// Every rank fills every body over the whole grid, so that the global id (the position in this
// fill) is the same whatever the decomposition; a rank then keeps its own columns.
ParticleSet createParticles(const std::vector<BodySpec>& bodies, const Materials& materials,
                            const GridDistribution& dist, Placement placement, double thickness) {
  const std::vector<TaggedPoint> all = fillBodies(bodies, dist.grid(), placement, thickness);
  std::vector<long long> ids;
  std::vector<const TaggedPoint*> mine;
  for (size_t k = 0; k < all.size(); ++k) {
    const double xp[3] = {all[k].point.x, all[k].point.y, all[k].point.z};
    if (!dist.ownsPoint(xp)) continue;
    mine.push_back(&all[k]);
    ids.push_back((long long)k);
  }
  return particleSetOf(mine, ids, bodies, materials, dist.grid().dim);
}

void setRotationAffineVelocity(ParticleSet& ps, const std::vector<BodySpec>& bodies) {
  auto affine = Kokkos::create_mirror_view(ps.affine);
  auto bodyId = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.body);
  for (int p = 0; p < ps.count; ++p) {
    double C[3][3];
    rotationMatrix(bodies[bodyId(p)].angularVelocity, C);
    for (int i = 0; i < ps.dim; ++i)
      for (int j = 0; j < ps.dim; ++j) affine(p, i, j) = C[i][j];
  }
  Kokkos::deep_copy(ps.affine, affine);
}

ParticleSet createParticles(const RectangularBody& body, const Materials& materials, const GridDistribution& dist) {
  BodySpec spec;
  spec.name = "body";
  spec.rectangle = true;
  spec.rect = body;
  spec.shape = makeRectangle(body.xMin, body.xMax, body.yMin, body.yMax);
  return createParticles({spec}, materials, dist, body.placement, body.thickness);
}

}  // namespace impm
