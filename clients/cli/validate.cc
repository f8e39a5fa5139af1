// `gaitforge validate ID`: a robust study's gaits evaluated again over a fresh ensemble, one
// its selection never saw (services/spec/validation_spec.h; docs/objectives.md,
// "Validation"), as a study of its own: one sweep level per gait, run by local workers or
// by --coordinator's, stored beside the study.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>

#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "services/core/file_text.h"
#include "services/spec/validation_spec.h"

namespace gaitforge::cli {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

v1::Evaluation NotEvaluated() {
  v1::Evaluation e;
  e.set_reason("not in the validation study's results");
  return e;
}

struct Row {
  int rank = -1;               // hall-of-fame rank; -1 for a gait not in it
  std::vector<double> genes;
  double fitness = kNaN;       // the study's (hall-of-fame gaits only)
  double predicted = kNaN;     // the study's ensemble mean (hall-of-fame gaits only)
  v1::Evaluation validated = NotEvaluated();
  int fresh_rank = -1;         // rank by the validated fitness among the valid; -1: invalid
};

double Metric(const v1::Evaluation& e, const std::string& name) {
  return e.metrics().count(name) ? e.metrics().at(name) : kNaN;
}

// The request: study `id`, the flags, and with --gaits the file's gaits.
int Request(const std::string& id, const v1::StudySpec& study, const ValidateOptions& v,
            v1::StudySpec* spec) {
  v1::Validation* r = spec->mutable_validate();
  r->set_study_id(id);
  r->set_members(v.members);
  r->set_seed(v.seed);
  r->set_top(v.top);
  r->set_from_calibration(v.from_calibration);
  if (v.gaits.empty()) return kOk;
  auto text = core::ReadWholeFile(v.gaits);
  if (!text.ok()) {
    std::cerr << "gaitforge: validate: --gaits: " << text.status().message() << "\n";
    return kUsage;
  }
  auto gaits = spec::ParseGaits(*text, v.gaits, study.bounds_size());
  if (!gaits.ok()) {
    std::cerr << "gaitforge: validate: " << gaits.status().message() << "\n";
    return kUsage;
  }
  for (const auto& g : *gaits) r->add_gaits()->mutable_genes()->Add(g.begin(), g.end());
  return kOk;
}

// One row per gait the validation study resolved to, in its order; a gait of the study's
// hall of fame (as it was when the validation started) gets its rank, fitness and
// prediction there.
std::vector<Row> Rows(const v1::Validation& resolved, const v1::GetHallOfFameResponse& hof) {
  std::vector<Row> rows;
  for (int i = 0; i < resolved.gaits_size(); ++i) {
    Row& row = rows.emplace_back();
    row.genes.assign(resolved.gaits(i).genes().begin(), resolved.gaits(i).genes().end());
    for (const auto& e : hof.entries()) {
      const auto& ind = e.individual();
      if (!std::equal(ind.genes().begin(), ind.genes().end(), row.genes.begin(), row.genes.end()))
        continue;
      row.rank = e.rank();
      row.fitness = ind.evaluation().fitness();
      row.predicted = Metric(ind.evaluation(), "robust.mean");
      break;
    }
  }
  return rows;
}

// Creates the validation study and runs it to its end; its id in *vid.
int RunValidation(const GlobalOptions& g, Connection& conn, int workers, int threads,
                  const v1::StudySpec& spec, std::string* vid) {
  GlobalOptions quiet = g;
  quiet.json = false;  // progress on stderr; stdout keeps this command's own output
  int start_code = kOk;
  const auto create = CreateStudyStart(g, spec, "create the validation study", &start_code);
  auto start = [&](v1::StudyService::Stub& stub) { return *vid = create(stub); };
  if (g.coordinator.empty())
    return RunWithLocalWorkers(quiet, conn, workers, threads, "", start, &start_code);
  if (start(conn.study()).empty()) return start_code;
  return WatchUntilDone(conn.study(), *vid, quiet, 30 * 24 * 3600.0);
}

// Each row's evaluation in the validation study (member i is level i, gait i).
int ReadValidation(Connection& conn, const GlobalOptions& g, const std::string& vid,
                   std::vector<Row>* rows) {
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::ListIndividualsRequest req;
  req.set_study_id(vid);
  req.set_generation(0);
  v1::ListIndividualsResponse resp;
  if (grpc::Status s = conn.study().ListIndividuals(&ctx, req, &resp); !s.ok())
    return ReportRpcError(s, "individuals of " + vid);
  for (const auto& ind : resp.individuals()) {
    if (ind.member() < 0 || ind.member() >= static_cast<int>(rows->size())) continue;
    Row& row = (*rows)[ind.member()];
    bool same = ind.genes_size() == static_cast<int>(row.genes.size());
    for (int j = 0; same && j < ind.genes_size(); ++j)
      same = std::abs(ind.genes(j) - row.genes[j]) <= 1e-9 * (1 + std::abs(row.genes[j]));
    if (!same) {
      std::cerr << "gaitforge: validate: " << vid << "'s member " << ind.member() << " is not gait "
                << ind.member() + 1 << "\n";
      return kFailed;
    }
    row.validated = ind.evaluation();
  }
  return kOk;
}

// Each valid row's rank (0 = best) by its validated fitness, ties in the rows' order.
void RankByValidation(std::vector<Row>* rows) {
  std::vector<Row*> valid;
  for (Row& r : *rows)
    if (r.validated.valid()) valid.push_back(&r);
  std::stable_sort(valid.begin(), valid.end(), [](const Row* a, const Row* b) {
    return a->validated.fitness() > b->validated.fitness();
  });
  for (size_t i = 0; i < valid.size(); ++i) valid[i]->fresh_rank = static_cast<int>(i);
}

std::string Rank(int rank) { return rank < 0 ? "null" : std::to_string(rank); }

std::string Num(double x) { return std::isfinite(x) ? absl::StrFormat("%.17g", x) : "null"; }

void PrintJson(const std::string& id, const std::string& vid, const v1::StudySpec& spec,
               const std::vector<Row>& rows) {
  std::cout << "{\"study_id\": " << JsonQuote(id) << ", \"validation_study_id\": " << JsonQuote(vid)
            << ", \"from_calibration\": "
            << (spec.validate().from_calibration().empty()
                    ? "null" : JsonQuote(spec.validate().from_calibration()))
            << ", \"members\": " << spec.objective().robust().members()
            << ", \"seed\": " << spec.objective().robust().seed() << ", \"gaits\": [";
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const v1::Evaluation& e = r.validated;
    std::vector<std::string> genes;
    for (double x : r.genes) genes.push_back(Num(x));
    std::cout << (i ? ", " : "") << "{\"rank\": " << Rank(r.rank)
              << ", \"validated_rank\": " << Rank(r.fresh_rank) << ", \"genes\": ["
              << absl::StrJoin(genes, ", ") << "], \"fitness\": " << Num(r.fitness)
              << ", \"predicted\": " << Num(r.predicted) << ", \"valid\": "
              << (e.valid() ? "true" : "false") << ", \"reason\": " << JsonQuote(e.reason())
              << ", \"validated\": {\"fitness\": " << Num(e.valid() ? e.fitness() : kNaN);
    for (const char* m : {"mean", "sd", "min", "max"})
      std::cout << ", \"" << m << "\": " << Num(Metric(e, std::string("robust.") + m));
    std::cout << "}}";
  }
  std::cout << "]}\n";
}

