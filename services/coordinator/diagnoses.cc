// Diagnoses as stored jobs (diagnoses.h).
#include "services/coordinator/diagnoses.h"

#include <chrono>
#include <filesystem>
#include <fstream>

#include "absl/strings/str_cat.h"
#include "google/protobuf/struct.pb.h"
#include "google/protobuf/util/json_util.h"
#include "google/protobuf/util/message_differencer.h"
#include "services/core/file_text.h"
#include "services/diagnosis/pipeline.h"
#include "services/diagnosis/spec.h"
#include "spdlog/spdlog.h"

namespace gaitforge::coordinator {
namespace {

int64_t NowMs() {
  return std::chrono::duration_cast<std::chrono::milliseconds>(
             std::chrono::system_clock::now().time_since_epoch())
      .count();
}

v1::DiagnosisState StateOf(const std::string& s) {
  if (s == "running") return v1::DIAGNOSIS_STATE_RUNNING;
  if (s == "completed") return v1::DIAGNOSIS_STATE_COMPLETED;
  if (s == "failed") return v1::DIAGNOSIS_STATE_FAILED;
  if (s == "cancelled") return v1::DIAGNOSIS_STATE_CANCELLED;
  return v1::DIAGNOSIS_STATE_UNSPECIFIED;
}

// The files of a finished diagnosis that are kept with it in the database.
// robot.yaml: the descriptor the corrected model names, when the diagnosis ran on one
// (another resolution of the robot, or a descriptor the spec carried).
const char* const kKeptFiles[] = {"diagnosis.json",    "diagnosis.svg", "located.svg",
                                  "located.json",      "located-held.json", "plan.json",
                                  "corrected-model.yaml", "robot.yaml"};

// The fits of a diagnosis, as studies of this coordinator.
class CoordinatorStudies : public diagnosis::Studies {
 public:
  explicit CoordinatorStudies(Coordinator& c) : c_(c) {}
  absl::StatusOr<std::vector<v1::StudySummary>> List() override { return c_.ListStudies(); }
  absl::StatusOr<std::string> Create(const v1::StudySpec& spec) override {
    auto s = c_.CreateStudy(spec);
    if (!s.ok()) return s.status();
    return s->study_id();
  }
  absl::StatusOr<v1::StudySummary> Get(const std::string& id) override { return c_.GetStudy(id); }
  absl::StatusOr<v1::GetHallOfFameResponse> HallOfFame(const std::string& id) override {
    return c_.HallOfFame(id, std::nullopt);
  }

