#include "services/dashboard/dashboard_api.h"

#include <charconv>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"
#include "services/dashboard/diagnosis_api.h"
#include "services/dashboard/study_robot.h"
#include "services/dashboard/web_assets.h"
#include "services/rpc/proto_json.h"

namespace gaitforge::dashboard {
namespace {

using rpc::ToJson;

template <typename T>
HttpResponse Reply(const absl::StatusOr<T>& r) {
  if (!r.ok()) return ErrorResponse(r.status());
  return JsonResponse(ToJson(*r));
}

// The query's whole number `key`, or `fallback` when absent.
absl::StatusOr<int> IntParam(const HttpRequest& req, const std::string& key, int fallback) {
  auto it = req.query.find(key);
  if (it == req.query.end()) return fallback;
  int v = 0;
  const std::string& s = it->second;
  auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v);
  if (ec != std::errc() || end != s.data() + s.size() || v < 0)
    return absl::InvalidArgumentError(
        absl::StrCat(key, ": expected a whole number (0 or more), got '", s, "'"));
  return v;
}

HttpResponse History(coordinator::Coordinator& c, const std::string& id, const HttpRequest& req) {
  auto since = IntParam(req, "since", 0);
  if (!since.ok()) return ErrorResponse(since.status());
  auto h = c.History(id);
  if (!h.ok()) return ErrorResponse(h.status());
  // Only the generations the page lacks: a live page asks for ?since=N every second.
  v1::GetHistoryResponse out;
  for (const auto& g : h->generations())
    if (g.generation() >= *since) *out.add_generations() = g;
  return JsonResponse(ToJson(out));
}

HttpResponse HallOfFame(coordinator::Coordinator& c, const std::string& id,
                        const HttpRequest& req) {
  auto g = IntParam(req, "generation", -1);
  if (!g.ok()) return ErrorResponse(g.status());
  return Reply(c.HallOfFame(id, *g < 0 ? std::nullopt : std::optional<int>(*g)));
}

HttpResponse Individuals(coordinator::Coordinator& c, const std::string& id,
                         const HttpRequest& req) {
  if (!req.query.count("generation"))
    return ErrorResponse(absl::InvalidArgumentError("individuals: ?generation=G is required"));
  auto g = IntParam(req, "generation", 0);
  if (!g.ok()) return ErrorResponse(g.status());
  return Reply(c.Individuals(id, *g));
}

HttpResponse StaticFile(const HttpRequest& req) {
  const WebAsset* a = FindWebAsset(req.path);
  if (a == nullptr) {
    HttpResponse r;
    r.status = 404;
    r.content_type = "text/plain; charset=utf-8";
    r.body = absl::StrCat("no page ", req.path, " here: the dashboard is at /\n");
    return r;
  }
  HttpResponse r;
  r.content_type = a->content_type;
  r.body = std::string(a->bytes());
  r.etag = a->etag;
  return r;
}

}  // namespace

HttpResponse DashboardApi::Handle(const HttpRequest& req) const {
  HttpResponse r;
  if (req.method != "GET" && req.method != "HEAD") {
    r = ErrorResponse(absl::InvalidArgumentError(
        absl::StrCat(req.method, " is not served: the dashboard is read-only (GET only)")));
    r.status = 405;
    r.headers["Allow"] = "GET, HEAD";
    return r;
  }
  r = req.path == "/api" || req.path.rfind("/api/", 0) == 0 ? Api(req) : StaticFile(req);
  if (r.status == 200 && !r.etag.empty() && req.if_none_match == r.etag) {
    r.status = 304;
    r.body.clear();
  }
  return r;
}

HttpResponse DashboardApi::Api(const HttpRequest& req) const {
  // The same rule and tokens as the gRPC StudyService: reading studies needs a client (or
  // admin) token once tokens are configured.
  if (auto a = auth_.CheckBearer(req.authorization, coordinator::Role::kClient, "header");
      !a.ok())
    return ErrorResponse(a);
  const std::vector<std::string> parts =
      absl::StrSplit(req.path.substr(1), '/', absl::SkipEmpty());
  if (parts.size() == 2 && parts[1] == "studies") {
    auto list = c_.ListStudies();
    if (!list.ok()) return ErrorResponse(list.status());
    v1::ListStudiesResponse out;
    for (auto& s : *list) *out.add_studies() = std::move(s);
    return JsonResponse(ToJson(out));
  }
  if (parts.size() >= 3 && parts.size() <= 4 && parts[1] == "studies")
    return Study(parts[2], parts.size() == 4 ? parts[3] : "", req);
  if (parts.size() >= 2 && parts[1] == "diagnoses") return DiagnosisApi(diagnoses_, parts, req);
  return ErrorResponse(absl::NotFoundError(
      absl::StrCat("no endpoint GET ", req.path, " (docs/dashboard.md lists them)")));
}

HttpResponse DashboardApi::Study(const std::string& id, const std::string& what,
                                 const HttpRequest& req) const {
  if (what.empty()) return Reply(c_.GetStudy(id));
  if (what == "progress") {
    auto p = c_.Progress(id);
    if (!p.ok()) return ErrorResponse(p.status());
    return JsonResponse(ToJson(p->first));
  }
  if (what == "history") return History(c_, id, req);
  if (what == "hall-of-fame") return HallOfFame(c_, id, req);
  if (what == "individuals") return Individuals(c_, id, req);
  if (what == "robot") {
    auto s = c_.GetStudy(id);
    if (!s.ok()) return ErrorResponse(s.status());
    return JsonResponse(StudyRobotJson(s->spec()));
  }
  return ErrorResponse(absl::NotFoundError(absl::StrCat(
      "no endpoint GET ", req.path,
      "; a study has: progress, history, hall-of-fame, individuals, robot")));
}

}  // namespace gaitforge::dashboard
