// A structured background grid of box cells, in 2D (nz = 0: one layer of nodes) or 3D.
// Nodes are numbered with x slowest and z fastest, node(i, j, k) = (i * (ny + 1) + j) * (nz + 1) + k
// (in 2D: i * (ny + 1) + j), so that a slab of cell columns owns a contiguous range of global
// node ids; the node map partitions over x slabs.
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

// Local indexing of the nodes a rank sees (owned plus ghost): node columns
// [colBegin, colEnd) of the global grid, every row and layer. Used inside kernels.
struct LocalNodeIndexer {
  int colBegin = 0, colEnd = 0, nodesY = 0, nodesZ = 1;
  KOKKOS_INLINE_FUNCTION int operator()(int i, int j, int k = 0) const {
    return ((i - colBegin) * nodesY + j) * nodesZ + k;
  }
  KOKKOS_INLINE_FUNCTION bool contains(int i, int j, int k = 0) const {
    return i >= colBegin && i < colEnd && j >= 0 && j < nodesY && k >= 0 && k < nodesZ;
  }
  KOKKOS_INLINE_FUNCTION int size() const { return (colEnd - colBegin) * nodesY * nodesZ; }
};

}  // namespace impm
