#include "services/coordinator/grpc_status.h"

namespace gaitforge::coordinator {

grpc::Status ToGrpc(const absl::Status& s) {
  if (s.ok()) return grpc::Status::OK;
  // absl and gRPC share the canonical code numbers.
  return grpc::Status(static_cast<grpc::StatusCode>(s.code()), std::string(s.message()));
}

grpc::Status NeedField(const std::string& value, const char* name) {
  if (value.empty())
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        std::string("field '") + name + "' is required");
  return grpc::Status::OK;
}

}  // namespace gaitforge::coordinator
