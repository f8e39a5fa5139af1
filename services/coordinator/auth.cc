#include "services/coordinator/auth.h"

#include <cstdlib>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "services/coordinator/grpc_status.h"

namespace gaitforge::coordinator {
namespace {

const char* RoleName(Role r) {
  switch (r) {
    case Role::kClient: return "client";
    case Role::kWorker: return "worker";
    case Role::kAdmin: return "admin";
  }
  return "?";
}

}  // namespace

bool ConstantTimeEquals(const std::string& a, const std::string& b) {
  // Length differences are not secret-dependent beyond the length itself.
  unsigned char diff = a.size() == b.size() ? 0 : 1;
  const size_t n = std::max(a.size(), b.size());
  for (size_t i = 0; i < n; ++i) {
    const unsigned char x = i < a.size() ? a[i] : 0;
    const unsigned char y = i < b.size() ? b[i] : 0;
    diff |= x ^ y;
  }
  return diff == 0;
}

absl::StatusOr<Auth> Auth::Load(const std::string& tokens_file) {
  Auth auth;
  const std::pair<Role, const char*> env[] = {{Role::kClient, "GAITFORGE_CLIENT_TOKEN"},
                                              {Role::kWorker, "GAITFORGE_WORKER_TOKEN"},
                                              {Role::kAdmin, "GAITFORGE_ADMIN_TOKEN"}};
  for (const auto& [role, var] : env) {
    if (const char* v = std::getenv(var); v && *v) {
      if (std::string(v).size() < 16)
        return absl::InvalidArgumentError(
            absl::StrCat(var, " is ", std::string(v).size(), " characters long; at least 16 required"));
      auth.tokens_[role] = v;
    }
  }
  if (tokens_file.empty()) return auth;
  std::ifstream in(tokens_file);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot read tokens file '", tokens_file, "'"));
  std::string line;
  for (int n = 1; std::getline(in, line); ++n) {
    std::istringstream words(line);
    std::string role, token, extra;
    if (!(words >> role) || role[0] == '#') continue;
    if (!(words >> token) || (words >> extra))
      return absl::InvalidArgumentError(
          absl::StrCat(tokens_file, ":", n, ": expected 'ROLE TOKEN' (ROLE: client, worker, admin)"));
    Role r;
    if (role == "client") r = Role::kClient;
    else if (role == "worker") r = Role::kWorker;
    else if (role == "admin") r = Role::kAdmin;
    else
      return absl::InvalidArgumentError(absl::StrCat(tokens_file, ":", n, ": unknown role '", role,
                                                     "' (allowed: client, worker, admin)"));
    if (token.size() < 16)
      return absl::InvalidArgumentError(absl::StrCat(
          tokens_file, ":", n, ": the ", role, " token is ", token.size(),
          " characters long; at least 16 required"));
    auth.tokens_[r] = token;
  }
  return auth;
}

grpc::Status Auth::CheckEither(const grpc::ServerContextBase* ctx, Role a, Role b) const {
  grpc::Status s = Check(ctx, a);
  if (s.ok() || s.error_code() == grpc::StatusCode::UNAUTHENTICATED) return s;
  return Check(ctx, b);
}

grpc::Status Auth::Check(const grpc::ServerContextBase* ctx, Role needed) const {
  if (tokens_.empty()) return grpc::Status::OK;
  const auto& md = ctx->client_metadata();
  auto it = md.find("authorization");
  std::string value;
  if (it != md.end()) value.assign(it->second.data(), it->second.size());
  return ToGrpc(CheckBearer(it == md.end() ? nullptr : &value, needed, "metadata"));
}

absl::Status Auth::CheckBearer(const std::string* authorization, Role needed,
                               const char* carrier) const {
  if (tokens_.empty()) return absl::OkStatus();
  if (authorization == nullptr)
    return absl::UnauthenticatedError(
        absl::StrCat("missing 'authorization: Bearer TOKEN' ", carrier));
  const std::string prefix = "Bearer ";
  if (authorization->rfind(prefix, 0) != 0)
    return absl::UnauthenticatedError(
        absl::StrCat("authorization ", carrier, " must be 'Bearer TOKEN'"));
  const std::string token = authorization->substr(prefix.size());
  bool known = false;
  Role role = Role::kClient;
  for (const auto& [r, t] : tokens_) {
    // Every configured token is compared, matched or not.
    if (ConstantTimeEquals(token, t)) {
      known = true;
      role = r;
    }
  }
  if (!known) return absl::UnauthenticatedError("unknown token");
  if (role == Role::kAdmin || role == needed) return absl::OkStatus();
  return absl::PermissionDeniedError(
      absl::StrCat("a ", RoleName(role), " token cannot call this (needs the ", RoleName(needed),
                   " or admin role)"));
}

}  // namespace gaitforge::coordinator
