// A structured background grid of box cells, in 2D (nz = 0: one layer of nodes) or 3D.
// Nodes are numbered with x slowest and z fastest, node(i, j, k) = (i * (ny + 1) + j) * (nz + 1) + k
// (in 2D: i * (ny + 1) + j). The node maps are built from lists of ids (GridDistribution), so a
// rank's box of nodes need not be a contiguous range.
#pragma once

#include <Kokkos_Core.hpp>

namespace impm {

struct StructuredGrid {
  double x0 = 0.0, y0 = 0.0, z0 = 0.0;  // lower corner
  double hx = 1.0, hy = 1.0, hz = 1.0;  // cell sizes
  int nx = 1, ny = 1;                   // number of cells
  int nz = 0;                           // 0: a 2D grid
  int dim = 2;                          // spatial dimension, 2 or 3 (3 has nz >= 1)

  KOKKOS_INLINE_FUNCTION int nodesX() const { return nx + 1; }
  KOKKOS_INLINE_FUNCTION int nodesY() const { return ny + 1; }
  KOKKOS_INLINE_FUNCTION int nodesZ() const { return dim == 3 ? nz + 1 : 1; }
  KOKKOS_INLINE_FUNCTION long long numNodes() const { return (long long)(nx + 1) * (ny + 1) * nodesZ(); }
  KOKKOS_INLINE_FUNCTION long long numCells() const { return (long long)nx * ny * (dim == 3 ? nz : 1); }
  KOKKOS_INLINE_FUNCTION long long nodeId(int i, int j, int k = 0) const {
    return ((long long)i * (ny + 1) + j) * nodesZ() + k;
  }
  KOKKOS_INLINE_FUNCTION double nodeX(int i) const { return x0 + i * hx; }
  KOKKOS_INLINE_FUNCTION double nodeY(int j) const { return y0 + j * hy; }
  KOKKOS_INLINE_FUNCTION double nodeZ(int k) const { return z0 + k * hz; }
  KOKKOS_INLINE_FUNCTION double xMax() const { return x0 + nx * hx; }
  KOKKOS_INLINE_FUNCTION double yMax() const { return y0 + ny * hy; }
  KOKKOS_INLINE_FUNCTION double zMax() const { return z0 + nz * hz; }
  // Per direction d (0, 1, 2): origin, cell size and cell count.
  KOKKOS_INLINE_FUNCTION double origin(int d) const { return d == 0 ? x0 : d == 1 ? y0 : z0; }
  KOKKOS_INLINE_FUNCTION double spacing(int d) const { return d == 0 ? hx : d == 1 ? hy : hz; }
  KOKKOS_INLINE_FUNCTION int cells(int d) const { return d == 0 ? nx : d == 1 ? ny : nz; }
};

// A grid with its inverse cell sizes, computed once per kernel launch: the particle stencils'
// fast path (LinearMpm::interiorStencil) scales by 1/h, and a division per particle and
// direction inside the particle loop sat on the critical path of every stencil (GCC does not
// hoist it: the loop body is a separate function). 1.0 / h is the value the per-particle
// division gave, so results are unchanged bit for bit.
struct StencilGrid : StructuredGrid {
  double inverseSpacing[3] = {1.0, 1.0, 1.0};
  explicit StencilGrid(const StructuredGrid& g) : StructuredGrid(g) {
    for (int d = 0; d < 3; ++d) inverseSpacing[d] = 1.0 / spacing(d);
  }
};

// The cell index along direction d of a point at coordinate x, clamped to the grid (0 along z in
// 2D). A point on a cell line belongs to the cell above it (the 1e-9 absorbs rounding in
// positions computed as origin + k h). Particle creation, migration and restart all use it.
KOKKOS_INLINE_FUNCTION int cellIndexOf(const StructuredGrid& g, int d, double x) {
  const int n = g.cells(d);
  if (d == 2 && g.dim != 3) return 0;
  const double xi = (x - g.origin(d)) / g.spacing(d) + 1e-9;
  int i = static_cast<int>(xi);
  if (xi < i) --i;
  return i < 0 ? 0 : (i > n - 1 ? n - 1 : i);
}

// Local indexing of the nodes a rank sees (owned plus ghost): the box of global node indices
// [lo[d], lo[d] + n[d]) per direction (n[2] = 1 in 2D), numbered x slowest like the global ids.
// Used inside kernels.
struct LocalNodeIndexer {
  int lo[3] = {0, 0, 0};
  int n[3] = {0, 0, 1};
  KOKKOS_INLINE_FUNCTION int operator()(int i, int j, int k = 0) const {
    return ((i - lo[0]) * n[1] + (j - lo[1])) * n[2] + (k - lo[2]);
  }
  KOKKOS_INLINE_FUNCTION bool contains(int i, int j, int k = 0) const {
    return i >= lo[0] && i < lo[0] + n[0] && j >= lo[1] && j < lo[1] + n[1] && k >= lo[2] && k < lo[2] + n[2];
  }
  KOKKOS_INLINE_FUNCTION int size() const { return n[0] * n[1] * n[2]; }
  KOKKOS_INLINE_FUNCTION int end(int d) const { return lo[d] + n[d]; }

  // The node box [lo, hi) per direction.
  static LocalNodeIndexer box(int lo0, int hi0, int lo1, int hi1, int lo2 = 0, int hi2 = 1) {
    LocalNodeIndexer ix;
    ix.lo[0] = lo0;
    ix.lo[1] = lo1;
    ix.lo[2] = lo2;
    ix.n[0] = hi0 - lo0;
    ix.n[1] = hi1 - lo1;
    ix.n[2] = hi2 - lo2;
    return ix;
  }
  // Every node of the grid.
  static LocalNodeIndexer wholeGrid(const StructuredGrid& g) {
    return box(0, g.nodesX(), 0, g.nodesY(), 0, g.nodesZ());
  }
};

}  // namespace impm
