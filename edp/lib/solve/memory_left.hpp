// solve/memory_left.hpp -- what this process may still allocate under its memory limits, for the plugin
// solve/cholmod_columns.cpp (its refusal of a Cholesky factor that cannot fit: docs/errors.md, exit 8).
#include <fstream>
#include <cstring>
#include <string>
#include <algorithm>
#include <sys/resource.h>

// a field of /proc/self/status, in KiB (0 if absent)
inline double statusKiB(const char *key) {
  std::ifstream status("/proc/self/status");
  std::string line;
  size_t n = strlen(key);
  while (std::getline(status, line))
    if (line.compare(0, n, key) == 0) return atof(line.c_str( ) + n);
  return 0;
}
// the MiB this process may still allocate under its limits (ulimit -d: RLIMIT_DATA against VmData; ulimit -v:
// RLIMIT_AS against VmSize), -1 without a limit
inline double memoryLeftMiB( ) {
  double left = -1;
  struct rlimit r;
  if (getrlimit(RLIMIT_DATA, &r) == 0 && r.rlim_cur != RLIM_INFINITY)
    left = (r.rlim_cur / 1024. - statusKiB("VmData:")) / 1024.;
  if (getrlimit(RLIMIT_AS, &r) == 0 && r.rlim_cur != RLIM_INFINITY) {
    double l = (r.rlim_cur / 1024. - statusKiB("VmSize:")) / 1024.;
    left = (left < 0 ? l : std::min(left, l));
  }
  return left;
}
