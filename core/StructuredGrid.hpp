// A structured background grid of rectangular cells. Nodes are numbered column by column
// (x slowest), node(i, j) = i * (ny + 1) + j, so that a slab of cell columns owns a
// contiguous range of global node ids; the node map partitions over x slabs.
#pragma once

#include <Kokkos_Core.hpp>

namespace impm {

struct StructuredGrid {
  double x0 = 0.0, y0 = 0.0;  // lower-left corner
  double hx = 1.0, hy = 1.0;  // cell sizes
  int nx = 1, ny = 1;         // number of cells

  KOKKOS_INLINE_FUNCTION int nodesX() const { return nx + 1; }
  KOKKOS_INLINE_FUNCTION int nodesY() const { return ny + 1; }
  KOKKOS_INLINE_FUNCTION long long numNodes() const { return (long long)(nx + 1) * (ny + 1); }
  KOKKOS_INLINE_FUNCTION long long numCells() const { return (long long)nx * ny; }
  KOKKOS_INLINE_FUNCTION long long nodeId(int i, int j) const { return (long long)i * (ny + 1) + j; }
  KOKKOS_INLINE_FUNCTION long long cellId(int i, int j) const { return (long long)i * ny + j; }
  KOKKOS_INLINE_FUNCTION double nodeX(int i) const { return x0 + i * hx; }
  KOKKOS_INLINE_FUNCTION double nodeY(int j) const { return y0 + j * hy; }
  KOKKOS_INLINE_FUNCTION double xMax() const { return x0 + nx * hx; }
  KOKKOS_INLINE_FUNCTION double yMax() const { return y0 + ny * hy; }
};

// Local indexing of the nodes a rank sees (owned plus ghost): node columns
// [colBegin, colEnd) of the global grid, every row. Used inside kernels.
struct LocalNodeIndexer {
  int colBegin = 0, colEnd = 0, nodesY = 0;
  KOKKOS_INLINE_FUNCTION int operator()(int i, int j) const { return (i - colBegin) * nodesY + j; }
  KOKKOS_INLINE_FUNCTION bool contains(int i, int j) const {
    return i >= colBegin && i < colEnd && j >= 0 && j < nodesY;
  }
  KOKKOS_INLINE_FUNCTION int size() const { return (colEnd - colBegin) * nodesY; }
};

}  // namespace impm
