#include "services/dashboard/diagnosis_api.h"

#include <google/protobuf/struct.pb.h>
#include <google/protobuf/util/json_util.h>

#include "absl/strings/match.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "absl/strings/strip.h"
#include "services/dashboard/json_text.h"
#include "services/rpc/proto_json.h"

namespace gaitforge::dashboard {
namespace {

// A stored SVG is data, not page: in its own document it may style itself, nothing more (no
// script, no fetch, no frame), so an SVG with a script in the database cannot act as the page.
constexpr char kFileCsp[] = "default-src 'none'; style-src 'unsafe-inline'";

HttpResponse List(coordinator::Diagnoses& d) {
  auto list = d.List();
  if (!list.ok()) return ErrorResponse(list.status());
  v1::ListDiagnosesResponse out;
  for (auto& s : *list) *out.add_diagnoses() = std::move(s);
  return JsonResponse(rpc::ToJson(out));
}

// The report as stored when it is JSON (verbatim: the bytes the CLI prints with --json,
// without the closing newline), or null and why not.
std::pair<std::string, std::string> ReportJson(const std::string& stored) {
  const std::string report(absl::StripTrailingAsciiWhitespace(stored));
  if (report.empty()) return {"null", ""};
  google::protobuf::Struct parsed;
  if (auto s = google::protobuf::util::JsonStringToMessage(report, &parsed); !s.ok())
    return {"null", absl::StrCat("the stored report is not JSON: ", s.message().as_string())};
  return {report, ""};
}

// {"diagnosis": DiagnosisSummary, "report": REPORT or null, "report_error": "", "files": [..]}
HttpResponse One(coordinator::Diagnoses& d, const std::string& id) {
  auto g = d.Get(id, /*with_files=*/true);
  if (!g.ok()) return ErrorResponse(g.status());
  auto [report, error] = ReportJson(g->report_json());
  std::vector<std::string> files;
  for (const auto& f : g->files()) files.push_back(JsonString(f.name()));
  return JsonResponse(JsonObject({{"diagnosis", rpc::ToJson(g->diagnosis())},
                                  {"report", report},
                                  {"report_error", JsonString(error)},
                                  {"files", JsonArray(files)}}));
}

HttpResponse File(coordinator::Diagnoses& d, const std::string& id, const std::string& name) {
  auto g = d.Get(id, /*with_files=*/true);
  if (!g.ok()) return ErrorResponse(g.status());
  std::vector<std::string> names;
  for (const auto& f : g->files()) {
    if (f.name() != name) {
      names.push_back(f.name());
      continue;
    }
    HttpResponse r;
    r.content_type = DiagnosisFileType(name);
    r.body = f.content();
    r.etag = BodyTag(r.body);
    r.headers["Content-Security-Policy"] = kFileCsp;
    return r;
  }
  return ErrorResponse(absl::NotFoundError(
      names.empty()
          ? absl::StrCat("diagnosis ", id, " has no file '", name,
                         "': it has no files (they are kept once it completes)")
          : absl::StrCat("diagnosis ", id, " has no file '", name, "' (it has ",
                         absl::StrJoin(names, ", "), ")")));
}

}  // namespace

std::string DiagnosisFileType(const std::string& name) {
  if (absl::EndsWith(name, ".svg")) return "image/svg+xml";
  if (absl::EndsWith(name, ".json")) return "application/json";
  if (absl::EndsWith(name, ".yaml")) return "text/yaml; charset=utf-8";
  return "application/octet-stream";
}

HttpResponse DiagnosisApi(coordinator::Diagnoses* diagnoses, const std::vector<std::string>& parts,
                          const HttpRequest& req) {
  if (diagnoses == nullptr)
    return ErrorResponse(absl::NotFoundError(
        "this dashboard serves no diagnoses (its coordinator has no stored diagnoses)"));
  if (parts.size() == 2) return List(*diagnoses);
  if (parts.size() == 3) return One(*diagnoses, parts[2]);
  if (parts.size() == 5 && parts[3] == "files") return File(*diagnoses, parts[2], parts[4]);
  return ErrorResponse(absl::NotFoundError(
      absl::StrCat("no endpoint GET ", req.path,
                   "; a diagnosis has: /api/diagnoses/ID and /api/diagnoses/ID/files/NAME")));
}

}  // namespace gaitforge::dashboard
