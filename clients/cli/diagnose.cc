// `gaitforge diagnose SPEC`: the gap finder (docs/diagnosis.md). A study of calibration
// studies run on the coordinator and its workers:
//   1. baseline: calibrate the base model (its uncertain parameters and the time offset;
//      marker offsets are profiled out), every fit weighting the training recordings by
//      their noise floors (weighting: floor, FloorWeights) or equally;
//   2. locate: slice the baseline's residuals (clients/python/gaitforge_locate.py);
//   3. screen every candidate effect (workers/effects) with a short fit, all at once;
//   4. refit the leading candidates fully, and pairs of them;
//   5. decide by BIC on the training error and by the held-out error over an ensemble of
//      numerically irrelevant variants (timestep, contact softness): "found" only when an
//      effect beats the baseline by the BIC margin AND cuts the ensemble-mean held-out
//      error by 15% AND wins the paired comparison across the variants (one-sided t test,
//      5%); of those that pass, the lowest held-out error is named; two effects within the
//      margin of each other, or a rival the held-out data cannot reject that fits the
//      training data better: "ambiguous", with an experiment that tells them apart; else
//      "none" (clients/cli/diagnosis_decision.h).
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "clients/cli/diagnosis_decision.h"
#include "clients/cli/processes.h"
#include "gaitforge/v1/diagnosis.pb.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "google/protobuf/util/message_differencer.h"
#include "services/recording/recording.h"
#include "services/spec/spec_loader.h"
#include "services/spec/spec_validation.h"
#include "workers/effects/effects.h"

