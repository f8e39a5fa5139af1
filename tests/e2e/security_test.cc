// Cluster-ready: tokens per role, TLS, limits, simulator builds and the metrics endpoint,
// against the real coordinator and workers on loopback.
#include <gtest/gtest.h>
#include <sqlite3.h>

#include <chrono>
#include <regex>
#include <thread>

#include "clients/cli/cli.h"
#include "gaitforge/v1/worker.grpc.pb.h"
#include "grpc/health/v1/health.grpc.pb.h"
#include "services/rpc/channel.h"
#include "tests/e2e/cluster.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {
namespace {

constexpr char kClient[] = "client-token-0123456789abcdef";
constexpr char kWorker[] = "worker-token-0123456789abcdef";
constexpr char kAdmin[] = "admin-token-0123456789abcdef00";

const char* kSpec = "name: sec\nseed: 5\npopulation: 20\ngenerations: 4\n"
                    "objective: {name: analytic.sphere}\n";

std::string Query(const std::string& db, const std::string& sql) {
  sqlite3* h = nullptr;
  sqlite3_open_v2(db.c_str(), &h, SQLITE_OPEN_READONLY, nullptr);
  sqlite3_stmt* st = nullptr;
  sqlite3_prepare_v2(h, sql.c_str(), -1, &st, nullptr);
  std::string out;
  if (sqlite3_step(st) == SQLITE_ROW && sqlite3_column_text(st, 0))
    out = reinterpret_cast<const char*>(sqlite3_column_text(st, 0));
  sqlite3_finalize(st);
  sqlite3_close(h);
  return out;
}

class Secured : public ::testing::Test {
 protected:
  void SetUp() override {
    WriteFile(dir_.File("tokens"), std::string("# role token\nclient ") + kClient +
                                       "\nworker " + kWorker + "\nadmin " + kAdmin + "\n");
    for (const auto& [name, token] : std::vector<std::pair<std::string, std::string>>{
             {"client.tok", kClient}, {"worker.tok", kWorker}, {"admin.tok", kAdmin}})
      WriteFile(dir_.File(name), token + "\n");
    WriteFile(dir_.File("spec.yaml"), kSpec);
    cluster_ = std::make_unique<LocalCluster>(
        dir_.path(), dir_.File("r.db"),
        std::vector<std::string>{"--tokens-file", dir_.File("tokens")});
    ASSERT_TRUE(cluster_->ok());
  }
  CommandResult Cli(const std::string& token_file, const std::string& args) {
    return cluster_->Cli((token_file.empty() ? "" : "--token-file " + dir_.File(token_file)) +
                         " " + args);
  }
  TempDir dir_;
  std::unique_ptr<LocalCluster> cluster_;
};

TEST_F(Secured, CallsWithoutTheRightTokenAreRejectedAndChangeNothing) {
  auto r = Cli("", "submit " + dir_.File("spec.yaml"));
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("missing 'authorization: Bearer TOKEN'"), std::string::npos) << r.err;
  r = Cli("worker.tok", "submit " + dir_.File("spec.yaml"));
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("a worker token cannot call this"), std::string::npos) << r.err;
  WriteFile(dir_.File("wrong.tok"), "not-a-known-token-at-all");
  EXPECT_EQ(Cli("wrong.tok", "list").exit_code, 6);
  EXPECT_EQ(Query(dir_.File("r.db"), "SELECT COUNT(*) FROM studies"), "0");

  // A client token cannot lease jobs; no token is unauthenticated.
  auto channel = cli::MakeChannel(cluster_->target());
  auto worker = v1::WorkerService::NewStub(channel);
  v1::LeaseRequest lease;
  lease.mutable_worker()->set_worker_id("intruder");
  lease.set_max_jobs(4);
  v1::LeaseResponse out;
  {
    grpc::ClientContext ctx;
    rpc::PrepareCall(ctx, 10, kClient);
    EXPECT_EQ(worker->Lease(&ctx, lease, &out).error_code(), grpc::StatusCode::PERMISSION_DENIED);
  }
  {
    grpc::ClientContext ctx;
    rpc::PrepareCall(ctx, 10, "");
    EXPECT_EQ(worker->Lease(&ctx, lease, &out).error_code(), grpc::StatusCode::UNAUTHENTICATED);
  }
  // Health stays open for probes.
  auto health = grpc::health::v1::Health::NewStub(channel);
  grpc::ClientContext ctx;
  rpc::PrepareCall(ctx, 10, "");
  grpc::health::v1::HealthCheckResponse h;
  EXPECT_TRUE(health->Check(&ctx, grpc::health::v1::HealthCheckRequest(), &h).ok());
}

