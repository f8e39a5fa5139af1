// Stored diagnoses (docs/diagnosis.md, "Stored diagnoses"): `gaitforge diagnoses` lists
// them, `gaitforge diagnosis ID` waits for one (progress on stderr), copies its report and
// figures into --out/NAME-diagnosis and prints it in words (or the report with --json).
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <thread>

#include "absl/strings/str_format.h"
#include "clients/cli/cli.h"
#include "gaitforge/v1/diagnosis.grpc.pb.h"
#include "services/diagnosis/words.h"

namespace gaitforge::cli {
namespace {

const char* StateName(v1::DiagnosisState s) {
  switch (s) {
    case v1::DIAGNOSIS_STATE_RUNNING: return "running";
    case v1::DIAGNOSIS_STATE_COMPLETED: return "completed";
    case v1::DIAGNOSIS_STATE_FAILED: return "failed";
    case v1::DIAGNOSIS_STATE_CANCELLED: return "cancelled";
    default: return "unknown";
  }
}

grpc::Status Get(v1::DiagnosisService::Stub& stub, const std::string& id, bool files,
                 const GlobalOptions& g, v1::GetDiagnosisResponse* out) {
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetDiagnosisRequest req;
  req.set_diagnosis_id(id);
  req.set_with_files(files);
  return stub.GetDiagnosis(&ctx, req, out);
}

// Progress while it runs: a bar on a terminal, a line per stage and finished fit otherwise.
void ShowProgress(const v1::DiagnosisSummary& d, bool tty, std::string* shown) {
  if (d.progress().empty() || d.progress() == *shown) return;
  if (tty) {
    DrawProgressBar(d.fraction(), d.progress());
  } else if (d.progress().substr(0, d.progress().find(" fits done")) !=
             shown->substr(0, shown->find(" fits done"))) {
    std::cerr << d.progress() << "\n";
  }
  *shown = d.progress();
}

}  // namespace

int AwaitDiagnosis(v1::DiagnosisService::Stub& stub, const std::string& id,
                   const std::string& out_root, const GlobalOptions& g, bool runner) {
  const bool tty = isatty(STDERR_FILENO) && !g.json;
  std::string shown;
  v1::GetDiagnosisResponse r;
  for (;;) {
    if (auto s = Get(stub, id, false, g, &r); !s.ok()) return ReportRpcError(s, "diagnosis " + id);
    if (r.diagnosis().state() != v1::DIAGNOSIS_STATE_RUNNING) break;
    if (!runner) {
      std::cerr << "gaitforge: diagnosis " << id << " is interrupted: no coordinator runs it. "
                << "Run `gaitforge diagnose SPEC` with its spec again: it takes the diagnosis "
                   "up where it stopped, reusing every finished fit\n";
      return kStudyNotCompleted;
    }
    if (!g.json) ShowProgress(r.diagnosis(), tty, &shown);
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  if (tty && !shown.empty()) std::cerr << "\n";
  if (r.diagnosis().state() != v1::DIAGNOSIS_STATE_COMPLETED) {
    std::cerr << "gaitforge: diagnosis " << id << " " << StateName(r.diagnosis().state())
              << (r.diagnosis().error().empty() ? "" : ": " + r.diagnosis().error()) << "\n";
    return kStudyNotCompleted;
  }
  if (auto s = Get(stub, id, true, g, &r); !s.ok()) return ReportRpcError(s, "diagnosis " + id);
  const std::string dir = out_root + "/" + r.diagnosis().spec().name() + "-diagnosis";
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  for (const auto& f : r.files())
    std::ofstream(dir + "/" + f.name(), std::ios::binary) << f.content();
  if (g.json) {
    std::cout << r.report_json();
    return kOk;
  }
  auto words = diagnosis::ReportWords(r.report_json(), dir);
  if (!words.ok()) {
    std::cerr << "gaitforge: diagnosis " << id << ": " << words.status().message() << "\n";
    return kFailed;
  }
  std::cout << *words;
  return kOk;
}

int CmdDiagnosis(const GlobalOptions& g, const std::vector<std::string>& args,
                 const std::string& out_root) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge diagnosis ID [--out DIR] [--json]\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, false, &code, /*live=*/true);
  if (!conn) return code;
  auto stub = v1::DiagnosisService::NewStub(conn->channel());
  // A private read-only coordinator runs nothing: a running diagnosis there is interrupted.
  return AwaitDiagnosis(*stub, args[0], out_root, g, !g.coordinator.empty() || conn->shared());
}

int CancelDiagnosis(Connection& conn, const std::string& id, const GlobalOptions& g) {
  auto stub = v1::DiagnosisService::NewStub(conn.channel());
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::CancelDiagnosisRequest req;
  req.set_diagnosis_id(id);
  v1::DiagnosisSummary resp;
  if (auto s = stub->CancelDiagnosis(&ctx, req, &resp); !s.ok()) {
    if (s.error_code() == grpc::StatusCode::NOT_FOUND)
      s = grpc::Status(s.error_code(), "no study or diagnosis with id '" + id + "'");
    return ReportRpcError(s, "cancel " + id);
  }
  if (g.json) std::cout << ToJson(resp) << "\n";
  else std::cout << id << " cancelling (a diagnosis stops at its next check)\n";
  return kOk;
}

int CmdDiagnoses(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (!args.empty()) {
    std::cerr << "gaitforge: usage: gaitforge diagnoses [--json]\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, false, &code, /*live=*/true);
  if (!conn) return code;
  auto stub = v1::DiagnosisService::NewStub(conn->channel());
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::ListDiagnosesResponse resp;
  if (auto s = stub->ListDiagnoses(&ctx, v1::ListDiagnosesRequest(), &resp); !s.ok())
    return ReportRpcError(s, "diagnoses");
  if (g.json) {
    std::cout << ToJson(resp) << "\n";
    return kOk;
  }
  std::cout << absl::StrFormat("%-28s %-10s %-10s %s\n", "ID", "STATE", "VERDICT", "PROGRESS");
  for (const auto& d : resp.diagnoses())
    std::cout << absl::StrFormat("%-28s %-10s %-10s %s\n", d.diagnosis_id(), StateName(d.state()),
                                 d.verdict().empty() ? "-" : d.verdict(),
                                 !d.error().empty() ? d.error() : d.progress());
  return kOk;
}

}  // namespace gaitforge::cli
