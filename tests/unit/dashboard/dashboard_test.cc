// The dashboard's HTTP API over a real Coordinator and SQLite file: every endpoint's JSON,
// errors (404, 400, 405), ETags, the token rules shared with the gRPC API, the embedded
// page, and the same over a real loopback socket.
#include <civetweb.h>
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "services/dashboard/dashboard_api.h"
#include "services/dashboard/http_server.h"
#include "services/dashboard/study_robot.h"
#include "tests/integration/study_driver.h"
#include "tests/support/temp_dir.h"
#include "tests/unit/dashboard/requests.h"

namespace gaitforge::testing {
namespace {

using dashboard::DashboardApi;
using dashboard::HttpRequest;
using dashboard::HttpResponse;

class DashboardTest : public ::testing::Test {
 protected:
  void SetUp() override {
    auto store = storage::OpenSqliteStore(dir_.File("d.db"));
    ASSERT_TRUE(store.ok()) << store.status();
    coord_ = std::make_unique<coordinator::Coordinator>(std::move(*store),
                                                        coordinator::CoordinatorOptions{}, clock_);
    auto s = coord_->CreateStudy(SmallSpec(3, 12, 4));
    ASSERT_TRUE(s.ok()) << s.status();
    id_ = s->study_id();
    Drive(*coord_, {});
  }

  HttpResponse Get(const std::string& path, const std::string& token = "",
                   std::map<std::string, std::string> query = {}) {
    return GetFrom(DashboardApi(*coord_, auth_), path, token, std::move(query));
  }

  void RequireTokens() {
    auth_.Add(coordinator::Role::kClient, kClient);
    auth_.Add(coordinator::Role::kWorker, kWorker);
    auth_.Add(coordinator::Role::kAdmin, kAdmin);
  }

