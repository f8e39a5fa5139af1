#pragma once
// Client side of every gaitforge connection (workers, the CLI, tests): channel credentials
// (plaintext or TLS with an optional client certificate), keepalive, message limits, and
// the per-call deadline plus bearer token.
#include <grpcpp/grpcpp.h>

#include <memory>
#include <string>

#include "absl/status/statusor.h"

namespace gaitforge::rpc {

struct ChannelOptions {
  std::string target;    // host:port
  std::string tls_ca;    // PEM CA file: use TLS and trust this CA
  std::string tls_cert;  // PEM client certificate (with tls_key), for servers that ask
  std::string tls_key;
  std::string token;     // bearer token sent with every call (empty: none)
  // A connection of its own rather than one shared with other channels to the same target
  // (gRPC shares subchannels process-wide): bench/swarm emulates many workers in one process.
  bool own_connection = false;
};

// Reads the token from `file` if given, else from the environment variable `env`.
// Errors name the file. Tokens never come from argv.
absl::StatusOr<std::string> LoadToken(const std::string& file, const char* env);

absl::StatusOr<std::shared_ptr<grpc::Channel>> MakeChannel(const ChannelOptions& options);

// Sets the deadline (seconds from now) and the token on a call.
void PrepareCall(grpc::ClientContext& ctx, double seconds, const std::string& token);

}  // namespace gaitforge::rpc
