#pragma once
// Process-wide settings for a gRPC server or client process.

namespace gaitforge::rpc {

// Turns off abseil's mutex deadlock detection. Debian 12 builds abseil without NDEBUG, so
// every lock of gRPC's internal mutexes updated a global lock-order graph: ~4% of the
// coordinator's CPU at 1,024 workers (issue 30). gaitforge's own mutexes are std::mutex.
void DisableAbslDeadlockDetection();

}  // namespace gaitforge::rpc