  TempDir dir_;
  core::ManualClock clock_;
  coordinator::Auth auth_;
  std::unique_ptr<coordinator::Coordinator> coord_;
  std::string id_;
};

TEST_F(DashboardTest, ListsStudiesAndServesAStudyAsTheProtoJson) {
  HttpResponse list = Get("/api/studies");
  EXPECT_EQ(list.status, 200);
  EXPECT_EQ(list.content_type, "application/json");
  EXPECT_TRUE(Has(list.body, "\"study_id\":\"" + id_ + "\"")) << list.body;
  HttpResponse one = Get("/api/studies/" + id_);
  EXPECT_EQ(one.status, 200);
  EXPECT_TRUE(Has(one.body, "\"state\":\"STUDY_STATE_COMPLETED\"")) << one.body;
  EXPECT_TRUE(Has(one.body, "\"generations_done\":4")) << one.body;
  EXPECT_TRUE(Has(one.body, "\"stop_reason\":\"its 4 generations are done\"")) << one.body;
  HttpResponse p = Get("/api/studies/" + id_ + "/progress");
  EXPECT_EQ(p.status, 200);
  EXPECT_TRUE(Has(p.body, "\"generations_total\":4")) << p.body;
}

TEST_F(DashboardTest, HistorySinceAGenerationGivesOnlyTheNewerOnes) {
  HttpResponse all = Get("/api/studies/" + id_ + "/history");
  ASSERT_EQ(all.status, 200);
  for (int g = 0; g < 4; ++g) EXPECT_TRUE(Has(all.body, "\"generation\":" + std::to_string(g)));
  EXPECT_TRUE(Has(all.body, "\"invalid\":0") && Has(all.body, "\"invalid_reason\":\"\""));
  HttpResponse newer = Get("/api/studies/" + id_ + "/history", "", {{"since", "3"}});
  EXPECT_FALSE(Has(newer.body, "\"generation\":2")) << newer.body;
  EXPECT_TRUE(Has(newer.body, "\"generation\":3")) << newer.body;
  HttpResponse none = Get("/api/studies/" + id_ + "/history", "", {{"since", "4"}});
  EXPECT_EQ(none.body, "{\"generations\":[]}");
  HttpResponse bad = Get("/api/studies/" + id_ + "/history", "", {{"since", "x"}});
  EXPECT_EQ(bad.status, 400);
  EXPECT_TRUE(Has(bad.body, "since: expected a whole number (0 or more), got 'x'")) << bad.body;
}

TEST_F(DashboardTest, HallOfFameAndMembersOfAGeneration) {
  HttpResponse hof = Get("/api/studies/" + id_ + "/hall-of-fame");
  ASSERT_EQ(hof.status, 200);
  EXPECT_TRUE(Has(hof.body, "\"generation\":3") && Has(hof.body, "\"rank\":0")) << hof.body;
  HttpResponse early = Get("/api/studies/" + id_ + "/hall-of-fame", "", {{"generation", "1"}});
  EXPECT_TRUE(Has(early.body, "\"generation\":1")) << early.body;
  HttpResponse late = Get("/api/studies/" + id_ + "/hall-of-fame", "", {{"generation", "9"}});
  EXPECT_EQ(late.status, 404);
  EXPECT_TRUE(Has(late.body, "generation = 9 is out of range")) << late.body;
  HttpResponse members = Get("/api/studies/" + id_ + "/individuals", "", {{"generation", "0"}});
  ASSERT_EQ(members.status, 200);
  EXPECT_TRUE(Has(members.body, "\"member\":11") && Has(members.body, "\"worker_id\":\"driver\""));
  EXPECT_EQ(Get("/api/studies/" + id_ + "/individuals").status, 400);
}

TEST_F(DashboardTest, UnknownStudiesAndEndpointsAre404WithAMessage) {
  HttpResponse r = Get("/api/studies/no-such-study");
  EXPECT_EQ(r.status, 404);
  EXPECT_EQ(r.body, "{\"error\":\"no study with id 'no-such-study'\",\"code\":\"NOT_FOUND\"}");
  EXPECT_EQ(Get("/api/studies/no-such-study/history").status, 404);
  HttpResponse what = Get("/api/studies/" + id_ + "/genes");
  EXPECT_EQ(what.status, 404);
  EXPECT_TRUE(Has(what.body, "a study has: progress, history")) << what.body;
  EXPECT_EQ(Get("/api/nothing").status, 404);
  EXPECT_EQ(Get("/no-page.html").status, 404);
}

TEST_F(DashboardTest, IsReadOnly) {
  HttpRequest r;
  r.method = "POST";
  r.path = "/api/studies";
  HttpResponse out = DashboardApi(*coord_, auth_).Handle(r);
  EXPECT_EQ(out.status, 405);
  EXPECT_EQ(out.headers["Allow"], "GET, HEAD");
}

TEST_F(DashboardTest, AnUnchangedAnswerIsA304WithoutBody) {
  HttpResponse first = Get("/api/studies/" + id_ + "/history");
  ASSERT_FALSE(first.etag.empty());
  HttpResponse second =
      GetFrom(DashboardApi(*coord_, auth_), "/api/studies/" + id_ + "/history", "", {}, first.etag);
  EXPECT_EQ(second.status, 304);
  EXPECT_TRUE(second.body.empty());
}

TEST_F(DashboardTest, ServesTheEmbeddedPage) {
  HttpResponse page = Get("/");
  EXPECT_EQ(page.status, 200);
  EXPECT_EQ(page.content_type, "text/html; charset=utf-8");
  EXPECT_TRUE(Has(page.body, "<script src=\"app.js\">")) << page.body;
  for (const char* f : {"/app.js", "/study.js", "/diagnosis.js", "/report.js", "/gait.js", "/style.css",
                        "/vendor/uPlot.iife.min.js", "/vendor/uPlot.min.css"})
    EXPECT_EQ(Get(f).status, 200) << f;
}

TEST_F(DashboardTest, TokensAreTheGrpcApisOnes) {
  RequireTokens();
  HttpResponse none = Get("/api/studies");
  EXPECT_EQ(none.status, 401);
  EXPECT_EQ(none.headers["WWW-Authenticate"], "Bearer realm=\"gaitforge\"");
  EXPECT_TRUE(Has(none.body, "missing 'authorization: Bearer TOKEN' header")) << none.body;
  EXPECT_EQ(Get("/api/studies", "not-a-known-token-at-all").status, 401);
  HttpResponse worker = Get("/api/studies/" + id_, kWorker);
  EXPECT_EQ(worker.status, 403);
  EXPECT_TRUE(Has(worker.body, "a worker token cannot call this")) << worker.body;
  EXPECT_EQ(Get("/api/studies/" + id_, kClient).status, 200);
  EXPECT_EQ(Get("/api/studies/" + id_ + "/history", kAdmin).status, 200);
  // The page carries no data: it loads without a token and then asks for one.
  EXPECT_EQ(Get("/").status, 200);
}

TEST(StudyRobot, NamesTheControllerTheGenesDrive) {
  v1::StudySpec spec;
  spec.mutable_objective()->set_name("caterpillar.distance");
  const std::string cat = dashboard::StudyRobotJson(spec);
  EXPECT_TRUE(Has(cat, "\"robot\":\"caterpillar\"") && Has(cat, "\"kind\":\"phase_onoff\"")) << cat;
  EXPECT_TRUE(Has(cat, "\"B3\"") && Has(cat, "\"name\":\"a_T1\"")) << cat;
  // A robot that is only data: the descriptor the spec carries.
  std::ifstream in(GAITFORGE_SOURCE_DIR "/tests/fixtures/robots/twobox/robot.yaml");
  std::stringstream text;
  text << in.rdbuf();
  spec.mutable_objective()->set_name("robot.distance");
  spec.mutable_objective()->set_robot("twobox");
  spec.mutable_objective()->set_robot_descriptor(text.str());
  const std::string twobox = dashboard::StudyRobotJson(spec);
  EXPECT_TRUE(Has(twobox, "\"robot\":\"twobox\"") && Has(twobox, "\"kind\":\"sine\"")) << twobox;
  // A calibration's genes are parameters: the robot, no controller to draw them with.
  spec.mutable_objective()->set_name("robot.calibration");
  const std::string fit = dashboard::StudyRobotJson(spec);
  EXPECT_TRUE(Has(fit, "\"robot\":\"twobox\"") && Has(fit, "\"controller\":null") &&
              Has(fit, "the robot's parameters")) << fit;
  spec.clear_objective();
  spec.mutable_objective()->set_name("caterpillar.calibration");
  const std::string own = dashboard::StudyRobotJson(spec);
  EXPECT_TRUE(Has(own, "\"robot\":\"caterpillar\"") && Has(own, "\"controller\":null")) << own;
  spec.mutable_objective()->set_name("analytic.sphere");
  const std::string none = dashboard::StudyRobotJson(spec);
  EXPECT_TRUE(Has(none, "\"controller\":null") && Has(none, "drives no robot")) << none;
}

// GET over a real socket with civetweb's own client: status line and body.
std::string HttpGet(int port, const std::string& path, const std::string& token) {
  char err[256] = {0};
  const std::string auth = token.empty() ? "" : "Authorization: Bearer " + token + "\r\n";
  mg_connection* c = mg_download("127.0.0.1", port, 0, err, sizeof err,
                                 "GET %s HTTP/1.1\r\nHost: 127.0.0.1\r\n%s\r\n", path.c_str(),
                                 auth.c_str());
  if (c == nullptr) return std::string("error: ") + err;
  std::string out = std::to_string(mg_get_response_info(c)->status_code) + " ";
  char buf[4096];
  for (int n; (n = mg_read(c, buf, sizeof buf)) > 0;) out.append(buf, n);
  mg_close_connection(c);
  return out;
}

TEST_F(DashboardTest, ServesOverLoopback) {
  RequireTokens();
  DashboardApi api(*coord_, auth_);
  auto server = dashboard::HttpServer::Start("127.0.0.1:0", api);
  ASSERT_TRUE(server.ok()) << server.status();
  const int port = (*server)->port();
  ASSERT_GT(port, 0);
  EXPECT_EQ((*server)->url(), "http://127.0.0.1:" + std::to_string(port) + "/");
  EXPECT_TRUE(HttpGet(port, "/api/studies", "").rfind("401 {", 0) == 0);
  const std::string ok = HttpGet(port, "/api/studies/" + id_ + "/history?since=3", kClient);
  EXPECT_TRUE(ok.rfind("200 {\"generations\":[{\"generation\":3,", 0) == 0) << ok;
  EXPECT_TRUE(HttpGet(port, "/", "").rfind("200 <!doctype html>", 0) == 0);
  // A port in use is refused with the reason.
  auto second = dashboard::HttpServer::Start("127.0.0.1:" + std::to_string(port), api);
  ASSERT_FALSE(second.ok());
  EXPECT_TRUE(Has(std::string(second.status().message()),
                  "cannot serve the dashboard on 127.0.0.1:" + std::to_string(port)))
      << second.status();
}

}  // namespace
}  // namespace gaitforge::testing
