#pragma once
// Where and how the coordinator listens: interface resolution, TLS, and the rule that a
// listener reachable from other hosts speaks TLS (unless the operator says --insecure).
#include <grpcpp/security/server_credentials.h>

#include <cstdint>
#include <memory>
#include <string>

#include "absl/status/statusor.h"

namespace gaitforge::coordinator {

struct TlsFiles {
  std::string cert;       // PEM server certificate (chain)
  std::string key;        // PEM private key
  std::string client_ca;  // PEM CA for client certificates (optional: then required)
};

// "HOST:PORT" with HOST replaced by the IPv4 address of `iface` when iface is set.
// INVALID_ARGUMENT unless PORT is a number in [0, 65535].
absl::StatusOr<std::string> ResolveListen(const std::string& listen, const std::string& iface);
// OK if a plain socket can bind `address` now; else UNAVAILABLE saying why ("cannot listen
// on 127.0.0.1:50051: the port is already in use"). Checked before the database is
// touched, and again to explain a failed gRPC bind.
absl::Status TryBind(const std::string& address);
// "HOST:PORT" with PORT replaced (for logging the port a ":0" listener really got).
std::string WithPort(const std::string& address, int port);
// True for 127.0.0.0/8, ::1 and "localhost".
bool IsLoopback(const std::string& host_port);
absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(
    const TlsFiles& tls, const std::string& address, bool insecure);
// "HOST:PORT" for other hosts to dial: the listen host, or this host's name for 0.0.0.0/[::].
std::string DialAddress(const std::string& address, int port);

absl::StatusOr<std::string> ReadFile(const std::string& path);

// Raises the open-file limit to its hard maximum: every worker holds a connection, and a
// default soft limit of 1024 would refuse workers past about a thousand (docs/scaling.md).
// Returns the new soft limit.
int64_t RaiseOpenFileLimit();

}  // namespace gaitforge::coordinator
