// How freed memory goes back to the system, set once when xsect starts. glibc's defaults hand
// every freed block above 128 kB back at once (mmap threshold, heap trimming), so a stream of
// frames, each decoded and segmented into buffers of that size, faults every page in again per
// frame; on this project's 2-core VM page faults are expensive. Measured on freehand-2000 (2000
// frames of 640x480 px, `xsect check`): 34 s by default, 14 s with freed blocks up to 32 MB kept
// for reuse and the heap trimmed past 512 MB (64 MB measured the same). Larger blocks (dense
// grids) are still returned at once, so peak memory hardly changes. A setting glibc refuses only
// leaves its default: nothing to stop for.
//
// Large arrays (the cut mesh's millions of vertices and triangles, the run-length topology) are
// faulted in 4 kB page by page, and each fault costs microseconds on such VMs. glibc backs its
// heap and large blocks with transparent huge pages when the tunable glibc.malloc.hugetlb=1 is
// set, which it reads only when a process starts: xsect restarts itself once with it. Measured on
// freehand-2000 (`xsect run`): 22.6-23.0 s without, 17.8-19.9 s with (the conformal cut 4.4 ->
// 2.7 s, the mesh check 1.6 -> 0.65 s), peak memory 1.37 -> 1.42 GB. A GLIBC_TUNABLES that
// already names glibc.malloc.hugetlb (=0 to turn it off) is left as it is.
#pragma once

#include <malloc.h>
#include <sys/auxv.h>
#include <unistd.h>

#include <cstdlib>
#include <cstring>
#include <string>

namespace xsect {

/// Restarts this program with glibc.malloc.hugetlb=1 added to GLIBC_TUNABLES, unless the variable
/// already names that tunable; returns (and carries on as it is) when the restart is not possible.
/// Restarts at most once (XSECT_RESTARTED marks the restarted process, whatever glibc does with
/// GLIBC_TUNABLES), never in secure mode (set-user-id: glibc ignores tunables there) and never
/// when started through the dynamic loader (/proc/self/exe is then the loader, not xsect).
inline void restartWithHugePages(char** argv) {
  if (std::getenv("XSECT_RESTARTED") || getauxval(AT_SECURE) != 0) return;
  const char* set = std::getenv("GLIBC_TUNABLES");
  if (set && std::strstr(set, "glibc.malloc.hugetlb")) return;
  char exe[4096];
  const ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
  if (n <= 0) return;
  exe[n] = '\0';
  const char* name = std::strrchr(exe, '/');
  if (std::strncmp(name ? name + 1 : exe, "ld-", 3) == 0) return;
  const bool had = set != nullptr;
  const std::string before = had ? set : "";
  const std::string value = before.empty() ? "glibc.malloc.hugetlb=1" : before + ":glibc.malloc.hugetlb=1";
  if (setenv("GLIBC_TUNABLES", value.c_str(), 1) != 0 || setenv("XSECT_RESTARTED", "1", 1) != 0) return;
  execv(exe, argv);
  if (had) setenv("GLIBC_TUNABLES", before.c_str(), 1);  // exec failed: run as before
  else unsetenv("GLIBC_TUNABLES");
  unsetenv("XSECT_RESTARTED");
}

inline void keepFreedMemoryForReuse() {
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 512 << 20);
}

}  // namespace xsect
