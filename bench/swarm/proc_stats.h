#pragma once
// CPU and memory of a process, from /proc (the coordinator's) or getrusage (our own), so
// the swarm reports its own CPU apart from the coordinator's.
#include <sys/types.h>

#include <cstdint>

namespace gaitforge::swarm {

// User + system CPU seconds of `pid` so far (0 if it cannot be read).
double ProcessCpuSeconds(pid_t pid);
// Our own user + system CPU seconds.
double SelfCpuSeconds();
// Resident and peak resident memory of `pid`, MiB (VmRSS, VmHWM; 0 if unreadable).
struct Memory {
  double rss_mib = 0, peak_mib = 0;
};
Memory ProcessMemory(pid_t pid);
// Raises the open-file limit to its hard maximum (a connection per emulated worker);
// returns the new soft limit.
int64_t RaiseFileLimit();

}  // namespace gaitforge::swarm
