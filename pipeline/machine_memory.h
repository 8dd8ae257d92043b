// This machine's physical memory, against which grids and decoded frames are checked before they
// are allocated (exit 2 naming the field instead of an allocation failure).
#pragma once

#include <unistd.h>

namespace xsect {

/// Physical memory in bytes; 0 if the system does not say.
inline double physicalMemoryBytes() {
  const long pages = ::sysconf(_SC_PHYS_PAGES), pageSize = ::sysconf(_SC_PAGE_SIZE);
  return pages > 0 && pageSize > 0 ? double(pages) * double(pageSize) : 0.0;
}

}  // namespace xsect
