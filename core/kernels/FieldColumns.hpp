// Which grid velocity field a particle reads and writes. With multi-field contact every body has
// its own field on the grid (physics/MultiFieldContact.hpp): the columns of field f of a grid view
// are those of the single-field layout shifted by f * stride (FieldColumns). The kernels take
// either; SingleField, their default, is the one field at offset 0 as a compile-time constant, so
// that a run without contact indexes its columns as before (a run-time offset of 0 cost the 2D
// explicit step 5% at 1 thread and 18% at 2).
#pragma once

#include "core/ParticleSet.hpp"
#include "core/Types.hpp"

namespace impm {

struct SingleField {
  static constexpr bool multi = false;
  KOKKOS_INLINE_FUNCTION constexpr int offset(int) const { return 0; }
};

struct FieldColumns {
  static constexpr bool multi = true;
  Kokkos::View<const int*, DeviceType> body;         // each particle's body (ParticleSet::body)
  Kokkos::View<const int*, DeviceType> fieldOfBody;  // each body's field
  int stride = 0;                                    // columns per field in the view

  FieldColumns(const ParticleSet& ps, const Kokkos::View<const int*, DeviceType>& fields, int columnsPerField)
      : body(ps.body), fieldOfBody(fields), stride(columnsPerField) {}

  // The column shift of particle p's field.
  KOKKOS_INLINE_FUNCTION int offset(int p) const { return stride * fieldOfBody(body(p)); }
};

}  // namespace impm
