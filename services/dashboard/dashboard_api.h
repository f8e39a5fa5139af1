#pragma once
// The dashboard's read-only HTTP API (docs/dashboard.md): GET /api/... answered from the
// Coordinator's own queries, the ones the gRPC StudyService serves, as the protobuf
// messages' JSON (field names as in the .proto, like `gaitforge --json`), the stored
// diagnoses (diagnosis_api.h), and the page's static files. No sockets here (http_server.h carries the bytes), so tests can call it
// directly.
#include <string>

#include "services/coordinator/auth.h"
#include "services/coordinator/coordinator.h"
#include "services/coordinator/diagnoses.h"
#include "services/dashboard/http_answer.h"

namespace gaitforge::dashboard {

class DashboardApi {
 public:
  // `diagnoses`: the coordinator's stored diagnoses (/api/diagnoses); none: those endpoints
  // say so with 404.
  DashboardApi(coordinator::Coordinator& c, const coordinator::Auth& auth,
               coordinator::Diagnoses* diagnoses = nullptr)
      : c_(c), auth_(auth), diagnoses_(diagnoses) {}
  // Any request: an /api/ endpoint (client token required when tokens are configured), or
  // a static file. An unchanged answer to a request with If-None-Match is 304, no body.
  HttpResponse Handle(const HttpRequest& request) const;

 private:
  HttpResponse Api(const HttpRequest& request) const;
  HttpResponse Study(const std::string& id, const std::string& what,
                     const HttpRequest& request) const;

  coordinator::Coordinator& c_;
  const coordinator::Auth& auth_;
  coordinator::Diagnoses* diagnoses_;
};

}  // namespace gaitforge::dashboard
