// The dashboard's diagnosis endpoints over a real Coordinator, SQLite file and Diagnoses (a
// read-only one, as `gaitforge dashboard` has): the list, one diagnosis with its parsed
// report, stored files with their content types and the SVG's own content security policy,
// 404s naming what is missing, ETags, tokens, and the SVG's headers over a real socket.
#include <civetweb.h>
#include <gtest/gtest.h>

#include "services/dashboard/dashboard_api.h"
#include "services/dashboard/diagnosis_api.h"
#include "services/dashboard/http_server.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/dashboard/requests.h"

namespace gaitforge::testing {
namespace {

using dashboard::DashboardApi;
using dashboard::HttpResponse;

constexpr char kReport[] =
    R"({"name": "hose", "robot": "caterpillar", "verdict": "found", "effects": [{"id": )"
    R"("tether.constant", "params": {}, "study_id": "fit-1"}], "runners_up": [{"id": )"
    R"("ground.slope", "why_not": "worse held out"}]})"
    "\n";
constexpr char kSvg[] = "<svg xmlns=\"http://www.w3.org/2000/svg\"><script>alert(1)</script></svg>";
constexpr char kSvgCsp[] = "default-src 'none'; style-src 'unsafe-inline'";

storage::DiagnosisRecord Record(const std::string& id, const std::string& state, int64_t ms) {
  storage::DiagnosisRecord r;
  r.diagnosis_id = id;
  r.name = "hose";
  v1::DiagnosisSpec spec;
  spec.set_name("hose");
  spec.set_robot("caterpillar");
  r.spec = spec.SerializeAsString();
  r.state = state;
  r.created_ms = r.updated_ms = ms;
  return r;
}

class DiagnosesEndpointsTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = storage::OpenSqliteStore(dir_.File("d.db"));
    ASSERT_TRUE(store.ok()) << store.status();
    coord_ = std::make_unique<coordinator::Coordinator>(std::move(*store),
                                                        coordinator::CoordinatorOptions{}, clock_);
    storage::DiagnosisRecord done = Record("hose-done", "completed", 1000);
    done.verdict = "found";
    done.report = kReport;
    done.files = {{"diagnosis.json", kReport},
                  {"located.svg", kSvg},
                  {"corrected-model.yaml", "objective:\n  name: caterpillar.distance\n"}};
    storage::DiagnosisRecord bad = Record("hose-bad", "completed", 2000);
    bad.report = "{not json";
    storage::DiagnosisRecord failed = Record("hose-failed", "failed", 3000);
    failed.error = "no such effect 'x'";
    for (const auto& r : {done, bad, failed, Record("hose-running", "running", 4000)})
      ASSERT_TRUE(coord_->store().PutDiagnosis(r).get().ok());
    diagnoses_ = std::make_unique<coordinator::Diagnoses>(*coord_, dir_.File("work"), true);
  }

  HttpResponse Get(const std::string& path, const std::string& token = "",
                   const std::string& if_none_match = "") {
    return GetFrom(DashboardApi(*coord_, auth_, diagnoses_.get()), path, token, {}, if_none_match);
  }

  TempDir dir_;
  core::ManualClock clock_;
  coordinator::Auth auth_;
  std::unique_ptr<coordinator::Coordinator> coord_;
  std::unique_ptr<coordinator::Diagnoses> diagnoses_;
};

TEST_F(DiagnosesEndpointsTest, ListsEveryDiagnosisWithStateVerdictAndError) {
  HttpResponse list = Get("/api/diagnoses");
  ASSERT_EQ(list.status, 200);
  EXPECT_EQ(list.content_type, "application/json");
  for (const char* id : {"hose-done", "hose-bad", "hose-failed", "hose-running"})
    EXPECT_TRUE(Has(list.body, std::string("\"diagnosis_id\":\"") + id + "\"")) << id;
  EXPECT_TRUE(Has(list.body, "\"state\":\"DIAGNOSIS_STATE_COMPLETED\"") &&
              Has(list.body, "\"verdict\":\"found\"") && Has(list.body, "\"robot\":\"caterpillar\""))
      << list.body;
  EXPECT_TRUE(Has(list.body, "\"state\":\"DIAGNOSIS_STATE_FAILED\"") &&
              Has(list.body, "\"error\":\"no such effect 'x'\""))
      << list.body;
  EXPECT_TRUE(Has(list.body, "\"stage\":\"\",\"fraction\":0,\"progress\":\"\"")) << list.body;
}

TEST_F(DiagnosesEndpointsTest, OneDiagnosisCarriesItsReportParsedAndItsFilesNames) {
  HttpResponse one = Get("/api/diagnoses/hose-done");
  ASSERT_EQ(one.status, 200);
  EXPECT_TRUE(one.body.rfind("{\"diagnosis\":{\"diagnosis_id\":\"hose-done\"", 0) == 0) << one.body;
  // The report as stored, without its closing newline.
  const std::string report(kReport, sizeof kReport - 2);
  EXPECT_TRUE(Has(one.body, "\"report\":" + report + ",\"report_error\":\"\"")) << one.body;
  EXPECT_TRUE(Has(one.body, R"("files":["corrected-model.yaml","diagnosis.json","located.svg"]})"))
      << one.body;
  // Running: no report and no files yet.
  HttpResponse running = Get("/api/diagnoses/hose-running");
  EXPECT_TRUE(Has(running.body, "\"report\":null,\"report_error\":\"\",\"files\":[]")) << running.body;
  // A report that is not JSON is said so, not passed on broken.
  HttpResponse bad = Get("/api/diagnoses/hose-bad");
  ASSERT_EQ(bad.status, 200);
  EXPECT_TRUE(Has(bad.body, "\"report\":null,\"report_error\":\"the stored report is not JSON"))
      << bad.body;
  // Unchanged: 304 without a body.
  HttpResponse again = Get("/api/diagnoses/hose-done", "", one.etag);
  EXPECT_EQ(again.status, 304);
  EXPECT_TRUE(again.body.empty());
}

