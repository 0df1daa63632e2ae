// Small dense Dim x Dim matrices (2 or 3) inside kernels: determinant, inverse and product.
#pragma once

#include <Kokkos_Core.hpp>

namespace impm {

template <int Dim>
KOKKOS_INLINE_FUNCTION double determinant(const double (&F)[Dim][Dim]) {
  if constexpr (Dim == 2) {
    return F[0][0] * F[1][1] - F[0][1] * F[1][0];
  } else {
    return F[0][0] * (F[1][1] * F[2][2] - F[1][2] * F[2][1]) - F[0][1] * (F[1][0] * F[2][2] - F[1][2] * F[2][0]) +
           F[0][2] * (F[1][0] * F[2][1] - F[1][1] * F[2][0]);
  }
}

// A^-1 given det A (the caller has it already and checked it).
template <int Dim>
KOKKOS_INLINE_FUNCTION void inverse(const double (&A)[Dim][Dim], double det, double (&inv)[Dim][Dim]) {
  const double r = 1.0 / det;
  if constexpr (Dim == 2) {
    inv[0][0] = A[1][1] * r;
    inv[0][1] = -A[0][1] * r;
    inv[1][0] = -A[1][0] * r;
    inv[1][1] = A[0][0] * r;
  } else {
    inv[0][0] = (A[1][1] * A[2][2] - A[1][2] * A[2][1]) * r;
    inv[0][1] = (A[0][2] * A[2][1] - A[0][1] * A[2][2]) * r;
    inv[0][2] = (A[0][1] * A[1][2] - A[0][2] * A[1][1]) * r;
    inv[1][0] = (A[1][2] * A[2][0] - A[1][0] * A[2][2]) * r;
    inv[1][1] = (A[0][0] * A[2][2] - A[0][2] * A[2][0]) * r;
    inv[1][2] = (A[0][2] * A[1][0] - A[0][0] * A[1][2]) * r;
    inv[2][0] = (A[1][0] * A[2][1] - A[1][1] * A[2][0]) * r;
    inv[2][1] = (A[0][1] * A[2][0] - A[0][0] * A[2][1]) * r;
    inv[2][2] = (A[0][0] * A[1][1] - A[0][1] * A[1][0]) * r;
  }
}

// C = A B.
template <int Dim>
KOKKOS_INLINE_FUNCTION void multiply(const double (&A)[Dim][Dim], const double (&B)[Dim][Dim], double (&C)[Dim][Dim]) {
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) {
      double c = 0;
      for (int k = 0; k < Dim; ++k) c += A[i][k] * B[k][j];
      C[i][j] = c;
    }
}

}  // namespace impm
