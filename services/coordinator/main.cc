// gaitforge-coordinator: holds studies (engine + job queue + SQLite store) and serves the
// StudyService, the WorkerService and grpc.health.v1 on one port.
#include <grpcpp/grpcpp.h>
#include <grpcpp/health_check_service_interface.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/file.h>
#include <unistd.h>
#include <spdlog/spdlog.h>

#include <atomic>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "services/coordinator/coordinator.h"
#include "services/coordinator/services.h"
#include "services/core/flags.h"
#include "services/core/logging.h"

using namespace gaitforge;

namespace {

constexpr int kMaxMessageBytes = 64 << 20;

int Fail(const std::string& msg) {
  std::cerr << "gaitforge-coordinator: " << msg << "\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  std::string listen = "127.0.0.1:50051";
  std::string db = "runs/gaitforge.db";
  std::string port_file;
  std::string sync = "full";
  std::string log_level = "info";
  int64_t lease_ms = 10000;
  int max_attempts = 3;
  int64_t backup_after_ms = 2000;
  bool read_only = false;
  core::Flags flags("gaitforge-coordinator [flags]",
                    "Holds studies (engine + job queue + SQLite results database) and serves "
                    "gaitforge.v1.StudyService, gaitforge.v1.WorkerService and grpc.health.v1.\n"
                    "On start it resumes every study the database says is running.");
  flags.Add("listen", &listen, "address to serve on, host:port (port 0: any free port)");
  flags.Add("db", &db, "SQLite results database (created if missing; never on NFS)");
  flags.Add("port-file", &port_file, "write the bound port here once serving");
  flags.Add("sync", &sync, "SQLite durability: full (survives power loss) or normal");
  flags.Add("lease-ms", &lease_ms, "job lease length in ms; heartbeats renew it");
  flags.Add("max-attempts", &max_attempts, "lost leases before a job is closed as poisoned");
  flags.Add("backup-after-ms", &backup_after_ms,
            "hand out backup copies of jobs leased this long when the queue is empty (0: off)");
  flags.AddBool("read-only", &read_only, "serve queries only: resume nothing, accept no study");
  flags.Add("log-level", &log_level, "trace, debug, info, warn, error or off");
  if (auto s = flags.Parse(argc, argv); !s.ok()) return Fail(std::string(s.message()));
  if (flags.help_requested()) {
    std::cout << flags.Help();
    return 0;
  }
  if (!flags.positional().empty()) return Fail("unexpected argument '" + flags.positional()[0] + "'");
  if (sync != "full" && sync != "normal") return Fail("--sync: expected full or normal, got '" + sync + "'");
  if (lease_ms < 100 || lease_ms > 3600000) return Fail("--lease-ms: out of range [100, 3600000]");
  if (max_attempts < 1 || max_attempts > 100) return Fail("--max-attempts: out of range [1, 100]");
  core::SetupLogging("coordinator", log_level);

  // Signals go to one thread that waits for them.
  sigset_t sigs;
  sigemptyset(&sigs);
  sigaddset(&sigs, SIGINT);
  sigaddset(&sigs, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &sigs, nullptr);

  std::error_code ec;
  const auto parent = std::filesystem::path(db).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent, ec);
  // One writing coordinator per database: a second would resume the same studies.
  if (!read_only) {
    const std::string lock_path = db + ".lock";
    const int fd = open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd < 0) return Fail("cannot open lock file " + lock_path);
    if (flock(fd, LOCK_EX | LOCK_NB) != 0) {
      char buf[32] = {0};
      (void)!pread(fd, buf, sizeof buf - 1, 0);
      return Fail("database " + db + " is in use by another coordinator (pid " +
                  std::string(buf).substr(0, std::string(buf).find('\n')) +
                  "); talk to it with --coordinator, or stop it first");
    }
    const std::string pid = std::to_string(getpid()) + "\n";
    (void)!ftruncate(fd, 0);
    (void)!pwrite(fd, pid.data(), pid.size(), 0);
    // fd stays open (and locked) for the life of the process.
  }
  auto store = storage::OpenSqliteStore(db, storage::Durability{sync == "full"});
  if (!store.ok()) return Fail(std::string(store.status().message()));

  coordinator::CoordinatorOptions options;
  options.lease_ms = lease_ms;
  options.max_attempts = max_attempts;
  options.backup_after_ms = backup_after_ms;
  options.read_only = read_only;
  options.db_path = std::filesystem::absolute(db).string();
  coordinator::Coordinator coord(std::move(*store), options, core::RealClock());
  if (auto s = coord.RecoverStudies(); !s.ok()) return Fail(std::string(s.message()));

  coordinator::StudyServiceImpl study_service(coord);
  coordinator::WorkerServiceImpl worker_service(coord);
  grpc::EnableDefaultHealthCheckService(true);
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(listen, grpc::InsecureServerCredentials(), &port);
  builder.RegisterService(&study_service);
  builder.RegisterService(&worker_service);
  builder.SetMaxReceiveMessageSize(kMaxMessageBytes);
  builder.SetMaxSendMessageSize(kMaxMessageBytes);
  // Keepalive on both sides (../shared/guides/distributed-notes.md): accept client pings
  // every 10 s even without calls, and ping idle clients every 30 s.
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, 30000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 10000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS, 5000);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MAX_PING_STRIKES, 0);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) return Fail("cannot listen on " + listen);
  spdlog::info("serving on port {} with database {}", port, options.db_path);
  if (!port_file.empty()) {
    const std::string tmp = port_file + ".tmp";
    std::ofstream(tmp) << port << "\n";
    std::filesystem::rename(tmp, port_file, ec);
    if (ec) return Fail("cannot write --port-file " + port_file + ": " + ec.message());
  }

  std::atomic<bool> stop{false};
  std::thread ticker([&] {
    while (!stop.load()) {
      coord.Tick();
      std::this_thread::sleep_for(std::chrono::milliseconds(200));
    }
  });
  int sig = 0;
  sigwait(&sigs, &sig);
  spdlog::info("signal {}: shutting down", sig);
  coord.Shutdown();  // wakes long polls and watchers
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(3));
  stop = true;
  ticker.join();
  coord.Shutdown();
  spdlog::info("stopped");
  return 0;
}
