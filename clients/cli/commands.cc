// Query and control commands: submit, watch, list, show, hof, history, individuals,
// cancel, health.
#include <cmath>
#include <iostream>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "grpc/health/v1/health.grpc.pb.h"
#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::cli {
namespace {

int NeedArgs(const std::vector<std::string>& args, size_t n, const char* usage) {
  if (args.size() != n) {
    std::cerr << "gaitforge: usage: " << usage << "\n";
    return kUsage;
  }
  return kOk;
}


std::string Genes(const google::protobuf::RepeatedField<double>& genes) {
  std::vector<std::string> parts;
  for (double x : genes) parts.push_back(absl::StrFormat("%.4f", x));
  return absl::StrJoin(parts, " ");
}

// Full precision, for files scripts read back.
std::string GenesExact(const google::protobuf::RepeatedField<double>& genes) {
  std::vector<std::string> parts;
  for (double x : genes) parts.push_back(absl::StrFormat("%.17g", x));
  return absl::StrJoin(parts, " ");
}

// An invalid member's fitness is no number (it is stored as 0, the best value a
// fitness of minus a loss can have): "invalid" in tables, an empty CSV field.
std::string TableFitness(const v1::Evaluation& e) {
  return e.valid() ? absl::StrFormat("%.6g", e.fitness()) : "invalid";
}
std::string CsvFitness(const v1::Evaluation& e) {
  return e.valid() ? absl::StrFormat("%.17g", e.fitness()) : "";
}

std::string CsvQuote(const std::string& s) {
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

void PrintSummary(const v1::StudySummary& s, bool unheld) {
  std::cout << "study        " << s.study_id() << "\n"
            << "name         " << s.spec().name() << "\n"
            << "state        " << ShownState(s.state(), unheld) << "\n"
            << "engine       " << s.spec().engine() << "\n"
            << "objective    " << s.spec().objective().name() << "\n"
            << "seed         " << s.spec().seed() << "\n"
            << "generations  " << s.generations_done() << " / " << s.spec().generations()
            << "\n"
            << "population   " << s.spec().population() << "\n"
            << "evaluations  " << s.evaluations() << "\n"
            << "best         " << s.best_fitness() << "\n"
            << "mean         " << s.mean_fitness() << "\n";
  if (!s.error().empty()) std::cout << "error        " << s.error() << "\n";
  if (!s.stop_reason().empty()) std::cout << "stopped      " << s.stop_reason() << "\n";
  if (!s.db_path().empty()) std::cout << "database     " << s.db_path() << "\n";
}

}  // namespace

// Loads, completes and validates a spec file; errors name file, line and field.
int LoadSpec(const std::string& path, v1::StudySpec* out) {
  auto loaded = spec::LoadSpecFile(path);
  if (!loaded.ok()) {
    std::cerr << "gaitforge: " << loaded.status().message() << "\n";
    return loaded.status().code() == absl::StatusCode::kNotFound ? kNotFound : kUsage;
  }
  spec::ApplyDefaults(&loaded->spec);
  if (auto s = spec::ValidationStatus(spec::Validate(loaded->spec), &*loaded); !s.ok()) {
    std::cerr << "gaitforge: invalid spec:\n" << s.message() << "\n";
    return kUsage;
  }
  *out = loaded->spec;
  return kOk;
}

int CmdSubmit(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (int c = NeedArgs(args, 1, "gaitforge submit SPEC.yaml"); c) return c;
  v1::CreateStudyRequest req;
  if (int c = LoadSpec(args[0], req.mutable_spec()); c) return c;
  if (g.coordinator.empty()) {
    std::cerr << "gaitforge: submit needs a running coordinator (--coordinator HOST:PORT or "
                 "GAITFORGE_COORDINATOR); to run a study on this machine use 'gaitforge local'\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, true, &code);
  if (!conn) return code;
  if (int c = UploadSpecRecordings(*conn, args[0], req.mutable_spec(), g); c) return c;
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::CreateStudyResponse resp;
  grpc::Status s = conn->study().CreateStudy(&ctx, req, &resp);
  if (!s.ok()) return ReportRpcError(s, "submit " + args[0]);
  if (g.json) std::cout << ToJson(resp.study()) << "\n";
  else std::cout << resp.study().study_id() << "\n";
  return kOk;
}

int CmdWatch(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (int c = NeedArgs(args, 1, "gaitforge watch STUDY_ID"); c) return c;
  int code = kOk;
  auto conn = Connect(g, false, &code, /*live=*/true);
  if (!conn) return code;
  if (Unheld(g)) {
    // Nothing runs the study: the file would say "running" forever.
    v1::StudySummary study;
    grpc::Status s = FetchStudy(conn->study(), g, args[0], &study);
    if (!s.ok()) return ReportRpcError(s, "watch " + args[0]);
    if (study.state() == v1::STUDY_STATE_RUNNING || study.state() == v1::STUDY_STATE_INTERRUPTED) {
      std::cerr << "gaitforge: study " << args[0] << " is interrupted: no coordinator runs it "
                << "(the one that did stopped or was killed); " << ContinueHint(g, args[0])
                << "\n";
      return kStudyNotCompleted;
    }
  }
  return WatchUntilDone(conn->study(), args[0], g, 7 * 24 * 3600.0);
}

int CmdList(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (int c = NeedArgs(args, 0, "gaitforge list"); c) return c;
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::ListStudiesResponse resp;
  grpc::Status s = conn->study().ListStudies(&ctx, v1::ListStudiesRequest(), &resp);
  if (!s.ok()) return ReportRpcError(s, "list");
  if (g.json) {
    std::cout << ToJson(resp) << "\n";
    return kOk;
  }
  const bool unheld = Unheld(g);
  std::cout << absl::StrFormat("%-32s %-11s %-12s %9s %12s %10s\n", "STUDY", "STATE",
                               "OBJECTIVE", "GEN", "BEST", "EVALS");
  for (const auto& st : resp.studies()) {
    std::cout << absl::StrFormat("%-32s %-11s %-12s %4d/%-4d %12.6g %10d\n", st.study_id(),
                                 ShownState(st.state(), unheld), st.spec().objective().name(),
                                 st.generations_done(), st.spec().generations(),
                                 st.best_fitness(), st.evaluations());
  }
  return kOk;
}

int CmdShow(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (int c = NeedArgs(args, 1, "gaitforge show STUDY_ID"); c) return c;
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  v1::StudySummary resp;
  grpc::Status s = FetchStudy(conn->study(), g, args[0], &resp);
  if (!s.ok()) return ReportRpcError(s, "show " + args[0]);
  if (g.json) {
    std::cout << ToJson(resp) << "\n";
    return kOk;
  }
  PrintSummary(resp, Unheld(g));
  // The latest generation's invalid members, from its history row.
  grpc::ClientContext hctx;
  SetDeadline(hctx, g.timeout_s);
  v1::GetHistoryRequest hreq;
  hreq.set_study_id(args[0]);
  v1::GetHistoryResponse history;
  if (conn->study().GetHistory(&hctx, hreq, &history).ok() && history.generations_size() > 0) {
    const auto& last = *history.generations().rbegin();
    std::cout << "invalid      " << last.invalid() << " in generation " << last.generation();
    if (last.invalid() > 0) std::cout << "; commonest reason: " << last.invalid_reason();
    std::cout << "\n";
  }
  return kOk;
}

int CmdHof(const GlobalOptions& g, const std::vector<std::string>& args, int generation,
           bool has_generation) {
  if (int c = NeedArgs(args, 1, "gaitforge hof STUDY_ID [--generation G]"); c) return c;
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetHallOfFameRequest req;
  req.set_study_id(args[0]);
  if (has_generation) req.set_generation(generation);
  v1::GetHallOfFameResponse resp;
  grpc::Status s = conn->study().GetHallOfFame(&ctx, req, &resp);
  if (!s.ok()) return ReportRpcError(s, "hof " + args[0]);
  if (g.json) {
    std::cout << ToJson(resp) << "\n";
    return kOk;
  }
  if (g.csv) {
    std::cout << "rank,origin_generation,origin_member,fitness,genes\n";
    for (const auto& e : resp.entries())
      std::cout << e.rank() << "," << e.individual().generation() << ","
                << e.individual().member() << "," << CsvFitness(e.individual().evaluation())
                << ","
                << GenesExact(e.individual().genes()) << "\n";
    return kOk;
  }
  std::cout << "hall of fame after generation " << resp.generation() << "\n";
  // A robust study's prediction: the ensemble mean, with its spread (min..max).
  const bool robust = resp.entries_size() > 0 &&
                      resp.entries(0).individual().evaluation().metrics().count("robust.mean");
  std::cout << absl::StrFormat("%4s %10s %12s  %s%s\n", "RANK", "FROM", "FITNESS",
                               robust ? "PREDICTED [MIN, MAX]            " : "", "GENES");
  for (const auto& e : resp.entries()) {
    const auto& m = e.individual().evaluation().metrics();
    std::string predicted;
    if (robust && m.count("robust.mean"))
      predicted = absl::StrFormat("%-32s", absl::StrFormat("%.4g [%.4g, %.4g]", m.at("robust.mean"),
                                                           m.at("robust.min"), m.at("robust.max")));
    else if (robust)
      predicted = std::string(32, ' ');
    std::cout << absl::StrFormat("%4d %5d/%-4d %12s  %s%s\n", e.rank(),
                                 e.individual().generation(), e.individual().member(),
                                 TableFitness(e.individual().evaluation()), predicted,
                                 Genes(e.individual().genes()));
  }
  return kOk;
}

int CmdHistory(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (int c = NeedArgs(args, 1, "gaitforge history STUDY_ID [--json|--csv]"); c) return c;
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::GetHistoryRequest req;
  req.set_study_id(args[0]);
  v1::GetHistoryResponse resp;
  grpc::Status s = conn->study().GetHistory(&ctx, req, &resp);
  if (!s.ok()) return ReportRpcError(s, "history " + args[0]);
  if (g.json) {
    std::cout << ToJson(resp) << "\n";
    return kOk;
  }
  if (g.csv) {
    std::cout << "generation,best,mean,stddev,diversity,evaluations,invalid,invalid_reason\n";
    for (const auto& h : resp.generations())
      std::cout << absl::StrFormat("%d,%.17g,%.17g,%.17g,%.17g,%d,%d,", h.generation(), h.best(),
                                   h.mean(), h.stddev(), h.diversity(), h.evaluations(),
                                   h.invalid())
                << CsvQuote(h.invalid_reason()) << "\n";
    return kOk;
  }
  std::cout << absl::StrFormat("%5s %12s %12s %10s %9s %6s %7s  %s\n", "GEN", "BEST", "MEAN",
                               "STDDEV", "DIVERSITY", "EVALS", "INVALID", "COMMONEST REASON");
  for (const auto& h : resp.generations())
    std::cout << absl::StrFormat("%5d %12.6g %12.6g %10.4g %9.4f %6d %7d  %s\n", h.generation(),
                                 h.best(), h.mean(), h.stddev(), h.diversity(), h.evaluations(),
                                 h.invalid(), h.invalid_reason());
  return kOk;
}

int CmdIndividuals(const GlobalOptions& g, const std::vector<std::string>& args, int generation) {
  if (int c = NeedArgs(args, 1, "gaitforge individuals STUDY_ID --generation G"); c) return c;
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::ListIndividualsRequest req;
  req.set_study_id(args[0]);
  req.set_generation(generation);
  v1::ListIndividualsResponse resp;
  grpc::Status s = conn->study().ListIndividuals(&ctx, req, &resp);
  if (!s.ok()) return ReportRpcError(s, "individuals " + args[0]);
  if (g.json) {
    std::cout << ToJson(resp) << "\n";
    return kOk;
  }
  std::cout << "member,valid,fitness,carried,worker,eval_seconds,reason,genes\n";
  for (const auto& i : resp.individuals())
    std::cout << i.member() << "," << i.evaluation().valid() << ","
              << CsvFitness(i.evaluation()) << "," << i.carried() << ","
              << i.worker_id() << "," << i.eval_seconds() << ","
              << CsvQuote(i.evaluation().reason()) << "," << GenesExact(i.genes()) << "\n";
  return kOk;
}

int CmdCancel(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (int c = NeedArgs(args, 1, "gaitforge cancel STUDY_ID"); c) return c;
  int code = kOk;
  auto conn = Connect(g, true, &code);
  if (!conn) return code;
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::CancelStudyRequest req;
  req.set_study_id(args[0]);
  v1::StudySummary resp;
  grpc::Status s = conn->study().CancelStudy(&ctx, req, &resp);
  // Not a study: perhaps a stored diagnosis (diagnosis.md, "Stored diagnoses").
  if (s.error_code() == grpc::StatusCode::NOT_FOUND) return CancelDiagnosis(*conn, args[0], g);
  if (!s.ok()) return ReportRpcError(s, "cancel " + args[0]);
  if (g.json) std::cout << ToJson(resp) << "\n";
  else std::cout << resp.study_id() << " " << StateName(resp.state()) << "\n";
  return kOk;
}

int CmdHealth(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (int c = NeedArgs(args, 0, "gaitforge health"); c) return c;
  if (g.coordinator.empty()) {
    std::cerr << "gaitforge: health needs --coordinator HOST:PORT (or GAITFORGE_COORDINATOR)\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, false, &code);
  if (!conn) return code;
  auto stub = grpc::health::v1::Health::NewStub(conn->channel());
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  grpc::health::v1::HealthCheckResponse resp;
  grpc::Status s = stub->Check(&ctx, grpc::health::v1::HealthCheckRequest(), &resp);
  if (!s.ok()) return ReportRpcError(s, "health of " + g.coordinator);
  std::cout << grpc::health::v1::HealthCheckResponse::ServingStatus_Name(resp.status()) << "\n";
  return resp.status() == grpc::health::v1::HealthCheckResponse::SERVING ? kOk : kUnavailable;
}

}  // namespace gaitforge::cli