TEST_F(DiagnosesEndpointsTest, FilesComeWithTheirContentTypesAndTheSvgWithItsOwnPolicy) {
  HttpResponse svg = Get("/api/diagnoses/hose-done/files/located.svg");
  ASSERT_EQ(svg.status, 200);
  EXPECT_EQ(svg.content_type, "image/svg+xml");
  EXPECT_EQ(svg.body, kSvg);
  EXPECT_EQ(svg.headers["Content-Security-Policy"], kSvgCsp);
  EXPECT_FALSE(svg.etag.empty());
  HttpResponse json = Get("/api/diagnoses/hose-done/files/diagnosis.json");
  EXPECT_EQ(json.content_type, "application/json");
  EXPECT_EQ(json.body, kReport);
  HttpResponse yaml = Get("/api/diagnoses/hose-done/files/corrected-model.yaml");
  EXPECT_EQ(yaml.content_type, "text/yaml; charset=utf-8");
  EXPECT_TRUE(Has(yaml.body, "caterpillar.distance"));
  EXPECT_EQ(Get("/api/diagnoses/hose-done/files/located.svg", "", svg.etag).status, 304);
  EXPECT_EQ(dashboard::DiagnosisFileType("x.bin"), "application/octet-stream");
}

TEST_F(DiagnosesEndpointsTest, MissingDiagnosesFilesAndEndpointsAre404WithAMessage) {
  HttpResponse none = Get("/api/diagnoses/nope");
  EXPECT_EQ(none.status, 404);
  EXPECT_EQ(none.body, "{\"error\":\"no diagnosis with id 'nope'\",\"code\":\"NOT_FOUND\"}");
  EXPECT_EQ(Get("/api/diagnoses/nope/files/located.svg").status, 404);
  HttpResponse file = Get("/api/diagnoses/hose-done/files/diagnosis.svg");
  EXPECT_EQ(file.status, 404);
  EXPECT_TRUE(Has(file.body, "diagnosis hose-done has no file 'diagnosis.svg' (it has "
                             "corrected-model.yaml, diagnosis.json, located.svg)"))
      << file.body;
  HttpResponse early = Get("/api/diagnoses/hose-running/files/located.svg");
  EXPECT_EQ(early.status, 404);
  EXPECT_TRUE(Has(early.body, "it has no files (they are kept once it completes)")) << early.body;
  HttpResponse what = Get("/api/diagnoses/hose-done/figures");
  EXPECT_EQ(what.status, 404);
  EXPECT_TRUE(Has(what.body, "a diagnosis has: /api/diagnoses/ID")) << what.body;
  // A dashboard without diagnoses says so.
  HttpResponse without = GetFrom(DashboardApi(*coord_, auth_), "/api/diagnoses");
  EXPECT_EQ(without.status, 404);
  EXPECT_TRUE(Has(without.body, "this dashboard serves no diagnoses")) << without.body;
}

TEST_F(DiagnosesEndpointsTest, TokensAreTheGrpcApisOnes) {
  auth_.Add(coordinator::Role::kClient, kClient);
  auth_.Add(coordinator::Role::kWorker, kWorker);
  for (const char* p : {"/api/diagnoses", "/api/diagnoses/hose-done",
                        "/api/diagnoses/hose-done/files/located.svg"}) {
    EXPECT_EQ(Get(p).status, 401) << p;
    EXPECT_EQ(Get(p, kWorker).status, 403) << p;
    EXPECT_EQ(Get(p, kClient).status, 200) << p;
  }
}

// The SVG over a real socket: its own policy replaces the page's (one header, not two).
TEST_F(DiagnosesEndpointsTest, ServesTheSvgWithOnlyItsOwnPolicy) {
  DashboardApi api(*coord_, auth_, diagnoses_.get());
  auto server = dashboard::HttpServer::Start("127.0.0.1:0", api);
  ASSERT_TRUE(server.ok()) << server.status();
  char err[256] = {0};
  mg_connection* c = mg_download("127.0.0.1", (*server)->port(), 0, err, sizeof err,
                                 "GET /api/diagnoses/hose-done/files/located.svg HTTP/1.1\r\n"
                                 "Host: 127.0.0.1\r\n\r\n");
  ASSERT_NE(c, nullptr) << err;
  const mg_response_info* info = mg_get_response_info(c);
  EXPECT_EQ(info->status_code, 200);
  std::vector<std::string> policies;
  std::string type;
  for (int i = 0; i < info->num_headers; ++i) {
    const std::string name = info->http_headers[i].name;
    if (name == "Content-Security-Policy") policies.push_back(info->http_headers[i].value);
    if (name == "Content-Type") type = info->http_headers[i].value;
  }
  mg_close_connection(c);
  EXPECT_EQ(type, "image/svg+xml");
  ASSERT_EQ(policies.size(), 1u);
  EXPECT_EQ(policies[0], kSvgCsp);
}

}  // namespace
}  // namespace gaitforge::testing