TEST_F(Secured, TheRightTokensRunAStudyAndTheAdminMaySeeIt) {
  auto r = Cli("client.tok", "submit " + dir_.File("spec.yaml"));
  ASSERT_EQ(r.exit_code, 0) << r.err;
  const std::string id = r.out.substr(0, r.out.find('\n'));
  // Workers without a token get nothing; with one, they finish the study.
  cluster_->StartWorkers(1);
  cluster_->StartWorkers(2, 1, {"--token-file", dir_.File("worker.tok")});
  auto w = Cli("client.tok", "watch " + id);
  EXPECT_EQ(w.exit_code, 0) << w.err;
  // Every evaluation came from a worker holding the worker token (w1, w2), none from w0.
  EXPECT_EQ(Query(dir_.File("r.db"), "SELECT COUNT(*) FROM individuals WHERE carried = 0 AND "
                                     "worker_id NOT IN ('w1', 'w2')"),
            "0");
  EXPECT_NE(Query(dir_.File("r.db"), "SELECT COUNT(*) FROM individuals WHERE carried = 0"), "0");
  EXPECT_EQ(Query(dir_.File("r.db"), "SELECT COUNT(*) FROM individuals WHERE worker_id = 'w0'"),
            "0");
  EXPECT_EQ(Cli("admin.tok", "show " + id).exit_code, 0);
}

TEST(Limits, OversizedMessagesAreRefusedWithAClearError) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("r.db"), {"--max-message-mb", "1"});
  ASSERT_TRUE(cluster.ok());
  auto worker = v1::WorkerService::NewStub(cli::MakeChannel(cluster.target()));
  v1::ReportRequest big;
  big.mutable_worker()->set_worker_id("w");
  auto* res = big.add_results();
  res->mutable_evaluation()->set_reason(std::string(2 << 20, 'x'));
  grpc::ClientContext ctx;
  rpc::PrepareCall(ctx, 10, "");
  v1::ReportResponse out;
  grpc::Status s = worker->Report(&ctx, big, &out);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::RESOURCE_EXHAUSTED) << s.error_message();
  EXPECT_NE(s.error_message().find("larger than max"), std::string::npos) << s.error_message();
  // Too large a batch is refused by value.
  v1::LeaseRequest lease;
  lease.mutable_worker()->set_worker_id("w");
  lease.set_max_jobs(5000);
  grpc::ClientContext ctx2;
  rpc::PrepareCall(ctx2, 10, "");
  v1::LeaseResponse lo;
  s = worker->Lease(&ctx2, lease, &lo);
  EXPECT_EQ(s.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_NE(s.error_message().find("max_jobs' = 5000 is out of range [1, 1024]"), std::string::npos);
}

TEST(Tls, AHandshakeWithATestCaWorksAndPlaintextFails) {
  TempDir dir;
  const std::string d = dir.path();
  auto gen = RunCommand(
      "cd " + d + " && openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=test-ca "
      "-keyout ca.key -out ca.pem && openssl req -newkey rsa:2048 -nodes -subj /CN=127.0.0.1 "
      "-keyout server.key -out server.csr && printf 'subjectAltName=IP:127.0.0.1\\n' > san.ext "
      "&& openssl x509 -req -in server.csr -CA ca.pem -CAkey ca.key -CAcreateserial -days 2 "
      "-extfile san.ext -out server.pem && openssl req -x509 -newkey rsa:2048 -nodes -days 2 "
      "-subj /CN=other-ca -keyout other.key -out other.pem");
  ASSERT_EQ(gen.exit_code, 0) << gen.err;
  LocalCluster cluster(d, dir.File("r.db"),
                       {"--tls-cert", dir.File("server.pem"), "--tls-key", dir.File("server.key")});
  ASSERT_TRUE(cluster.ok());
  auto ok = cluster.Cli("--tls-ca " + dir.File("ca.pem") + " list --json");
  EXPECT_EQ(ok.exit_code, 0) << ok.err;
  auto plain = cluster.Cli("--timeout 3 list");
  EXPECT_EQ(plain.exit_code, 4) << plain.err;
  auto wrong_ca = cluster.Cli("--timeout 3 --tls-ca " + dir.File("other.pem") + " list");
  EXPECT_EQ(wrong_ca.exit_code, 4) << wrong_ca.err;
  // A worker over TLS runs a study.
  WriteFile(dir.File("spec.yaml"), kSpec);
  auto sub = cluster.Cli("--tls-ca " + dir.File("ca.pem") + " submit " + dir.File("spec.yaml"));
  ASSERT_EQ(sub.exit_code, 0) << sub.err;
  cluster.StartWorkers(1, 1, {"--tls-ca", dir.File("ca.pem")});
  auto w = cluster.Cli("--tls-ca " + dir.File("ca.pem") + " watch " +
                       sub.out.substr(0, sub.out.find('\n')));
  EXPECT_EQ(w.exit_code, 0) << w.err;
  // Plaintext on a listener other hosts can reach is refused at start.
  auto open = RunCommand(Bin("gaitforge-coordinator") + " --listen 0.0.0.0:0 --db " +
                         dir.File("x.db"));
  EXPECT_EQ(open.exit_code, 2);
  EXPECT_NE(open.err.find("needs TLS"), std::string::npos) << open.err;
}

