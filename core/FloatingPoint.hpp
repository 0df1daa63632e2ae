// Subnormal numbers flushed to zero for this thread and the threads it starts (they inherit the
// floating-point environment): an explicit step load sends values ahead of the wave that decay
// through the subnormal range (about 1e-308), where x86 arithmetic is up to 100 times slower; on
// the 2D benchmark bar at 400 steps they took a third of the run's time. No mechanics lives below 1e-300.
// Call before Kokkos starts its threads.
#pragma once

#if defined(__SSE2__)
#include <xmmintrin.h>
#endif

namespace impm {

inline void flushSubnormalsToZero() {
#if defined(__SSE2__)
  _mm_setcsr(_mm_getcsr() | 0x8040);  // FTZ (bit 15) and DAZ (bit 6)
#endif
}

}  // namespace impm
