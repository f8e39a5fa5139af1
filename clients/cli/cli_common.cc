#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <thread>

#include "absl/strings/str_format.h"
#include "clients/cli/cli.h"
#include "services/core/json_text.h"
#include "clients/cli/processes.h"
#include "services/core/db_path.h"
#include "services/rpc/channel.h"
#include "services/rpc/proto_json.h"

namespace gaitforge::cli {

namespace {
std::string& CallToken() {
  static std::string token;
  return token;
}
}  // namespace

void SetCallToken(const std::string& token) { CallToken() = token; }

std::string LogsDir(const GlobalOptions& g) {
  return (std::filesystem::path(g.db).parent_path() / "logs").string();
}

std::shared_ptr<grpc::Channel> MakeChannel(const std::string& target) {
  return *rpc::MakeChannel(rpc::ChannelOptions{target, "", "", "", ""});
}

void SetDeadline(grpc::ClientContext& ctx, double seconds) {
  rpc::PrepareCall(ctx, seconds, CallToken());
}

namespace {

// Whether a coordinator at this loopback address accepts a connection within a second.
bool Answers(const std::string& address) {
  auto channel = rpc::MakeChannel({address, "", "", "", ""});
  return channel.ok() && (*channel)->WaitForConnected(std::chrono::system_clock::now() +
                                                      std::chrono::seconds(1));
}

}  // namespace

std::unique_ptr<Connection> Connection::Open(const GlobalOptions& g, bool writable,
                                             std::string* error, bool live) {
  std::unique_ptr<Connection> c(new Connection());
  if (!g.coordinator.empty()) {
    c->target_ = g.coordinator;
  } else {
    // Check before anything is created next to it: `--db DIR` would put logs/ beside DIR.
    auto path = core::CheckDbPath(g.db);
    const auto folder = std::filesystem::path(g.db).parent_path();
    if (!path.ok() && writable && g.db == GlobalOptions().db &&
        !std::filesystem::exists(folder)) {
      std::error_code ec;  // the default database's folder is made on first use
      std::filesystem::create_directories(folder, ec);
      path = core::CheckDbPath(g.db);
    }
    if (!path.ok()) {
      *error = std::string(path.message());
      return nullptr;
    }
    if (!writable && !std::filesystem::exists(g.db)) {
      *error = "no database at '" + g.db +
               "': run 'gaitforge local SPEC' first, or name a server with --coordinator";
      return nullptr;
    }
    auto holder = writable || live ? FindDbHolder(g.db) : std::nullopt;
    // A holder that does not answer is stopping (a `local` just interrupted releases the
    // database as its coordinator exits): wait for it to let go, then start our own.
    if (holder && !Answers(holder->address)) {
      for (int i = 0; i < 200 && holder; ++i) {
        std::this_thread::sleep_for(std::chrono::milliseconds(50));
        holder = FindDbHolder(g.db);
        if (holder && Answers(holder->address)) break;
      }
    }
    if (holder && holder->address.rfind("127.0.0.1:", 0) == 0) {
      c->target_ = holder->address;
      c->shared_ = true;
      c->dashboard_url_ = holder->dashboard;
      if (!g.json)
        std::cerr << "gaitforge: using the coordinator that holds " << g.db << " (pid "
                  << holder->pid << ", " << holder->address << ")\n";
    } else {
      c->pid_ = StartCoordinator(g.db, !writable, LogsDir(g), &c->target_, error, g.dashboard,
                                 &c->dashboard_url_);
      if (c->pid_ < 0) return nullptr;
    }
  }
  // The embedded coordinator listens on loopback in plaintext; a named one as configured.
  rpc::ChannelOptions o{c->target_, "", "", "", ""};
  if (!g.coordinator.empty()) o = {c->target_, g.tls_ca, g.tls_cert, g.tls_key, g.token};
  auto channel = rpc::MakeChannel(o);
  if (!channel.ok()) {
    *error = std::string(channel.status().message());
    return nullptr;
  }
  c->channel_ = *channel;
  c->study_ = v1::StudyService::NewStub(c->channel_);
  return c;
}

Connection::~Connection() {
  study_.reset();
  channel_.reset();
  if (pid_ > 0) Stop(pid_, 5);
}

std::unique_ptr<Connection> Connect(const GlobalOptions& g, bool writable, int* code,
                                    bool live) {
  std::string error;
  auto c = Connection::Open(g, writable, &error, live);
  if (!c) {
    std::cerr << "gaitforge: " << error << "\n";
    *code = error.rfind("no database", 0) == 0 ? kNotFound
            : error.rfind("--db ", 0) == 0     ? kUsage
                                               : kUnavailable;
  }
  return c;
}

grpc::Status FetchStudy(v1::StudyService::Stub& stub, const GlobalOptions& g,
                        const std::string& id, v1::StudySummary* out) {
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetStudyRequest req;
  req.set_study_id(id);
  return stub.GetStudy(&ctx, req, out);
}

int ReportRpcError(const grpc::Status& s, const std::string& what) {
  std::cerr << "gaitforge: " << what << ": " << s.error_message() << "\n";
  switch (s.error_code()) {
    case grpc::StatusCode::INVALID_ARGUMENT:
    case grpc::StatusCode::FAILED_PRECONDITION:
    case grpc::StatusCode::OUT_OF_RANGE:
      return s.error_code() == grpc::StatusCode::OUT_OF_RANGE ? kNotFound : kUsage;
    case grpc::StatusCode::NOT_FOUND:
      return kNotFound;
    case grpc::StatusCode::UNAVAILABLE:
    case grpc::StatusCode::DEADLINE_EXCEEDED:
      return kUnavailable;
    case grpc::StatusCode::UNAUTHENTICATED:
    case grpc::StatusCode::PERMISSION_DENIED:
      return kDenied;
    default:
      return kFailed;
  }
}

std::string ToJson(const google::protobuf::Message& m) { return rpc::ToJson(m); }

std::string StateName(v1::StudyState s) {
  switch (s) {
    case v1::STUDY_STATE_RUNNING: return "running";
    case v1::STUDY_STATE_PAUSED: return "paused";
    case v1::STUDY_STATE_CANCELLED: return "cancelled";
    case v1::STUDY_STATE_COMPLETED: return "completed";
    case v1::STUDY_STATE_FAILED: return "failed";
    case v1::STUDY_STATE_INTERRUPTED: return "interrupted";
    default: return "unknown";
  }
}

bool Unheld(const GlobalOptions& g) { return g.coordinator.empty() && !FindDbHolder(g.db); }

std::string ShownState(v1::StudyState s, bool unheld) {
  return unheld && s == v1::STUDY_STATE_RUNNING ? "interrupted" : StateName(s);
}

std::string ContinueHint(const GlobalOptions& g, const std::string& id) {
  if (!g.coordinator.empty())
    return "it goes on when the coordinator is back (it resumes running studies on start): "
           "'gaitforge watch " + id + "'";
  const std::string db = g.db == GlobalOptions().db ? "" : " --db " + g.db;
  return "continue it with 'gaitforge resume " + id + db + "'";
}

std::string FormatDuration(double s) {
  if (!std::isfinite(s) || s < 0) return "--";
  const int t = static_cast<int>(s + 0.5);
  if (t >= 3600) return absl::StrFormat("%dh%02dm", t / 3600, (t / 60) % 60);
  if (t >= 60) return absl::StrFormat("%dm%02ds", t / 60, t % 60);
  return absl::StrFormat("%ds", t);
}

std::string InvalidText(int invalid, const std::string& reason, bool short_reason) {
  std::string why = reason.empty() ? "no reason given" : reason;
  if (short_reason && why.size() > 40) why = why.substr(0, 37) + "...";
  return absl::StrFormat("invalid %d (%s)", invalid, why);
}

void DrawProgressBar(double frac, const std::string& line) {
  const int width = 30;
  const int fill = static_cast<int>(std::clamp(frac, 0.0, 1.0) * width);
  std::cerr << "\r[" << std::string(fill, '#') << std::string(width - fill, '.') << "] " << line
            << "   " << std::flush;
}

int WatchUntilDone(v1::StudyService::Stub& stub, const std::string& id, const GlobalOptions& g,
                   double watch_timeout_s) {
  grpc::ClientContext ctx;
  SetDeadline(ctx, watch_timeout_s);
  v1::WatchStudyRequest req;
  req.set_study_id(id);
  auto reader = stub.WatchStudy(&ctx, req);
  const bool tty = isatty(STDERR_FILENO) && !g.json;
  v1::Progress p;
  v1::Progress last;
  bool any = false;
  int printed_gen = -1;
  bool printed_any = false;
  auto started = std::chrono::steady_clock::now();
  while (reader->Read(&p)) {
    any = true;
    last = p;
    const int total = std::max(1, p.generations_total());
    const double frac = static_cast<double>(p.generations_done()) / total;
    std::string line = absl::StrFormat(
        "gen %d/%d  best %.6g  mean %.6g  %.0f ev/s  ETA %s", p.generations_done(), total,
        p.best(), p.mean(), p.evals_per_second(), FormatDuration(p.eta_seconds()));
    if (p.invalid() > 0) line += "  " + InvalidText(p.invalid(), p.invalid_reason(), tty);
    if (tty) {
      DrawProgressBar(frac, line);
    } else if (!g.json) {
      // One line per ~10% of the study, and the last one.
      const int step = std::max(1, total / 10);
      if (!printed_any || p.generations_done() / step != printed_gen / step ||
          p.state() != v1::STUDY_STATE_RUNNING) {
        std::cerr << line << "\n";
        printed_gen = p.generations_done();
        printed_any = true;
      }
    }
  }
  if (tty) std::cerr << "\n";
  grpc::Status s = reader->Finish();
  const bool lost = s.ok() ? any && last.state() == v1::STUDY_STATE_RUNNING
                           : s.error_code() == grpc::StatusCode::UNAVAILABLE ||
                                 s.error_code() == grpc::StatusCode::CANCELLED;
  if (lost) {
    // The coordinator stopped or died under the watch; the study's committed generations
    // are safe in the database.
    std::cerr << "gaitforge: lost the coordinator while watching study " << id
              << (s.ok() ? "" : " (" + s.error_message() + ")")
              << "; its committed generations are stored: " << ContinueHint(g, id) << "\n";
    return kUnavailable;
  }
  if (!s.ok()) return ReportRpcError(s, "watch " + id);
  if (!any) return kFailed;
  const double wall =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  if (g.json) {
    std::cout << ToJson(last) << "\n";
  } else {
    std::cerr << "study " << id << " " << StateName(last.state()) << " after "
              << last.generations_done() << " generations (" << FormatDuration(wall)
              << " watched), best fitness " << last.best() << ", " << last.evaluations()
              << " evaluations\n";
    if (!last.error().empty()) std::cerr << "error: " << last.error() << "\n";
    if (!last.stop_reason().empty()) std::cerr << "stopped: " << last.stop_reason() << "\n";
  }
  return last.state() == v1::STUDY_STATE_COMPLETED ? kOk : kStudyNotCompleted;
}

std::string JsonQuote(const std::string& s) { return core::JsonQuote(s); }

}  // namespace gaitforge::cli
