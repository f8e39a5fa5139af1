#pragma once
// The dashboard's HTTP request and answer as plain values (no sockets: http_server.h carries
// them), and the answers every endpoint shares: JSON with an ETag, and errors.
#include <map>
#include <string>

#include "absl/status/status.h"

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
  // Extra headers (WWW-Authenticate); a Content-Security-Policy here replaces the page's.
  std::map<std::string, std::string> headers;
};

// {"error": MESSAGE, "code": "NOT_FOUND"} with the HTTP status of the absl code.
HttpResponse ErrorResponse(const absl::Status& status);
// `body` (JSON text) with its ETag.
HttpResponse JsonResponse(std::string body);
// A body's identity for ETag/If-None-Match, quoted (FNV-1a: not a security property).
std::string BodyTag(const std::string& body);

}  // namespace gaitforge::dashboard
