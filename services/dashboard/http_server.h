#pragma once
// Carries the dashboard's HTTP (DashboardApi) over civetweb, the embeddable server Debian
// ships as libcivetweb (prometheus-cpp's exposer is built on it: already in the process).
#include <memory>
#include <string>

#include "absl/status/statusor.h"
#include "services/dashboard/dashboard_api.h"

struct mg_context;

namespace gaitforge::dashboard {

class HttpServer {
 public:
  // Serves `api` on HOST:PORT (port 0: any free one) until destroyed. Errors say why the
  // address cannot be served ("cannot serve the dashboard on 127.0.0.1:8080: ...").
  static absl::StatusOr<std::unique_ptr<HttpServer>> Start(const std::string& listen,
                                                           const DashboardApi& api);
  ~HttpServer();
  HttpServer(const HttpServer&) = delete;
  HttpServer& operator=(const HttpServer&) = delete;

  int port() const { return port_; }
  // "http://HOST:PORT/" with the port really bound.
  const std::string& url() const { return url_; }

 private:
  explicit HttpServer(const DashboardApi& api) : api_(api) {}
  const DashboardApi& api_;
  mg_context* ctx_ = nullptr;
  int port_ = 0;
  std::string url_;
};

}  // namespace gaitforge::dashboard
