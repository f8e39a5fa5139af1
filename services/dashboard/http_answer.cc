#include "services/dashboard/http_answer.h"

#include <cstdint>
#include <cstdio>

#include "absl/strings/str_cat.h"
#include "services/dashboard/json_text.h"

namespace gaitforge::dashboard {
namespace {

int HttpStatus(absl::StatusCode code) {
  switch (code) {
    case absl::StatusCode::kInvalidArgument: return 400;
    case absl::StatusCode::kUnauthenticated: return 401;
    case absl::StatusCode::kPermissionDenied: return 403;
    case absl::StatusCode::kNotFound:
    case absl::StatusCode::kOutOfRange: return 404;
    case absl::StatusCode::kFailedPrecondition: return 409;
    case absl::StatusCode::kUnavailable: return 503;
    default: return 500;
  }
}

}  // namespace

std::string BodyTag(const std::string& body) {
  uint64_t h = 1469598103934665603ull;
  for (unsigned char ch : body) h = (h ^ ch) * 1099511628211ull;
  char buf[24];
  std::snprintf(buf, sizeof buf, "\"%016llx\"", static_cast<unsigned long long>(h));
  return buf;
}

HttpResponse JsonResponse(std::string body) {
  HttpResponse r;
  r.etag = BodyTag(body);
  r.body = std::move(body);
  return r;
}

HttpResponse ErrorResponse(const absl::Status& status) {
  HttpResponse r;
  r.status = HttpStatus(status.code());
  r.body = JsonObject({{"error", JsonString(std::string(status.message()))},
                       {"code", JsonString(absl::StatusCodeToString(status.code()))}});
  if (r.status == 401) r.headers["WWW-Authenticate"] = "Bearer realm=\"gaitforge\"";
  return r;
}

}  // namespace gaitforge::dashboard