double Metric(const std::string& text, const std::string& name) {
  std::smatch m;
  const std::regex re("\\n" + std::regex_replace(name, std::regex(R"([{}"])"), R"(\$&)") +
                      R"( ([-0-9.e+]+))");
  return std::regex_search(text, m, re) ? std::stod(m[1]) : -1;
}

TEST(Metrics, TheEndpointAgreesWithTheDatabaseAfterAStudy) {
  TempDir dir;
  LocalCluster cluster(dir.path(), dir.File("r.db"), {"--metrics-listen", "127.0.0.1:0"});
  ASSERT_TRUE(cluster.ok());
  ASSERT_GT(cluster.metrics_port(), 0);
  WriteFile(dir.File("spec.yaml"), kSpec);
  auto sub = cluster.Cli("submit " + dir.File("spec.yaml"));
  ASSERT_EQ(sub.exit_code, 0) << sub.err;
  const std::string id = sub.out.substr(0, sub.out.find('\n'));
  cluster.StartWorkers(2);
  ASSERT_EQ(cluster.Cli("watch " + id).exit_code, 0);
  const std::string text = "\n" + HttpGet(cluster.metrics_port(), "/metrics");
  const std::string db = dir.File("r.db");
  const double evaluated = Metric(text, "gaitforge_evaluations_total{outcome=\"valid\"}") +
                           Metric(text, "gaitforge_evaluations_total{outcome=\"invalid\"}") +
                           Metric(text, "gaitforge_evaluations_total{outcome=\"poisoned\"}");
  EXPECT_EQ(evaluated, std::stod(Query(db, "SELECT evaluations FROM studies")));
  EXPECT_EQ(evaluated, std::stod(Query(db, "SELECT COUNT(*) FROM individuals WHERE carried = 0")));
  EXPECT_EQ(Metric(text, "gaitforge_study_generations_done{study=\"" + id + "\"}"), 4);
  EXPECT_DOUBLE_EQ(Metric(text, "gaitforge_study_best_fitness{study=\"" + id + "\"}"),
                   std::stod(Query(db, "SELECT best_fitness FROM studies")));
  EXPECT_EQ(Metric(text, "gaitforge_leases_total"),
            std::stod(Query(db, "SELECT SUM(leases) FROM generations")));
  EXPECT_EQ(Metric(text, "gaitforge_evaluation_duration_seconds_count"), evaluated);
  EXPECT_GT(Metric(text, "gaitforge_sqlite_commit_seconds_count"), 0);
  // The queue gauges are sampled every 200 ms (Tick, docs/metrics.md): the scrape right
  // after the study ends may predate the sample that sees the queue drained. Within a few
  // ticks it must read 0.
  double depth = Metric(text, "gaitforge_queue_depth");
  for (int i = 0; i < 50 && depth != 0; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    depth = Metric("\n" + HttpGet(cluster.metrics_port(), "/metrics"), "gaitforge_queue_depth");
  }
  EXPECT_EQ(depth, 0);
}

// Stored diagnoses obey the same tokens as studies.
TEST_F(Secured, DiagnosesNeedAClientToken) {
  auto r = Cli("", "diagnoses");
  EXPECT_EQ(r.exit_code, 6) << r.err;
  EXPECT_NE(r.err.find("missing 'authorization: Bearer TOKEN'"), std::string::npos) << r.err;
  EXPECT_EQ(Cli("worker.tok", "diagnoses").exit_code, 6);
  EXPECT_EQ(Cli("worker.tok", "diagnosis some-id").exit_code, 6);
  r = Cli("client.tok", "diagnoses --json");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_EQ(Cli("client.tok", "diagnosis no-such-id").exit_code, 3);
}

}  // namespace
}  // namespace gaitforge::testing
