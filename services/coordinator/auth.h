#pragma once
// Per-role bearer tokens (client, worker, admin). A call carries "authorization: Bearer T"
// metadata; T is compared in constant time with every configured token. Tokens come from
// a file (lines "ROLE TOKEN") or the environment (GAITFORGE_CLIENT_TOKEN,
// GAITFORGE_WORKER_TOKEN, GAITFORGE_ADMIN_TOKEN), never argv. With no token configured,
// every call is allowed (local mode on loopback needs no setup).
#include <grpcpp/server_context.h>

#include <map>
#include <string>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace gaitforge::coordinator {

enum class Role { kClient, kWorker, kAdmin };

class Auth {
 public:
  Auth() = default;
  // Reads tokens_file (may be empty: environment only). Errors name the file and line.
  static absl::StatusOr<Auth> Load(const std::string& tokens_file);
  bool enabled() const { return !tokens_.empty(); }
  // OK if the call may act as `needed` (admin may act as anyone); UNAUTHENTICATED without a
  // known token, PERMISSION_DENIED with a token of another role.
  grpc::Status Check(const grpc::ServerContextBase* ctx, Role needed) const;
  // OK if the call may act as either role.
  grpc::Status CheckEither(const grpc::ServerContextBase* ctx, Role a, Role b) const;
  // The same rule for any carrier of the "Bearer TOKEN" value (gRPC metadata, an HTTP
  // header): `authorization` is the value, nullptr when absent; `carrier` names it in
  // messages ("metadata", "header"). UNAUTHENTICATED or PERMISSION_DENIED as Check.
  absl::Status CheckBearer(const std::string* authorization, Role needed,
                           const char* carrier) const;
  void Add(Role role, std::string token) { tokens_[role] = std::move(token); }

 private:
  std::map<Role, std::string> tokens_;
};

// Compares without an early exit, so timing does not reveal how much of a token matched.
bool ConstantTimeEquals(const std::string& a, const std::string& b);

}  // namespace gaitforge::coordinator
