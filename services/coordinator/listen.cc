#include "services/coordinator/listen.h"

#include <arpa/inet.h>
#include <grpcpp/security/server_credentials.h>
#include <ifaddrs.h>
#include <netdb.h>
#include <netinet/in.h>
#include <sys/resource.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <sstream>

#include "absl/strings/str_cat.h"

namespace gaitforge::coordinator {
namespace {

std::string HostOf(const std::string& host_port) {
  if (!host_port.empty() && host_port[0] == '[') return host_port.substr(1, host_port.find(']') - 1);
  const size_t colon = host_port.rfind(':');
  return colon == std::string::npos ? host_port : host_port.substr(0, colon);
}

std::string PortOf(const std::string& host_port) {
  const size_t colon = host_port.rfind(':');
  return colon == std::string::npos ? "" : host_port.substr(colon + 1);
}

}  // namespace

absl::StatusOr<std::string> ReadFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return absl::NotFoundError(absl::StrCat("cannot read '", path, "'"));
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

absl::StatusOr<std::string> ResolveListen(const std::string& listen, const std::string& iface) {
  const std::string port = PortOf(listen);
  const bool digits = !port.empty() && port.size() <= 5 &&
                      port.find_first_not_of("0123456789") == std::string::npos;
  if (!digits || std::stoi(port) > 65535)
    return absl::InvalidArgumentError(absl::StrCat(
        "--listen ", listen, ": the port must be a number in [0, 65535] (0: any free port)"));
  if (iface.empty()) return listen;
  ifaddrs* list = nullptr;
  if (getifaddrs(&list) != 0) return absl::InternalError("getifaddrs failed");
  std::string ip;
  for (ifaddrs* a = list; a; a = a->ifa_next) {
    if (!a->ifa_addr || a->ifa_addr->sa_family != AF_INET || iface != a->ifa_name) continue;
    char buf[INET_ADDRSTRLEN];
    inet_ntop(AF_INET, &reinterpret_cast<sockaddr_in*>(a->ifa_addr)->sin_addr, buf, sizeof buf);
    ip = buf;
    break;
  }
  freeifaddrs(list);
  if (ip.empty())
    return absl::NotFoundError(
        absl::StrCat("--listen-interface: no IPv4 address on interface '", iface, "'"));
  return absl::StrCat(ip, ":", PortOf(listen));
}

bool IsLoopback(const std::string& host_port) {
  const std::string host = HostOf(host_port);
  return host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
}

absl::StatusOr<std::shared_ptr<grpc::ServerCredentials>> MakeServerCredentials(
    const TlsFiles& tls, const std::string& address, bool insecure) {
  if (tls.cert.empty() != tls.key.empty())
    return absl::InvalidArgumentError("--tls-cert and --tls-key go together");
  if (tls.cert.empty() && !tls.client_ca.empty())
    return absl::InvalidArgumentError("--tls-client-ca needs --tls-cert and --tls-key");
  if (tls.cert.empty()) {
    if (!IsLoopback(address) && !insecure)
      return absl::FailedPreconditionError(absl::StrCat(
          "listening on ", address, " (reachable from other hosts) needs TLS: pass --tls-cert "
          "and --tls-key, or --insecure on a network you trust"));
    return grpc::InsecureServerCredentials();
  }
  auto cert = ReadFile(tls.cert);
  if (!cert.ok()) return absl::NotFoundError(absl::StrCat("--tls-cert: ", cert.status().message()));
  auto key = ReadFile(tls.key);
  if (!key.ok()) return absl::NotFoundError(absl::StrCat("--tls-key: ", key.status().message()));
  grpc::SslServerCredentialsOptions o;
  o.pem_key_cert_pairs.push_back({*key, *cert});
  if (!tls.client_ca.empty()) {
    auto ca = ReadFile(tls.client_ca);
    if (!ca.ok())
      return absl::NotFoundError(absl::StrCat("--tls-client-ca: ", ca.status().message()));
    o.pem_root_certs = *ca;
    o.client_certificate_request = GRPC_SSL_REQUEST_AND_REQUIRE_CLIENT_CERTIFICATE_AND_VERIFY;
  }
  return grpc::SslServerCredentials(o);
}

std::string DialAddress(const std::string& address, int port) {
  std::string host = HostOf(address);
  if (host == "0.0.0.0" || host == "::" || host.empty()) {
    char name[256] = {0};
    gethostname(name, sizeof name - 1);
    host = name;
  }
  if (host.find(':') != std::string::npos) host = "[" + host + "]";
  return absl::StrCat(host, ":", port);
}

absl::Status TryBind(const std::string& address) {
  addrinfo hints{};
  hints.ai_socktype = SOCK_STREAM;
  hints.ai_flags = AI_PASSIVE;
  addrinfo* list = nullptr;
  if (getaddrinfo(HostOf(address).c_str(), PortOf(address).c_str(), &hints, &list) != 0)
    return absl::UnavailableError(
        absl::StrCat("cannot listen on ", address, ": cannot resolve the host"));
  std::string why;
  for (addrinfo* a = list; a && why.empty(); a = a->ai_next) {
    const int fd = socket(a->ai_family, a->ai_socktype, a->ai_protocol);
    if (fd < 0) continue;
    const int one = 1;
    setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);  // as gRPC does
    if (bind(fd, a->ai_addr, a->ai_addrlen) != 0)
      why = errno == EADDRINUSE ? "the port is already in use" : std::strerror(errno);
    close(fd);
  }
  freeaddrinfo(list);
  if (why.empty()) return absl::OkStatus();
  return absl::UnavailableError(absl::StrCat("cannot listen on ", address, ": ", why));
}

std::string WithPort(const std::string& address, int port) {
  const size_t colon = address.rfind(':');
  return absl::StrCat(colon == std::string::npos ? address : address.substr(0, colon), ":", port);
}

int64_t RaiseOpenFileLimit() {
  rlimit r{};
  if (getrlimit(RLIMIT_NOFILE, &r) != 0) return -1;
  if (r.rlim_cur < r.rlim_max) {
    r.rlim_cur = r.rlim_max;
    setrlimit(RLIMIT_NOFILE, &r);
    getrlimit(RLIMIT_NOFILE, &r);
  }
  return static_cast<int64_t>(r.rlim_cur);
}

}  // namespace gaitforge::coordinator
