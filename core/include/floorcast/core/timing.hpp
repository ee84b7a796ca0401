// CPU time of the calling thread: stage breakdowns stay meaningful when other
// processes compete for the cores; match_s is still wall time.
#pragma once

#include <ctime>

namespace floorcast {

/// CPU time of the whole process (all threads), seconds.
inline double process_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

inline double thread_cpu_s() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace floorcast