 private:
  Coordinator& c_;
};

}  // namespace

Diagnoses::Diagnoses(Coordinator& c, std::string work_root, bool read_only)
    : c_(c), work_root_(std::move(work_root)), read_only_(read_only) {}

Diagnoses::~Diagnoses() { Shutdown(); }

void Diagnoses::Shutdown() {
  stopping_ = true;
  std::map<std::string, std::unique_ptr<Run>> runs;
  {
    std::lock_guard<std::mutex> l(mu_);
    runs.swap(runs_);
  }
  for (auto& [id, run] : runs)
    if (run->thread.joinable()) run->thread.join();
}

absl::Status Diagnoses::Save(storage::DiagnosisRecord r) {
  r.updated_ms = NowMs();
  return c_.store().PutDiagnosis(r).get();
}

absl::Status Diagnoses::Recover() {
  if (read_only_) return absl::OkStatus();
  auto all = c_.store().ListDiagnoses();
  if (!all.ok()) return all.status();
  for (auto& r : *all)
    if (r.state == "running") {
      spdlog::info("diagnosis {}: running again after a restart (finished fits are reused)",
                   r.diagnosis_id);
      auto full = c_.store().GetDiagnosis(r.diagnosis_id, false);
      if (!full.ok()) return full.status();
      Start(std::move(*full));
    }
  return absl::OkStatus();
}

absl::StatusOr<v1::DiagnosisSummary> Diagnoses::Create(v1::DiagnosisSpec spec) {
  if (read_only_)
    return absl::FailedPreconditionError("this coordinator is read-only: it runs no diagnoses");
  // No robot named: the one the first training recording was recorded of.
  if (spec.robot().empty() && spec.training_size() > 0)
    if (auto first = c_.recordings().Get(spec.training(0)); first.ok())
      spec.set_robot(first->recording().robot());
  diagnosis::Defaults(&spec);
  if (auto s = diagnosis::Validate(spec); !s.ok()) return s;
  if (auto s = c_.recordings().CheckExist(spec.training(), "training"); !s.ok()) return s;
  if (auto s = c_.recordings().CheckExist(spec.held_out(), "held_out"); !s.ok()) return s;
  if (auto s = c_.recordings().CheckOneRobotAndRate(
          spec.robot(), {{"training", &spec.training()}, {"held_out", &spec.held_out()}});
      !s.ok())
    return s;
  auto all = c_.store().ListDiagnoses();
  if (!all.ok()) return all.status();
  for (const auto& r : *all) {
    v1::DiagnosisSpec stored;
    if ((r.state == "running" || r.state == "completed") && stored.ParseFromString(r.spec) &&
        google::protobuf::util::MessageDifferencer::Equals(stored, spec))
      return Summarize(r);
  }
  storage::DiagnosisRecord r;
  r.diagnosis_id = NewId(spec.name());
  r.name = spec.name();
  r.spec = spec.SerializeAsString();
  r.state = "running";
  r.created_ms = NowMs();
  if (auto s = Save(r); !s.ok()) return s;
  spdlog::info("diagnosis {} created", r.diagnosis_id);
  Start(r);
  return Summarize(r);
}

void Diagnoses::Start(storage::DiagnosisRecord record) {
  std::lock_guard<std::mutex> l(mu_);
  if (stopping_) return;
  auto run = std::make_unique<Run>();
  run->id = record.diagnosis_id;
  Run* raw = run.get();
  runs_[record.diagnosis_id] = std::move(run);
  raw->thread = std::thread([this, raw, record = std::move(record)]() mutable {
    Execute(*raw, std::move(record));
  });
}

namespace {

// Local copies of the recordings, named HASH16-NAME as the CLI downloads them.
absl::StatusOr<std::vector<std::string>> Materialize(
    storage::StudyStore& store, const google::protobuf::RepeatedPtrField<std::string>& hashes,
    const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  std::vector<std::string> files;
  for (const auto& h : hashes) {
    auto rec = store.GetRecording(h, true);
    if (!rec.ok()) return rec.status();
    const std::string path = absl::StrCat(dir, "/", h.substr(0, 16), "-", rec->name);
    std::ofstream(path, std::ios::binary) << rec->csv;
    std::ofstream(path + ".json", std::ios::binary) << rec->sidecar;
    files.push_back(path);
  }
  return files;
}

std::string ReadBytes(const std::string& path) { return core::ReadWholeFile(path).value_or(""); }

}  // namespace

void Diagnoses::Execute(Run& run, storage::DiagnosisRecord record) {
  v1::DiagnosisSpec spec;
  spec.ParseFromString(record.spec);
  diagnosis::Inputs in;
  in.dir = work_root_ + "/" + record.diagnosis_id;
  in.train.assign(spec.training().begin(), spec.training().end());
  in.held.assign(spec.held_out().begin(), spec.held_out().end());
  absl::StatusOr<std::string> report = std::string();
  auto train = Materialize(c_.store(), spec.training(), in.dir + "/recordings");
  auto held = Materialize(c_.store(), spec.held_out(), in.dir + "/recordings");
  if (!train.ok() || !held.ok()) {
    report = !train.ok() ? train.status() : held.status();
  } else {
    in.train_files = *train;
    in.held_files = *held;
    diagnosis::Reporter r;
    r.progress = [&run](const diagnosis::Reporter::Progress& p) {
      std::lock_guard<std::mutex> l(run.mu);
      run.stage = p.stage;
      run.fraction = p.fraction;
      run.progress = p.line;
    };
    r.note = [&run](const std::string& line) { spdlog::info("diagnosis {}: {}", run.id, line); };
    r.stopped = [this, &run] { return run.cancel.load() || stopping_.load(); };
    r.fit_created = [&run](const std::string& id) {
      std::lock_guard<std::mutex> l(run.mu);
      run.fits.push_back(id);
    };
    CoordinatorStudies studies(c_);
    report = diagnosis::Diagnose(spec, in, studies, r);
  }
  run.done = true;
  if (stopping_ && !run.cancel) return;  // still running in the database: Recover resumes it
  if (run.cancel) CancelFits(run);
  if (report.ok()) {
    record.state = "completed";
    record.report = *report;
    google::protobuf::Struct parsed;
    if (google::protobuf::util::JsonStringToMessage(*report, &parsed).ok() &&
        parsed.fields().count("verdict"))
      record.verdict = parsed.fields().at("verdict").string_value();
    for (const char* f : kKeptFiles)
      if (std::filesystem::exists(in.dir + "/" + f))
        record.files.emplace_back(f, ReadBytes(in.dir + "/" + f));
  } else {
    record.state = run.cancel ? "cancelled" : "failed";
    record.error = std::string(report.status().message());
  }
  if (auto s = Save(record); !s.ok())
    spdlog::error("diagnosis {}: cannot store its end: {}", record.diagnosis_id,
                  std::string(s.message()));
  spdlog::info("diagnosis {} {}{}", record.diagnosis_id, record.state,
               record.error.empty() ? "" : ": " + record.error);
}

// A cancelled diagnosis's fits that still run are cancelled too (those it reused from
// another diagnosis are left alone).
void Diagnoses::CancelFits(Run& run) {
  std::lock_guard<std::mutex> l(run.mu);
  for (const auto& id : run.fits) {
    auto s = c_.GetStudy(id);
    if (s.ok() && s->state() == v1::STUDY_STATE_RUNNING) (void)c_.CancelStudy(id);
  }
}

v1::DiagnosisSummary Diagnoses::Summarize(const storage::DiagnosisRecord& r) {
  v1::DiagnosisSummary s;
  s.set_diagnosis_id(r.diagnosis_id);
  s.mutable_spec()->ParseFromString(r.spec);
  s.set_state(StateOf(r.state));
  s.set_verdict(r.verdict);
  s.set_error(r.error);
  s.set_created_ms(r.created_ms);
  s.set_updated_ms(r.updated_ms);
  std::lock_guard<std::mutex> l(mu_);
  if (auto it = runs_.find(r.diagnosis_id); it != runs_.end() && r.state == "running") {
    std::lock_guard<std::mutex> rl(it->second->mu);
    s.set_stage(it->second->stage);
    s.set_fraction(it->second->fraction);
    s.set_progress(it->second->progress);
  }
  return s;
}

absl::StatusOr<v1::GetDiagnosisResponse> Diagnoses::Get(const std::string& id, bool with_files) {
  auto r = c_.store().GetDiagnosis(id, with_files);
  if (!r.ok()) return r.status();
  v1::GetDiagnosisResponse out;
  *out.mutable_diagnosis() = Summarize(*r);
  out.set_report_json(r->report);
  for (auto& [name, content] : r->files) {
    auto* f = out.add_files();
    f->set_name(name);
    f->set_content(std::move(content));
  }
  return out;
}

absl::StatusOr<std::vector<v1::DiagnosisSummary>> Diagnoses::List() {
  auto all = c_.store().ListDiagnoses();
  if (!all.ok()) return all.status();
  std::vector<v1::DiagnosisSummary> out;
  for (const auto& r : *all) out.push_back(Summarize(r));
  return out;
}

absl::StatusOr<v1::DiagnosisSummary> Diagnoses::Cancel(const std::string& id) {
  auto r = c_.store().GetDiagnosis(id, false);
  if (!r.ok()) return r.status();
  if (r->state != "running")
    return absl::FailedPreconditionError(
        absl::StrCat("diagnosis ", id, " is ", r->state, ", not running"));
  {
    std::lock_guard<std::mutex> l(mu_);
    auto it = runs_.find(id);
    if (it == runs_.end())
      return absl::FailedPreconditionError(
          absl::StrCat("diagnosis ", id, " is not run by this coordinator"));
    it->second->cancel = true;
  }
  return Summarize(*r);
}

}  // namespace gaitforge::coordinator
