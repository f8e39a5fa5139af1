#include "services/rpc/process.h"

#include "absl/synchronization/mutex.h"

namespace gaitforge::rpc {

void DisableAbslDeadlockDetection() {
  absl::SetMutexDeadlockDetectionMode(absl::OnDeadlockCycle::kIgnore);
}

}  // namespace gaitforge::rpc