void PrintTable(const std::string& id, const std::string& vid, const v1::StudySpec& spec,
                const std::vector<Row>& rows) {
  const std::string& cal = spec.validate().from_calibration();
  std::cout << rows.size() << " gaits of " << id << " over a fresh ensemble of "
            << spec.objective().robust().members() << " members (seed "
            << spec.objective().robust().seed() << ")"
            << (cal.empty() ? "" : " of calibration " + cal + "'s model") << ": study " << vid
            << "\n"
            << absl::StrFormat("%4s %5s %12s %12s  %-34s %10s\n", "RANK", "NOW", "FITNESS",
                               "PREDICTED", "VALIDATED MEAN [MIN, MAX]", "SD");
  double predicted = 0, validated = 0;
  int both = 0;
  for (const Row& r : rows) {
    const v1::Evaluation& e = r.validated;
    const std::string mean =
        e.valid() ? absl::StrFormat("%.4g [%.4g, %.4g]", Metric(e, "robust.mean"),
                                    Metric(e, "robust.min"), Metric(e, "robust.max"))
                  : "invalid: " + e.reason().substr(0, 60);
    std::cout << absl::StrFormat("%4s %5s %12.6g %12.6g  %-34s %10.4g\n",
                                 r.rank < 0 ? "-" : std::to_string(r.rank),
                                 r.fresh_rank < 0 ? "-" : std::to_string(r.fresh_rank), r.fitness,
                                 r.predicted, mean, Metric(e, "robust.sd"));
    if (e.valid() && std::isfinite(r.predicted)) {
      predicted += r.predicted;
      validated += Metric(e, "robust.mean");
      ++both;
    }
  }
  if (both > 0 && predicted != 0)
    std::cout << absl::StrFormat(
        "validated / predicted over %d gaits: %.3f (the study's ensemble mean of the gaits it "
        "kept, against the fresh ensemble's)\n", both, validated / predicted);
}

}  // namespace

int CmdValidate(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
                int threads, const ValidateOptions& v) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge validate STUDY_ID [--members M] [--ensemble-seed S] "
                 "[--top N | --gaits FILE] [--from-calibration CAL]\n";
    return kUsage;
  }
  int code = kOk;
  auto conn = Connect(g, true, &code);
  if (!conn) return code;
  v1::StudySummary study;
  if (grpc::Status s = FetchStudy(conn->study(), g, args[0], &study); !s.ok())
    return ReportRpcError(s, "validate " + args[0]);
  if (v.top > 0 && !v.gaits.empty()) {
    std::cerr << "gaitforge: validate: --top picks hall-of-fame gaits; not with --gaits\n";
    return kUsage;
  }
  v1::StudySpec request;
  if (int c = Request(args[0], study.spec(), v, &request); c) return c;
  auto hof = Hof(conn->study(), args[0], -1, g);  // before: a running study's moves on
  if (!hof.ok()) return HofError(hof.status(), "validate " + args[0]);
  std::string vid;
  if (int c = RunValidation(g, *conn, workers, threads, request, &vid); c) return c;
  v1::StudySummary validation;
  if (grpc::Status s = FetchStudy(conn->study(), g, vid, &validation); !s.ok())
    return ReportRpcError(s, "validate " + args[0]);
  std::vector<Row> rows = Rows(validation.spec().validate(), *hof);
  if (int c = ReadValidation(*conn, g, vid, &rows); c) return c;
  RankByValidation(&rows);
  const v1::StudySpec& spec = validation.spec();
  if (g.json)
    PrintJson(args[0], vid, spec, rows);
  else
    PrintTable(args[0], vid, spec, rows);
  return kOk;
}

}  // namespace gaitforge::cli
