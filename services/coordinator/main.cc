// gaitforge-coordinator: holds studies (engine + job queue + SQLite store) and serves the
// StudyService, the WorkerService, the RecordingService, the DiagnosisService and
// grpc.health.v1 on one port, and optionally the web dashboard (--dashboard-listen,
// docs/dashboard.md) and Prometheus metrics on their own.
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

#include <prometheus/exposer.h>

#include "services/coordinator/auth.h"
#include "services/coordinator/coordinator.h"
#include "services/coordinator/listen.h"
#include "services/coordinator/metrics.h"
#include "services/coordinator/diagnosis_service.h"
#include "services/coordinator/services.h"
#include "services/core/db_path.h"
#include "services/core/flags.h"
#include "services/core/logging.h"
#include "services/dashboard/http_server.h"
#include "services/rpc/process.h"

using namespace gaitforge;

namespace {


int Fail(const std::string& msg) {
  std::cerr << "gaitforge-coordinator: " << msg << "\n";
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  rpc::DisableAbslDeadlockDetection();
  std::string listen = "127.0.0.1:50051";
  std::string db = "runs/gaitforge.db";
  std::string port_file;
  std::string sync = "full";
  std::string log_level = "info";
  int64_t lease_ms = 10000;
  int max_attempts = 3;
  int64_t backup_after_ms = 2000;
  int max_message_mb = 64;
  int max_recording_mb = 64;
  bool read_only = false;
  bool insecure = false;
  std::string listen_interface, address_file, tokens_file, metrics_listen, dashboard_listen;
  std::string log_format = "text";
  coordinator::TlsFiles tls;
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
  flags.Add("listen-interface", &listen_interface,
            "listen on this network interface's IPv4 address (port from --listen)");
  flags.Add("address-file", &address_file,
            "write host:port for other hosts to dial here once serving (shared storage)");
  flags.Add("tls-cert", &tls.cert, "PEM server certificate: serve TLS");
  flags.Add("tls-key", &tls.key, "PEM private key of --tls-cert");
  flags.Add("tls-client-ca", &tls.client_ca, "PEM CA: require client certificates signed by it");
  flags.AddBool("insecure", &insecure, "allow plaintext on a non-loopback listener");
  flags.Add("tokens-file", &tokens_file,
            "bearer tokens, lines 'ROLE TOKEN' (client|worker|admin); also env "
            "GAITFORGE_{CLIENT,WORKER,ADMIN}_TOKEN; none: no authentication");
  flags.Add("metrics-listen", &metrics_listen,
            "serve Prometheus metrics at http://HOST:PORT/metrics (empty: off)");
  flags.Add("dashboard-listen", &dashboard_listen,
            "serve the read-only web dashboard at http://HOST:PORT/ (port 0: any free one; "
            "empty: off; docs/dashboard.md)");
  flags.Add("log-format", &log_format, "text or json (one JSON object per line)");
  flags.Add("max-message-mb", &max_message_mb, "largest gRPC message accepted or sent, MiB (1..1024)");
  flags.Add("max-recording-mb", &max_recording_mb, "largest recording accepted, MiB (1..1024)");
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
  if (max_message_mb < 1 || max_message_mb > 1024)
    return Fail("--max-message-mb: out of range [1, 1024]");
  const int kMaxMessageBytes = max_message_mb << 20;
  if (log_format != "text" && log_format != "json")
    return Fail("--log-format: expected text or json, got '" + log_format + "'");
  if (auto s = core::SetupLogging("coordinator", log_level, log_format == "json"); !s.ok())
    return Fail(std::string(s.message()));
  auto address = coordinator::ResolveListen(listen, listen_interface);
  if (!address.ok()) return Fail(std::string(address.status().message()));
  auto creds = coordinator::MakeServerCredentials(tls, *address, insecure);
  if (!creds.ok()) return Fail(std::string(creds.status().message()));
  auto auth = coordinator::Auth::Load(tokens_file);
  if (!auth.ok()) return Fail(std::string(auth.status().message()));
  if (auth->enabled() && tls.cert.empty() && !coordinator::IsLoopback(*address))
    spdlog::warn("tokens travel in plaintext on {} (--insecure)", *address);

  // Signals go to one thread that waits for them.
  sigset_t sigs;
  sigemptyset(&sigs);
  sigaddset(&sigs, SIGINT);
  sigaddset(&sigs, SIGTERM);
  pthread_sigmask(SIG_BLOCK, &sigs, nullptr);
  const int64_t open_files = coordinator::RaiseOpenFileLimit();
  if (open_files >= 0 && open_files < 4096)
    spdlog::warn("open-file limit {}: at most about {} workers can connect (raise ulimit -n)",
                 open_files, open_files - 64);

  std::error_code ec;
  if (auto s = core::CheckDbPath(db); !s.ok()) return Fail(std::string(s.message()));
  if (auto s = coordinator::TryBind(*address); !s.ok()) return Fail(std::string(s.message()));
  // One writing coordinator per database: a second would resume the same studies.
  int lock_fd = -1;
  if (!read_only) {
    const std::string lock_path = db + ".lock";
    const int fd = lock_fd = open(lock_path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
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
  coordinator::Metrics metrics;
  std::unique_ptr<prometheus::Exposer> exposer;
  if (!metrics_listen.empty()) {
    try {
      exposer = std::make_unique<prometheus::Exposer>(metrics_listen);
    } catch (const std::exception& e) {
      return Fail("--metrics-listen " + metrics_listen + ": " + e.what());
    }
    exposer->RegisterCollectable(metrics.registry());
    // The port really bound (port 0 in --metrics-listen picks one).
    const auto ports = exposer->GetListeningPorts();
    spdlog::info("metrics at http://{}/metrics",
                 coordinator::WithPort(metrics_listen, ports.empty() ? 0 : ports[0]));
  }
  options.metrics = &metrics;
  if (max_recording_mb < 1 || max_recording_mb > 1024)
    return Fail("--max-recording-mb: out of range [1, 1024]");
  options.max_recording_bytes = static_cast<size_t>(max_recording_mb) << 20;
  (*store)->SetCommitObserver([&metrics](double s) { metrics.Commit(s); });
  coordinator::Coordinator coord(std::move(*store), options, core::RealClock());
  if (auto s = coord.RecoverStudies(); !s.ok()) return Fail(std::string(s.message()));
  // Stored diagnoses work beside the database, in DB.diagnoses/ID.
  coordinator::Diagnoses diagnoses(coord, options.db_path + ".diagnoses", read_only);
  if (auto s = diagnoses.Recover(); !s.ok()) return Fail(std::string(s.message()));

  // The web dashboard: the same coordinator's reads (studies, diagnoses), the same tokens.
  dashboard::DashboardApi dashboard_api(coord, *auth, &diagnoses);
  std::unique_ptr<dashboard::HttpServer> dashboard;
  if (!dashboard_listen.empty()) {
    auto d = dashboard::HttpServer::Start(dashboard_listen, dashboard_api);
    if (!d.ok()) return Fail("--dashboard-listen: " + std::string(d.status().message()));
    dashboard = std::move(*d);
    if (auth->enabled() && !coordinator::IsLoopback(dashboard_listen))
      spdlog::warn("the dashboard's tokens travel in plaintext HTTP on {}", dashboard_listen);
    spdlog::info("dashboard at {}", dashboard->url());
  }

  coordinator::StudyServiceImpl study_service(coord, *auth);
  coordinator::WorkerServiceImpl worker_service(coord, *auth);
  coordinator::RecordingServiceImpl recording_service(coord, *auth);
  coordinator::DiagnosisServiceImpl diagnosis_service(diagnoses, *auth);
  grpc::EnableDefaultHealthCheckService(true);
  grpc::ServerBuilder builder;
  int port = 0;
  builder.AddListeningPort(*address, *creds, &port);
  builder.RegisterService(&study_service);
  builder.RegisterService(&worker_service);
  builder.RegisterService(&recording_service);
  builder.RegisterService(&diagnosis_service);
  builder.SetMaxReceiveMessageSize(kMaxMessageBytes);
  builder.SetMaxSendMessageSize(kMaxMessageBytes);
  // Keepalive on both sides (../shared/guides/distributed-notes.md): accept client pings
  // every 10 s even without calls, and ping idle clients every 30 s.
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIME_MS, 30000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_TIMEOUT_MS, 10000);
  builder.AddChannelArgument(GRPC_ARG_KEEPALIVE_PERMIT_WITHOUT_CALLS, 1);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MIN_RECV_PING_INTERVAL_WITHOUT_DATA_MS, 5000);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_MAX_PING_STRIKES, 0);
  // At most this many concurrent streams per connection (watchers, long polls).
  builder.AddChannelArgument(GRPC_ARG_MAX_CONCURRENT_STREAMS, 256);
  // A port another process listens on is refused, not shared (SO_REUSEPORT is gRPC's
  // default on Linux: a second coordinator would bind beside the first).
  builder.AddChannelArgument(GRPC_ARG_ALLOW_REUSEPORT, 0);
  builder.AddChannelArgument(GRPC_ARG_HTTP2_BDP_PROBE, 0);
  std::unique_ptr<grpc::Server> server = builder.BuildAndStart();
  if (!server || port == 0) {
    auto why = coordinator::TryBind(*address);
    return Fail(why.ok() ? "cannot listen on " + *address : std::string(why.message()));
  }
  if (lock_fd >= 0) {
    // The lock file says who holds the database and where: the CLI's embedded commands
    // (cancel, resume, watch, ...) talk to this coordinator instead of failing on the lock.
    // A third line names the dashboard's URL when it serves one.
    const std::string holder = std::to_string(getpid()) + "\n" +
                               coordinator::DialAddress(*address, port) + "\n" +
                               (dashboard ? "dashboard " + dashboard->url() + "\n" : "");
    (void)!ftruncate(lock_fd, 0);
    (void)!pwrite(lock_fd, holder.data(), holder.size(), 0);
  }
  spdlog::info("serving on {} port {} ({}, {}) with database {}", *address, port,
               tls.cert.empty() ? "plaintext" : "TLS",
               auth->enabled() ? "tokens required" : "no authentication", options.db_path);
  if (!address_file.empty()) {
    const std::string tmp = address_file + ".tmp";
    std::ofstream(tmp) << coordinator::DialAddress(*address, port) << "\n";
    std::filesystem::rename(tmp, address_file, ec);
    if (ec) return Fail("cannot write --address-file " + address_file + ": " + ec.message());
  }
  if (!port_file.empty()) {
    const std::string tmp = port_file + ".tmp";
    std::ofstream out(tmp);
    out << port << "\n";
    // Second line: the metrics port (useful with --metrics-listen HOST:0).
    if (exposer && !exposer->GetListeningPorts().empty()) out << exposer->GetListeningPorts()[0] << "\n";
    // Then the dashboard's URL, as "dashboard URL" (the CLI prints it).
    if (dashboard) out << "dashboard " << dashboard->url() << "\n";
    out.close();
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
  if (!address_file.empty()) std::filesystem::remove(address_file, ec);
  spdlog::info("signal {}: shutting down", sig);
  diagnoses.Shutdown();  // they stay running in the database; the next start resumes them
  dashboard.reset();  // no request in flight after this
  coord.Shutdown();  // wakes long polls and watchers
  server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(3));
  stop = true;
  ticker.join();
  coord.Shutdown();
  spdlog::info("stopped");
  return 0;
}
