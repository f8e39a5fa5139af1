#pragma once
// The one place where absl::Status becomes grpc::Status.
#include <grpcpp/support/status.h>

#include "absl/status/status.h"

namespace gaitforge::coordinator {

grpc::Status ToGrpc(const absl::Status& s);

}  // namespace gaitforge::coordinator
