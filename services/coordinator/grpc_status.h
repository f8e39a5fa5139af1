#pragma once
// The one place where absl::Status becomes grpc::Status.
#include <grpcpp/support/status.h>

#include <string>
#include <utility>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace gaitforge::coordinator {

grpc::Status ToGrpc(const absl::Status& s);

// A service method's answer: the value into *out, or the error.
template <typename T, typename Out>
grpc::Status Reply(absl::StatusOr<T> r, Out* out) {
  if (!r.ok()) return ToGrpc(r.status());
  *out = std::move(*r);
  return grpc::Status::OK;
}

// INVALID_ARGUMENT "field 'NAME' is required" when value is empty.
grpc::Status NeedField(const std::string& value, const char* name);

}  // namespace gaitforge::coordinator