namespace gaitforge::cli {

std::string DownloadRecording(Connection& conn, const std::string& hash, const std::string& dir,
                              const GlobalOptions& g);

namespace {


// Numerically irrelevant variants of the model: the canonical caterpillar hops, so these move
// its travel by tens of percent (../shared/robots/caterpillar.md). Every held-out error is
// the mean over them, and a discovery must win in the paired comparison across them.
const std::vector<std::string>& NumericVariants() {
  static const std::vector<std::string> v = {
      "", "simulation.timestep_s=0.0005", "simulation.timestep_s=0.00075",
      "simulation.timestep_s=0.00125", "ground.contact_cfm=3e-6", "ground.contact_cfm=3e-5"};
  return v;
}

// A fitted explanation: its FitScore (effects, ok, bic, held, held_variants) and the study.
struct Candidate : FitScore {
  std::string label;                  // effect id(s), "baseline" for none
  std::vector<v1::GeneBound> genes;   // what the study fits
  std::vector<double> mean0;
  std::string study_id;
  std::string reason;
  std::vector<double> values, spread;
  double train = NAN;
  std::vector<std::string> bound_params;  // effect parameters at the edge of their range
  int k = 0;                          // fitted parameters (nuisances included)
};

v1::GeneBound Bound(const std::string& name, double lo, double hi) {
  v1::GeneBound b;
  b.set_name(name);
  b.set_lo(lo);
  b.set_hi(hi);
  return b;
}

absl::Status Validate(const v1::DiagnosisSpec& d) {
  if (d.robot() != "caterpillar")
    return absl::InvalidArgumentError(absl::StrCat("field 'robot': '", d.robot(),
                                                   "' is not a robot gaitforge can diagnose "
                                                   "(known: caterpillar)"));
  if (d.training_size() == 0)
    return absl::InvalidArgumentError("field 'training': at least one recording is required");
  if (d.held_out_size() == 0)
    return absl::InvalidArgumentError(
        "field 'held_out': at least one recording is required (decisions rest on it)");
  for (int i = 0; i < d.candidates_size(); ++i) {
    const auto* e = effects::FindEffect(d.candidates(i));
    if (!e || e->params.empty())
      return absl::InvalidArgumentError(absl::StrCat(
          "field 'candidates[", i, "]': '", d.candidates(i),
          "' is not a fittable effect (docs/effects.md lists them)"));
  }
  for (int i = 0; i < d.base_parameters_size(); ++i) {
    const auto& b = d.base_parameters(i);
    if (b.name().empty() || !(b.lo() < b.hi()))
      return absl::InvalidArgumentError(absl::StrCat(
          "field 'base_parameters[", i, "]': needs a name and lo < hi"));
  }
  if (d.time_offset_range_s() < 0 || d.time_offset_range_s() > 1)
    return absl::InvalidArgumentError("field 'time_offset_range_s': out of range [0, 1] s");
  if (d.screening_evaluations() < 8 || d.full_evaluations() < 8)
    return absl::InvalidArgumentError(
        "fields 'screening_evaluations' and 'full_evaluations': at least 8");
  if (d.top() < 1 || d.top() > 20) return absl::InvalidArgumentError("field 'top': out of range [1, 20]");
  if (!(d.screening_tie() >= 0 && d.screening_tie() <= 0.2))
    return absl::InvalidArgumentError("field 'screening_tie': out of range [0, 0.2]");
  if (d.error() != "shape" && d.error() != "pointwise" && d.error() != "stats")
    return absl::InvalidArgumentError("field 'error': one of shape, pointwise, stats");
  if (d.weighting() != "equal" && d.weighting() != "floor")
    return absl::InvalidArgumentError(absl::StrCat("field 'weighting': '", d.weighting(),
                                                   "' is not one of equal, floor"));
  return absl::OkStatus();
}

void Defaults(v1::DiagnosisSpec* d) {
  if (d->name().empty()) d->set_name("diagnosis");
  if (d->robot().empty()) d->set_robot("caterpillar");
  if (!d->has_time_offset_range_s()) d->set_time_offset_range_s(0.05);
  if (!d->has_screening_evaluations()) d->set_screening_evaluations(120);
  if (!d->has_full_evaluations()) d->set_full_evaluations(480);
  if (!d->has_top()) d->set_top(3);
  if (!d->has_screening_tie()) d->set_screening_tie(0);
  if (!d->has_try_pairs()) d->set_try_pairs(true);
  if (d->error().empty()) d->set_error("shape");
  if (d->weighting().empty()) d->set_weighting("floor");
  if (!d->has_margin()) d->set_margin(10);
  if (d->candidates_size() == 0)
    for (const auto& e : effects::EffectCatalog())
      if (!e.params.empty()) d->add_candidates(e.id);
}

Candidate Make(const v1::DiagnosisSpec& d, const std::vector<std::string>& effect_ids) {
  Candidate c;
  c.effects = effect_ids;
  c.label = effect_ids.empty() ? "baseline" : absl::StrJoin(effect_ids, "+");
  for (const auto& b : d.base_parameters()) {
    c.genes.push_back(b);
    c.mean0.push_back(0.5 * (b.lo() + b.hi()));
  }
  for (const auto& id : effect_ids) {
    for (const auto& p : effects::FindEffect(id)->params) {
      c.genes.push_back(Bound(p.name, p.lo, p.hi));
      c.mean0.push_back(p.nominal);
    }
  }
  if (d.time_offset_range_s() > 0) {
    c.genes.push_back(Bound("nuisance.time_offset_s", -d.time_offset_range_s(),
                            d.time_offset_range_s()));
    c.mean0.push_back(0.0);
  }
  c.k = static_cast<int>(c.genes.size());
  return c;
}

v1::StudySpec StudyFor(const v1::DiagnosisSpec& d, const Candidate& c, int evaluations,
                       const std::vector<std::string>& train, const std::vector<std::string>& held,
                       const std::string& weights) {
  v1::StudySpec s;
  s.set_name(absl::StrCat(d.name(), "-", c.label));
  s.set_seed(d.seed());
  s.set_engine("cmaes");
  s.set_population(8);
  s.set_generations(100000);
  auto* o = s.mutable_objective();
  o->set_name("caterpillar.calibration");
  (*o->mutable_options())["error"] = d.error();
  if (!weights.empty()) (*o->mutable_options())["weights"] = weights;
  for (const auto& h : train) o->add_recordings(h);
  for (const auto& h : held) o->add_held_out(h);
  for (const auto& b : c.genes) *s.add_bounds() = b;
  auto* cm = s.mutable_cmaes();
  for (double m : c.mean0) cm->add_mean0(m);
  cm->set_sigma0(0.25);
  cm->set_restarts("none");
  cm->set_max_evaluations(evaluations);
  return s;
}

// Creates the studies and waits for all of them; fills study_id, values, spread, train.
int RunStudies(Connection& conn, const v1::DiagnosisSpec& d, std::vector<Candidate*> cands,
               int evaluations, const std::vector<std::string>& train,
               const std::vector<std::string>& held, const std::string& weights,
               const GlobalOptions& g, const char* stage, int* reused_total) {
  // A fit already in the database with the same spec (seed included) is reused, not run
  // again: a study's result depends only on its spec and seed, so an interrupted diagnosis
  // run again picks up its completed fits and waits for its interrupted ones (an embedded
  // coordinator resumes them on start) instead of computing them twice.
  v1::ListStudiesResponse existing;
  {
    grpc::ClientContext ctx;
    SetDeadline(ctx, g.timeout_s);
    grpc::Status s = conn.study().ListStudies(&ctx, v1::ListStudiesRequest(), &existing);
    if (!s.ok()) return ReportRpcError(s, "diagnose: list studies");
  }
  int reused = 0;
  for (auto* c : cands) {
    v1::CreateStudyRequest req;
    *req.mutable_spec() = StudyFor(d, *c, evaluations, train, held, weights);
    v1::StudySpec normalised = req.spec();
    spec::ApplyDefaults(&normalised);
    c->study_id.clear();
    for (const auto& st : existing.studies())
      if ((st.state() == v1::STUDY_STATE_COMPLETED || st.state() == v1::STUDY_STATE_RUNNING) &&
          google::protobuf::util::MessageDifferencer::Equals(st.spec(), normalised) &&
          (c->study_id.empty() || st.state() == v1::STUDY_STATE_COMPLETED))
        c->study_id = st.study_id();
    if (!c->study_id.empty()) {
      ++reused;
      continue;
    }
    grpc::ClientContext ctx;
    SetDeadline(ctx, g.timeout_s);
    v1::CreateStudyResponse resp;
    grpc::Status s = conn.study().CreateStudy(&ctx, req, &resp);
    if (!s.ok()) return ReportRpcError(s, absl::StrCat("diagnose: ", c->label));
    c->study_id = resp.study().study_id();
  }
  if (reused && !g.json)
    std::cerr << stage << ": " << reused << " of " << cands.size()
              << " fits reused from the database (same spec and seed)\n";
  *reused_total += reused;
  // Progress: a bar over the stage's evaluation budget on a terminal, a line per finished
  // fit otherwise.
  int shown = -1;
  const bool tty = isatty(STDERR_FILENO);
  const auto started = std::chrono::steady_clock::now();
  const double budget = static_cast<double>(evaluations) * cands.size();
  for (;;) {
    int done = 0;
    double spent = 0;
    for (auto* c : cands) {
      grpc::ClientContext ctx;
      SetDeadline(ctx, g.timeout_s);
      v1::GetStudyRequest req;
      req.set_study_id(c->study_id);
      v1::StudySummary sum;
      grpc::Status s = conn.study().GetStudy(&ctx, req, &sum);
      if (!s.ok()) return ReportRpcError(s, "diagnose: watch " + c->study_id);
      const bool finished = sum.state() != v1::STUDY_STATE_RUNNING;
      done += finished;
      // A fit that stopped early (CMA-ES tolerances) has used its budget.
      spent += finished ? evaluations : std::min<double>(sum.evaluations(), evaluations);
    }
    const double frac = budget > 0 ? spent / budget : 1.0;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    const std::string line = absl::StrFormat(
        "%s: %d/%d fits done, %.0f/%.0f evaluations, ETA %s", stage, done, cands.size(), spent,
        budget, frac > 0.02 ? FormatDuration(elapsed * (1 - frac) / frac) : std::string("--"));
    if (!g.json && tty) {
      const int width = 30, fill = static_cast<int>(std::min(1.0, frac) * width);
      std::cerr << "\r[" << std::string(fill, '#') << std::string(width - fill, '.') << "] "
                << line << "   " << std::flush;
    } else if (!g.json && done != shown) {
      std::cerr << line << "\n";
      shown = done;
    }
    if (done == static_cast<int>(cands.size())) break;
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  if (!g.json && tty) std::cerr << "\n";
  for (auto* c : cands) {
    grpc::ClientContext ctx;
    SetDeadline(ctx, g.timeout_s);
    v1::GetHallOfFameRequest req;
    req.set_study_id(c->study_id);
    v1::GetHallOfFameResponse hof;
    grpc::Status s = conn.study().GetHallOfFame(&ctx, req, &hof);
    if (!s.ok() || hof.entries_size() == 0 || !hof.entries(0).individual().evaluation().valid()) {
      c->reason = s.ok() ? "no valid fit" : s.error_message();
      continue;
    }
    const auto& best = hof.entries(0).individual();
    c->values.assign(best.genes().begin(), best.genes().end());
    c->spread.assign(hof.spread().begin(), hof.spread().end());
    c->train = -best.evaluation().fitness();
    c->ok = true;
  }
  return kOk;
}

std::string SetArg(const Candidate& c) {
  std::vector<std::string> parts;
  for (size_t i = 0; i < c.genes.size() && i < c.values.size(); ++i)
    parts.push_back(absl::StrFormat("%s=%.17g", c.genes[i].name(), c.values[i]));
  return absl::StrJoin(parts, ",");
}

// Error of calibration-eval on each of the files with the candidate's fit; empty on failure.
std::vector<double> FileErrors(const Candidate& c, const std::vector<std::string>& files,
                               const v1::DiagnosisSpec& d, const std::string& out_dir,
                               const std::string& extra_set = "") {
  std::vector<std::string> argv = {SiblingBinary("gaitforge-sim"), "calibration-eval",
                                   "--recordings", absl::StrJoin(files, ","), "--options",
                                   "error=" + d.error()};
  std::string set = SetArg(c);
  if (!extra_set.empty()) set += (set.empty() ? "" : ",") + extra_set;
  if (!set.empty()) argv.insert(argv.end(), {"--set", set});
  if (!out_dir.empty()) {
    std::error_code ec;
    std::filesystem::create_directories(out_dir, ec);
    argv.insert(argv.end(), {"--out-dir", out_dir});
  }
  std::string out;
  if (RunCapture(argv, &out) != 0) return {};
  std::vector<double> errors;
  for (size_t at = out.find("\"error\": "); at != std::string::npos;
       at = out.find("\"error\": ", at + 1))
    errors.push_back(std::strtod(out.c_str() + at + 9, nullptr));
  if (!out_dir.empty()) std::ofstream(out_dir + "/eval.json") << out;
  return errors;
}

// Their mean; NAN on failure.
double HeldOutError(const Candidate& c, const std::vector<std::string>& files,
                    const v1::DiagnosisSpec& d, const std::string& out_dir,
                    const std::string& extra_set = "") {
  const std::vector<double> errors = FileErrors(c, files, d, out_dir, extra_set);
  double sum = 0;
  for (double e : errors) sum += e;
  return errors.empty() ? NAN : sum / errors.size();
}

// weighting: floor. The spread (sd) of the uncalibrated model's error on each training file
// over the numeric variants, and weights 1 / sd^2 (sd at least a tenth of the median, so a
// file the variants agree on cannot take all the weight), scaled to a mean of 1. Empty when
// an evaluation fails.
std::vector<double> FloorWeights(const v1::DiagnosisSpec& d, const std::vector<std::string>& files,
                                 std::vector<double>* floors) {
  const auto& variants = NumericVariants();
  std::vector<std::vector<double>> e(variants.size());
  for (size_t v = 0; v < variants.size(); ++v) {
    e[v] = FileErrors(Make(d, {}), files, d, "", variants[v]);
    if (e[v].size() != files.size()) return {};
  }
  floors->assign(files.size(), 0);
  for (size_t f = 0; f < files.size(); ++f) {
    double mean = 0, sq = 0;
    for (const auto& ev : e) mean += ev[f] / e.size();
    for (const auto& ev : e) sq += (ev[f] - mean) * (ev[f] - mean);
    (*floors)[f] = std::sqrt(sq / (e.size() - 1));
  }
  std::vector<double> sorted = *floors;
  std::sort(sorted.begin(), sorted.end());
  const double least = 0.1 * sorted[sorted.size() / 2];
  std::vector<double> w;
  double sum = 0;
  for (double sd : *floors) {
    w.push_back(1 / std::max(sd * sd, least * least + 1e-30));
    sum += w.back();
  }
  for (double& x : w) x *= w.size() / sum;
  return w;
}

// Held-out error of c under every numeric variant, two at a time; c.held is their mean (NAN if
// any variant fails: a fit that only works at one timestep is no fit).
void ScoreHeldOut(Candidate& c, const std::vector<std::string>& files, const v1::DiagnosisSpec& d) {
  const auto& variants = NumericVariants();
  c.held_variants.assign(variants.size(), NAN);
  for (size_t i = 0; i < variants.size(); i += 2) {
    std::thread t;
    if (i + 1 < variants.size())
      t = std::thread([&, i] { c.held_variants[i + 1] = HeldOutError(c, files, d, "", variants[i + 1]); });
    c.held_variants[i] = HeldOutError(c, files, d, "", variants[i]);
    if (t.joinable()) t.join();
  }
  double sum = 0;
  for (double e : c.held_variants) sum += e;
  c.held = sum / variants.size();
}

std::string Num(double x) { return std::isfinite(x) ? absl::StrFormat("%.6g", x) : "null"; }

std::string NumList(const std::vector<double>& v) {
  std::vector<std::string> parts;
  for (double x : v) parts.push_back(Num(x));
  return "[" + absl::StrJoin(parts, ", ") + "]";
}

std::string Quote(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) {
    if (ch == '"' || ch == '\\') out += '\\';
    if (ch == '\n') {
      out += "\\n";
      continue;
    }
    out += ch;
  }
  return out + "\"";
}

}  // namespace

int CmdDiagnose(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
                int threads, const std::string& out_root) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge diagnose SPEC.yaml [--workers N] [--json]\n";
    return kUsage;
  }
  std::ifstream in(args[0]);
  if (!in) {
    std::cerr << "gaitforge: cannot open diagnosis spec '" << args[0] << "'\n";
    return kNotFound;
  }
  std::stringstream text;
  text << in.rdbuf();
  v1::DiagnosisSpec d;
  if (auto s = spec::ParseMessage(text.str(), args[0], &d, nullptr); !s.ok()) {
    std::cerr << "gaitforge: " << s.message() << "\n";
    return kUsage;
  }
  Defaults(&d);
  if (auto s = Validate(d); !s.ok()) {
    std::cerr << "gaitforge: " << args[0] << ": " << s.message() << "\n";
    return kUsage;
  }
  std::string error;
  auto conn = Connection::Open(g, true, &error);
  if (!conn) {
    std::cerr << "gaitforge: " << error << "\n";
    return kUnavailable;
  }
  std::vector<pid_t> pids;
  if (g.coordinator.empty()) pids = StartLocalWorkers(g, conn->target(), workers, threads);
  struct Stopper {
    std::vector<pid_t>& p;
    ~Stopper() { for (pid_t x : p) Stop(x, 10); }
  } stopper{pids};

  // Recordings: upload the files, keep the hashes; local copies for evaluation.
  v1::StudySpec carrier;
  for (const auto& r : d.training()) carrier.mutable_objective()->add_recordings(r);
  for (const auto& r : d.held_out()) carrier.mutable_objective()->add_held_out(r);
  if (int c = UploadSpecRecordings(*conn, args[0], &carrier, g); c) return c;
  const std::vector<std::string> train(carrier.objective().recordings().begin(),
                                       carrier.objective().recordings().end());
  const std::vector<std::string> held(carrier.objective().held_out().begin(),
                                      carrier.objective().held_out().end());
  const std::string dir = out_root + "/" + d.name() + "-diagnosis";
  std::error_code ec;
  std::filesystem::create_directories(dir + "/recordings", ec);
  std::vector<std::string> train_files, held_files;
  int64_t n = 0;  // compared samples, for the BIC: period bins x channels per recording
  for (const auto& h : train) {
    const std::string f = DownloadRecording(*conn, h, dir + "/recordings", g);
    if (f.empty()) return kFailed;
    train_files.push_back(f);
    std::ifstream a(f), b(f + ".json");
    std::stringstream sa, sb;
    sa << a.rdbuf();
    sb << b.rdbuf();
    auto rec = recording::ParseRecording(sa.str(), sb.str(), f, f + ".json");
    if (!rec.ok()) {
      std::cerr << "gaitforge: " << rec.status().message() << "\n";
      return kUsage;
    }
    const double period = rec->meta.genes.size() == 13 ? rec->meta.genes[12] : 1.0;
    const int64_t bins = d.error() == "pointwise"
                             ? static_cast<int64_t>(rec->t.size())
                             : std::max<int64_t>(1, std::llround(period / rec->dt));
    n += bins * static_cast<int64_t>(rec->channels.size());
  }
  for (const auto& h : held) {
    const std::string f = DownloadRecording(*conn, h, dir + "/recordings", g);
    if (f.empty()) return kFailed;
    held_files.push_back(f);
  }
  auto bic = [&](const Candidate& c) {
    return static_cast<double>(n) * std::log(std::max(c.train * c.train, 1e-300)) +
           c.k * std::log(static_cast<double>(n));
  };

  // Recording weights (weighting: floor), the same in every fit.
  std::vector<double> weights, train_floors;
  std::string weights_option;
  if (d.weighting() == "floor") {
    weights = FloorWeights(d, train_files, &train_floors);
    if (weights.empty()) {
      std::cerr << "gaitforge: weighting: floor: the model failed on a training recording under "
                   "a numeric variant (gaitforge-sim calibration-eval)\n";
      return kFailed;
    }
    std::vector<std::string> parts;
    for (double w : weights) parts.push_back(absl::StrFormat("%.6g", w));
    weights_option = absl::StrJoin(parts, ",");
  }

  // 1. Baseline.
  int reused = 0;  // fits found in the database with the same spec, not run again
  Candidate base = Make(d, {});
  if (int c = RunStudies(*conn, d, {&base}, d.full_evaluations(), train, held, weights_option, g,
                         "baseline", &reused); c)
    return c;
  if (!base.ok) {
    std::cerr << "gaitforge: the baseline fit failed: " << base.reason << "\n";
    return kFailed;
  }
  base.bic = bic(base);
  // The noise floor: the spread of the baseline's held-out error over the numeric variants.
  ScoreHeldOut(base, held_files, d);
  double floor_sd = 0;
  for (double e : base.held_variants) floor_sd += (e - base.held) * (e - base.held);
  floor_sd = std::sqrt(floor_sd / std::max<size_t>(1, base.held_variants.size() - 1));

  // 2. Locate, on the baseline's residuals.
  std::string located = "{}";
  {
    (void)HeldOutError(base, train_files, d, dir + "/baseline-train");
    std::vector<std::string> argv = {
        "/usr/bin/python3",
        std::filesystem::path(PlotScriptPath()).parent_path().string() + "/gaitforge_locate.py",
        "--eval", dir + "/baseline-train/eval.json", "--out", dir + "/located.json", "--figure",
        dir + "/located.svg"};
    std::string ignored;
    if (const int code = RunCapture(argv, &ignored); code == 0) {
      std::ifstream lf(dir + "/located.json");
      std::stringstream ls;
      ls << lf.rdbuf();
      if (!ls.str().empty()) located = ls.str();
    } else {
      // The diagnosis goes on (locating describes, it does not decide), but says so.
      std::cerr << "gaitforge: warning: locating the mismatch failed (gaitforge_locate.py exit "
                << code << " on " << dir << "/baseline-train/eval.json); the report has no "
                << "'where it showed'\n";
    }
  }

  // 3. Screening: every candidate effect, a short fit each, all at once.
  std::vector<Candidate> screened;
  for (const auto& id : d.candidates()) screened.push_back(Make(d, {id}));
  std::vector<Candidate*> ptrs;
  for (auto& c : screened) ptrs.push_back(&c);
  if (int c = RunStudies(*conn, d, ptrs, d.screening_evaluations(), train, held, weights_option, g,
                         "screening", &reused); c)
    return c;
  std::sort(screened.begin(), screened.end(), [](const Candidate& a, const Candidate& b) {
    if (a.ok != b.ok) return a.ok;
    return a.train < b.train;
  });

  // 4. Full fits of the leaders, then pairs of them.
  // With screening_tie > 0, near ties with the last leader are refitted too.
  std::vector<double> screened_train;
  for (const auto& c : screened)
    if (c.ok) screened_train.push_back(c.train);
  const int leaders = LeadersToRefit(screened_train, d.top(), d.screening_tie());
  std::vector<Candidate> full;
  for (int i = 0; i < leaders; ++i) full.push_back(Make(d, screened[i].effects));
  const size_t singles = full.size();
  if (d.try_pairs())
    for (size_t i = 0; i < singles && i < 2; ++i)
      for (size_t j = i + 1; j < singles && j < 3; ++j)
        full.push_back(Make(d, {full[i].effects[0], full[j].effects[0]}));
  ptrs.clear();
  for (auto& c : full) ptrs.push_back(&c);
  if (int c = RunStudies(*conn, d, ptrs, d.full_evaluations(), train, held, weights_option, g,
                         "refitting", &reused); c)
    return c;
  const size_t base_genes = d.base_parameters_size();
  for (auto& c : full) {
    if (!c.ok) continue;
    c.bic = bic(c);
    ScoreHeldOut(c, held_files, d);
    for (size_t i = base_genes; i < c.genes.size() && i < c.values.size(); ++i) {
      if (c.genes[i].name().rfind("nuisance.", 0) == 0) continue;
      if (AtBound(c.values[i], c.genes[i].lo(), c.genes[i].hi())) {
        c.at_bound = true;
        c.bound_params.push_back(c.genes[i].name());
      }
    }
  }
  std::sort(full.begin(), full.end(), [](const Candidate& a, const Candidate& b) {
    if (a.ok != b.ok) return a.ok;
    return a.bic < b.bic;
  });

  // 5. Decide (clients/cli/diagnosis_decision.h).
  DecisionRule rule;
  rule.margin = d.margin();
  const std::vector<FitScore> scores(full.begin(), full.end());
  const Decision decision = Decide(base, scores, rule);
  const std::string verdict = decision.verdict;
  std::vector<const Candidate*> named;
  for (int i : decision.named) named.push_back(&full[i]);

  // 6. The corrected model: a caterpillar.distance option ready for new gait studies.
  std::string corrected;
  if (!named.empty()) {
    std::vector<std::string> set;
    const Candidate& w = *named[0];
    for (size_t i = 0; i < w.genes.size(); ++i)
      if (w.genes[i].name().rfind("nuisance.", 0) != 0)
        set.push_back(absl::StrFormat("%s=%.9g", w.genes[i].name(), w.values[i]));
    corrected = dir + "/corrected-model.yaml";
    std::ofstream(corrected)
        << "# The caterpillar model with the effect the gap finder found (" << w.label
        << "),\n# ready for new gait studies: use this objective section in a study spec.\n"
        << "objective:\n  name: caterpillar.distance\n  options:\n    set: \""
        << absl::StrJoin(set, ",") << "\"\n";
  }

  // Report: JSON and words.
  auto why_not = [&](const Candidate& c) {
    return WhyNotNamed(base, c, named.empty() ? nullptr : named[0], rule);
  };
  auto effect_json = [&](const Candidate& c) {
    std::string j = absl::StrCat("{\"id\": ", Quote(c.label), ", \"params\": {");
    for (size_t i = 0; i < c.genes.size() && i < c.values.size(); ++i)
      absl::StrAppend(&j, i ? ", " : "", Quote(c.genes[i].name()), ": {\"value\": ",
                      Num(c.values[i]), ", \"sd\": ", i < c.spread.size() ? Num(c.spread[i]) : "null",
                      "}");
    absl::StrAppend(&j, "}, \"train\": ", Num(c.train), ", \"held_out\": ", Num(c.held),
                    ", \"held_out_variants\": ", NumList(c.held_variants),
                    ", \"paired_t\": ", Num(PairedT(base.held_variants, c.held_variants)),
                    ", \"at_bound\": [", absl::StrJoin(c.bound_params, ", ", [](std::string* o, const std::string& n) { o->append(Quote(n)); }), "]",
                    ", \"delta_bic\": ",
                    Num(c.bic - base.bic));
    if (std::find(named.begin(), named.end(), &c) == named.end())
      absl::StrAppend(&j, ", \"why_not\": ", Quote(why_not(c)));
    absl::StrAppend(&j, "}");
    return j;
  };
  std::string json = absl::StrCat("{\"name\": ", Quote(d.name()), ", \"verdict\": ", Quote(verdict),
                                  ", \"effects\": [");
  for (size_t i = 0; i < named.size(); ++i) absl::StrAppend(&json, i ? ", " : "", effect_json(*named[i]));
  absl::StrAppend(&json, "], \"errors\": {\"baseline_train\": ", Num(base.train),
                  ", \"baseline_held_out\": ", Num(base.held),
                  ", \"baseline_held_out_variants\": ", NumList(base.held_variants),
                  ", \"noise_floor_held_out\": ", Num(floor_sd), ", \"weighting\": ",
                  Quote(d.weighting()), ", \"training_weights\": ", NumList(weights),
                  ", \"training_floors\": ", NumList(train_floors));
  if (!named.empty())
    absl::StrAppend(&json, ", \"train\": ", Num(named[0]->train), ", \"held_out\": ",
                    Num(named[0]->held));
  absl::StrAppend(&json, "}, \"runners_up\": [");
  int k = 0;
  for (const auto& c : full) {
    if (!named.empty() && &c == named[0]) continue;
    absl::StrAppend(&json, k++ ? ", " : "", effect_json(c));
  }
  absl::StrAppend(&json, "], \"screening\": [");
  k = 0;
  for (const auto& c : screened)
    absl::StrAppend(&json, k++ ? ", " : "", "{\"id\": ", Quote(c.label), ", \"train\": ",
                    Num(c.train), "}");
  std::string experiment;
  if (verdict == "ambiguous")
    for (const auto* c : named)
      if (const auto* e = effects::FindEffect(c->effects[0])) experiment += e->experiment + " ";
  // The figure's overlays: the baseline and the named explanation (or, with none named, the
  // fit closest held out) simulated on the held-out recordings.
  const Candidate* shown = named.empty() ? nullptr : named[0];
  if (!shown)
    for (const auto& c : full)
      if (c.ok && std::isfinite(c.held) && (!shown || c.held < shown->held)) shown = &c;
  std::string overlay = "{\"baseline_eval\": ";
  if (std::isfinite(HeldOutError(base, held_files, d, dir + "/baseline-held")))
    absl::StrAppend(&overlay, Quote(dir + "/baseline-held/eval.json"));
  else
    absl::StrAppend(&overlay, "null");
  if (shown && std::isfinite(HeldOutError(*shown, held_files, d, dir + "/explanation-held")))
    absl::StrAppend(&overlay, ", \"other_eval\": ", Quote(dir + "/explanation-held/eval.json"),
                    ", \"other\": ", Quote(named.empty() ? "closest rejected: " + shown->label
                                                          : shown->label));
  absl::StrAppend(&overlay, "}");
  absl::StrAppend(&json, "], \"refitted_singles\": ", singles, ", \"reused_fits\": ", reused,
                  ", \"located\": ", located,
                  ", \"experiment\": ", Quote(experiment), ", \"corrected_model\": ",
                  Quote(corrected), ", \"compared_samples\": ", n, ", \"rule\": {\"margin\": ",
                  Num(rule.margin), ", \"held_out_gain\": ", Num(rule.held_out_gain),
                  ", \"paired_t\": ", Num(rule.paired_t), ", \"pair_gain\": ",
                  Num(rule.pair_gain), "}, \"overlay\": ", overlay);
  // The figures: drawn from the report itself, then listed in it (only those written).
  std::ofstream(dir + "/diagnosis.json") << json << "}\n";
  std::vector<std::string> figures;
  if (std::filesystem::exists(dir + "/located.svg")) figures.push_back(dir + "/located.svg");
  if (RunPlotScript({"diagnosis", "--report", dir + "/diagnosis.json", "--out",
                     dir + "/diagnosis.svg"}) == 0)
    figures.push_back(dir + "/diagnosis.svg");
  else
    std::cerr << "gaitforge: warning: the diagnosis figure could not be drawn "
                 "(clients/python/gaitforge_plot.py diagnosis; needs python3-matplotlib)\n";
  absl::StrAppend(&json, ", \"figures\": [",
                  absl::StrJoin(figures, ", ", [](std::string* o, const std::string& f) {
                    o->append(Quote(f));
                  }),
                  "]}\n");
  std::ofstream(dir + "/diagnosis.json") << json;
  if (g.json) {
    std::cout << json;
  } else {
    std::cout << "diagnosis " << d.name() << ": ";
    if (verdict == "none") {
      std::cout << "no missing physics found: no candidate beat the baseline by the BIC margin ("
                << d.margin() << ") and cut its held-out error ("
                << absl::StrFormat("%.3g mm +- %.2g mm over numerically irrelevant variants",
                                   1000 * base.held, 1000 * floor_sd)
                << ") by " << static_cast<int>(rule.held_out_gain * 100)
                << "% with a paired t above " << rule.paired_t << " across the variants\n";
    } else {
      std::cout << (verdict == "found" ? "found " : "ambiguous between ");
      for (size_t i = 0; i < named.size(); ++i) std::cout << (i ? " and " : "") << named[i]->label;
      std::cout << "\n";
      for (const auto* c : named) {
        const auto* e = effects::FindEffect(c->effects[0]);
        if (e) std::cout << "  " << e->name << ": " << e->meaning << "\n";
        for (size_t i = 0; i < c->genes.size() && i < c->values.size(); ++i)
          std::cout << absl::StrFormat("    %-34s %12.5g  +- %s\n", c->genes[i].name(), c->values[i],
                                       i < c->spread.size() ? absl::StrFormat("%.3g", c->spread[i])
                                                            : std::string("n/a"));
      }
      std::cout << absl::StrFormat(
          "  held-out error %.4g -> %.4g mm, training %.4g -> %.4g mm, delta BIC %.1f\n",
          1000 * base.held, 1000 * named[0]->held, 1000 * base.train, 1000 * named[0]->train,
          named[0]->bic - base.bic);
      if (!experiment.empty()) std::cout << "  to tell them apart: " << experiment << "\n";
      std::cout << "  corrected model: " << corrected << "\n";
    }
    // Where it showed, in the locate script's words (its summary), then the files.
    google::protobuf::Struct where;
    if (google::protobuf::util::JsonStringToMessage(located, &where).ok() &&
        where.fields().count("summary"))
      std::cout << "  where it showed: " << where.fields().at("summary").string_value() << "\n";
    std::cout << "  where the mismatch lives, by slice: " << dir
              << "/located.json and located.svg\n";
    if (std::find(figures.begin(), figures.end(), dir + "/diagnosis.svg") != figures.end())
      std::cout << "  held-out errors and overlays, before and after: " << dir
                << "/diagnosis.svg\n";
    if (static_cast<int>(singles) > d.top())
      std::cout << "  refitted " << singles << " leaders of the screening, not " << d.top()
                << ": the last within " << 100 * d.screening_tie() << "% of the " << d.top()
                << (d.top() == 1 ? "st" : d.top() == 2 ? "nd" : d.top() == 3 ? "rd" : "th")
                << " (a short fit cannot order near ties)\n";
    std::cout << "  runners-up, and why they lost:\n";
    for (const auto& c : full)
      if (std::find(named.begin(), named.end(), &c) == named.end())
        std::cout << absl::StrFormat("    %s (dBIC %.1f, held-out %.3g mm%s): %s\n", c.label,
                                     c.bic - base.bic, 1000 * c.held,
                                     c.at_bound ? ", at the edge of its range: " +
                                                      absl::StrJoin(c.bound_params, ", ")
                                                : std::string(),
                                     why_not(c));
    std::cout << "  report: " << dir << "/diagnosis.json\n";
  }
  return kOk;
}

}  // namespace gaitforge::cli
