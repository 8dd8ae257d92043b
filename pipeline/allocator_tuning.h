// How freed memory goes back to the system, set once when xsect starts. glibc's defaults hand
// every freed block above 128 kB back at once (mmap threshold, heap trimming), so a stream of
// frames, each decoded and segmented into buffers of that size, faults every page in again per
// frame; on this project's 2-core VM page faults are expensive. Measured on freehand-2000 (2000
// frames of 640x480 px, `xsect check`): 34 s by default, 14 s with freed blocks up to 32 MB kept
// for reuse and the heap trimmed past 512 MB (64 MB measured the same). Larger blocks (dense
// grids) are still returned at once, so peak memory hardly changes. A setting glibc refuses only
// leaves its default: nothing to stop for.
#pragma once

#include <malloc.h>

namespace xsect {

inline void keepFreedMemoryForReuse() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
}

}  // namespace xsect
