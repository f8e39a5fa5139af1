#include "tests/e2e/cluster.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <sqlite3.h>
#include <stdio.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <regex>
#include <thread>

#include "clients/cli/processes.h"
#include "tests/support/temp_dir.h"

namespace gaitforge::testing {

std::string Bin(const std::string& name) { return std::string(GAITFORGE_BIN_DIR) + "/" + name; }

std::string RunClusterStudy(const TempDir& dir, const std::string& db, const std::string& text,
                            int workers) {
  WriteFile(dir.File("spec.yaml"), text);
  LocalCluster cluster(dir.path(), db);
  if (!cluster.ok()) return "";
  auto submit = cluster.Cli("submit " + dir.File("spec.yaml"));
  EXPECT_EQ(submit.exit_code, 0) << submit.err;
  const std::string id = submit.out.substr(0, submit.out.find('\n'));
  cluster.StartWorkers(workers);
  auto watch = cluster.Cli("watch " + id + " --json");
  EXPECT_EQ(watch.exit_code, 0) << watch.err;
  EXPECT_NE(watch.out.find("STUDY_STATE_COMPLETED"), std::string::npos) << watch.out;
  return id;
}

std::string RunLocal(const TempDir& dir, const std::string& text, const std::string& expect) {
  WriteFile(dir.File("spec.yaml"), text);
  const std::string cli = "cd " + dir.path() + " && " + Bin("gaitforge");
  auto r = RunCommand(cli + " local spec.yaml --workers 2");
  EXPECT_EQ(r.exit_code, 0) << r.err;
  EXPECT_NE(r.err.find(expect), std::string::npos) << r.err;
  auto list = RunCommand(cli + " list --json");
  std::smatch m;
  if (!std::regex_search(list.out, m, std::regex(R"re("study_id":"([^"]+)")re"))) {
    ADD_FAILURE() << list.out;
    return "";
  }
  return m[1].str();
}

std::vector<std::string> Rows(const std::string& db, const std::string& sql) {
  sqlite3* h = nullptr;
  EXPECT_EQ(sqlite3_open_v2(db.c_str(), &h, SQLITE_OPEN_READONLY, nullptr), SQLITE_OK);
  sqlite3_stmt* st = nullptr;
  EXPECT_EQ(sqlite3_prepare_v2(h, sql.c_str(), -1, &st, nullptr), SQLITE_OK) << sql;
  std::vector<std::string> rows;
  while (sqlite3_step(st) == SQLITE_ROW) {
    std::string row;
    for (int c = 0; c < sqlite3_column_count(st); ++c) {
      const auto* t = sqlite3_column_text(st, c);
      row += (t ? reinterpret_cast<const char*>(t) : "NULL") + std::string("|");
    }
    rows.push_back(row);
  }
  sqlite3_finalize(st);
  sqlite3_close(h);
  return rows;
}

CommandResult RunCommand(const std::string& command_line) {
  static int counter = 0;
  const std::string err_file = (std::filesystem::temp_directory_path() /
                                ("gaitforge-e2e-err-" + std::to_string(getpid()) + "-" +
                                 std::to_string(counter++)))
                                   .string();
  CommandResult r;
  FILE* p = popen((command_line + " 2>" + err_file).c_str(), "r");
  if (!p) return r;
  char buf[4096];
  size_t n;
  while ((n = fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int status = pclose(p);
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = ReadFile(err_file);
  std::filesystem::remove(err_file);
  return r;
}

LocalCluster::LocalCluster(const std::string& dir, const std::string& db,
                           const std::vector<std::string>& extra_flags)
    : dir_(dir), db_(db) {
  const std::string port_file = dir + "/coordinator.port";
  std::filesystem::remove(port_file);
  std::vector<std::string> argv = {Bin("gaitforge-coordinator"), "--listen", "127.0.0.1:0",
                                   "--db", db, "--port-file", port_file, "--log-level", "warn"};
  argv.insert(argv.end(), extra_flags.begin(), extra_flags.end());
  coordinator_ = cli::Spawn(argv, dir + "/coordinator.log");
  const int port = cli::WaitForPortFile(port_file, coordinator_, 30);
  if (port < 0) {
    ADD_FAILURE() << "coordinator did not start:\n" << ReadFile(dir + "/coordinator.log");
    coordinator_ = -1;
    return;
  }
  target_ = "127.0.0.1:" + std::to_string(port);
  // A second line holds the metrics port when --metrics-listen is on.
  std::ifstream pf(port_file);
  int first = 0;
  if (pf >> first >> metrics_port_) {
  } else {
    metrics_port_ = -1;
  }
  const bool tls = std::find(extra_flags.begin(), extra_flags.end(), "--tls-cert") != extra_flags.end();
  if (tls) target_ = "127.0.0.1:" + std::to_string(port);
}

LocalCluster::~LocalCluster() {
  StopWorkers();
  StopCoordinator();
}

void LocalCluster::StartWorkers(int n, int threads, const std::vector<std::string>& extra_flags) {
  for (int i = 0; i < n; ++i) {
    const std::string id = "w" + std::to_string(workers_.size());
    std::vector<std::string> argv = {Bin("gaitforge-worker"), "--coordinator", target_,
                                     "--threads", std::to_string(threads), "--worker-id", id,
                                     "--log-level", "warn"};
    argv.insert(argv.end(), extra_flags.begin(), extra_flags.end());
    workers_.push_back(cli::Spawn(argv, dir_ + "/" + id + ".log"));
  }
}

std::string WaitForGenerations(const std::string& cli, int generations) {
  for (int i = 0; i < 1200; ++i) {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    auto list = RunCommand(cli + " list --json");
    const size_t at = list.out.find("\"generations_done\":");
    if (at == std::string::npos || std::atoi(list.out.c_str() + at + 19) < generations) continue;
    const size_t from = list.out.find("\"study_id\":\"") + 12;
    return list.out.substr(from, list.out.find('"', from) - from);
  }
  return "";
}

std::string HttpGet(int port, const std::string& path) {
  const int fd = socket(AF_INET, SOCK_STREAM, 0);
  if (fd < 0) return "";
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_port = htons(static_cast<uint16_t>(port));
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  if (connect(fd, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0) {
    close(fd);
    return "";
  }
  const std::string req = "GET " + path + " HTTP/1.0\r\nHost: 127.0.0.1\r\n\r\n";
  (void)!write(fd, req.data(), req.size());
  std::string resp;
  char buf[4096];
  ssize_t n;
  while ((n = read(fd, buf, sizeof buf)) > 0) resp.append(buf, n);
  close(fd);
  const size_t body = resp.find("\r\n\r\n");
  return body == std::string::npos ? "" : resp.substr(body + 4);
}

void LocalCluster::StopWorkers() {
  for (pid_t p : workers_) cli::Stop(p, 10);
  workers_.clear();
}

void LocalCluster::StopCoordinator() {
  if (coordinator_ > 0) cli::Stop(coordinator_, 10);
  coordinator_ = -1;
}

void LocalCluster::KillCoordinator() {
  if (coordinator_ > 0) {
    kill(coordinator_, SIGKILL);
    waitpid(coordinator_, nullptr, 0);
  }
  coordinator_ = -1;
}

CommandResult LocalCluster::Cli(const std::string& args) const {
  return RunCommand(Bin("gaitforge") + " --coordinator " + target_ + " " + args);
}

}  // namespace gaitforge::testing
