#pragma once
// The dashboard's read-only HTTP API (docs/dashboard.md): GET /api/... answered from the
// Coordinator's own queries, the ones the gRPC StudyService serves, as the protobuf
// messages' JSON (field names as in the .proto, like `gaitforge --json`), and the page's
// static files. No sockets here (http_server.h carries the bytes), so tests can call it
// directly.
#include <map>
#include <string>

#include "services/coordinator/auth.h"
#include "services/coordinator/coordinator.h"

namespace gaitforge::dashboard {

struct HttpRequest {
  std::string method;  // "GET"
  std::string path;    // decoded, without the query: "/api/studies/ab12"
  std::map<std::string, std::string> query;  // decoded ?key=value pairs
  const std::string* authorization = nullptr;  // the Authorization header, if sent
  std::string if_none_match;                   // the If-None-Match header, if sent
};

struct HttpResponse {
  int status = 200;
  std::string content_type = "application/json";
  std::string body;
  std::string etag;  // quoted; empty: none
  std::map<std::string, std::string> headers;  // extra headers (WWW-Authenticate)
};

class DashboardApi {
 public:
  DashboardApi(coordinator::Coordinator& c, const coordinator::Auth& auth)
      : c_(c), auth_(auth) {}
  // Any request: an /api/ endpoint (client token required when tokens are configured), or
  // a static file. An unchanged answer to a request with If-None-Match is 304, no body.
  HttpResponse Handle(const HttpRequest& request) const;

 private:
  HttpResponse Api(const HttpRequest& request) const;
  HttpResponse Study(const std::string& id, const std::string& what,
                     const HttpRequest& request) const;

  coordinator::Coordinator& c_;
  const coordinator::Auth& auth_;
};

// {"error": MESSAGE, "code": "NOT_FOUND"} with the HTTP status of the absl code.
HttpResponse ErrorResponse(const absl::Status& status);

}  // namespace gaitforge::dashboard
