#pragma once
// The dashboard's diagnosis endpoints (docs/dashboard.md): GET /api/diagnoses,
// /api/diagnoses/ID (the summary and the parsed report), /api/diagnoses/ID/files/NAME (a
// stored file's bytes), answered from the coordinator's stored diagnoses (Diagnoses, the
// object the gRPC DiagnosisService serves).
#include <string>
#include <vector>

#include "services/coordinator/diagnoses.h"
#include "services/dashboard/http_answer.h"

namespace gaitforge::dashboard {

// `parts`: the path's segments, "api", "diagnoses", ... (the token is checked already).
// `diagnoses` null: this dashboard has none to show (404 saying so).
HttpResponse DiagnosisApi(coordinator::Diagnoses* diagnoses, const std::vector<std::string>& parts,
                          const HttpRequest& req);

// A stored file's content type by its name: image/svg+xml, application/json, text/yaml.
std::string DiagnosisFileType(const std::string& name);

}  // namespace gaitforge::dashboard
