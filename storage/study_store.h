#pragma once
// The results database as the coordinator sees it. Plain records in, plain records out:
// no protobuf types, so the store can be tested and replaced on its own.
//
// Contracts (../shared/guides/design.md, "Durability"):
//  - one writer thread owns the write connection; writes are applied in the order they
//    were submitted, several per transaction; a returned future is ready once its write is
//    committed (or failed, leaving nothing of it behind);
//  - CommitGeneration writes the generation's statistics, the engine state, the hall of
//    fame, carried members and the study's progress in one transaction;
//  - reads use their own connections and never wait for the writer.
#include <cstdint>
#include <functional>
#include <future>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"

namespace gaitforge::storage {

struct StudyRecord {
  std::string study_id;
  std::string name;
  std::string spec;       // serialized StudySpec
  std::string spec_json;  // for people
  std::string state;      // running | paused | cancelled | completed | failed
  int generations_total = 0;
  int generations_done = 0;
  std::optional<double> best_fitness;
  std::optional<double> mean_fitness;
  int64_t evaluations = 0;
  int64_t created_ms = 0;
  int64_t updated_ms = 0;
  std::string error;
  std::string sim_build;  // pinned by the first lease; empty until then
};

struct IndividualRecord {
  std::string study_id;
  int generation = 0;
  int member = 0;
  std::vector<double> genes;
  bool valid = false;
  double fitness = 0.0;
  std::string reason;
  std::map<std::string, double> metrics;
  std::string worker_id;
  double eval_seconds = 0.0;
  bool carried = false;
  int origin_generation = 0;
  int origin_member = 0;
  int64_t reported_ms = 0;
  double violation = 0.0;  // total constraint violation; 0 = feasible
};

struct HofRecord {
  int rank = 0;
  int origin_generation = 0;
  int origin_member = 0;
  std::vector<double> genes;
  bool valid = false;
  double fitness = 0.0;
};

// What the job queue saw while a generation ran.
struct JobCounters {
  int64_t leases = 0;
  int64_t lease_expiries = 0;
  int64_t duplicates = 0;
  int64_t backups = 0;
  int64_t poisoned = 0;
};

struct GenerationRecord {
  std::string study_id;
  int generation = 0;
  double best = 0, mean = 0, stddev = 0, diversity = 0;
  int evaluations = 0;  // members evaluated in this generation (not carried)
  int invalid = 0;
  // Read only: the commonest reason among the invalid members ("" if none is invalid).
  std::string invalid_reason;
  int64_t committed_ms = 0;
  JobCounters counters;
  std::string engine_state;
  std::vector<HofRecord> hall_of_fame;
  std::vector<IndividualRecord> carried;  // members not evaluated again
  // The study row after this generation.
  std::string study_state;
  std::optional<double> study_best;  // the hall of fame's best
  int64_t study_evaluations = 0;
};

struct RecordingRecord {
  std::string hash;
  std::string name;
  std::string robot;
  int64_t rows = 0;
  std::vector<std::string> channels;
  double dt = 0;
  int dropped_rows = 0;
  std::string csv;      // empty when listed without bytes
  std::string sidecar;
  int64_t added_ms = 0;
  int64_t bytes = 0;    // CSV plus sidecar, also when listed without them
};

// A diagnosis as a stored job (docs/diagnosis.md, "Stored diagnoses").
struct DiagnosisRecord {
  std::string diagnosis_id;
  std::string name;
  std::string spec;     // serialized DiagnosisSpec
  std::string state;    // running | completed | failed | cancelled
  std::string verdict;  // found | ambiguous | none, once completed
  std::string error;
  std::string report;   // diagnosis.json; empty when listed
  int64_t created_ms = 0;
  int64_t updated_ms = 0;
  std::vector<std::pair<std::string, std::string>> files;  // (name, content); when asked for
};

struct Durability {
  // synchronous=FULL: a commit survives power loss. NORMAL: survives a process crash.
  bool full_sync = true;
};

class StudyStore {
 public:
  virtual ~StudyStore() = default;

  // Writes (ordered, asynchronous; wait on the future for durability).
  virtual std::future<absl::Status> CreateStudy(const StudyRecord& study) = 0;
  virtual std::future<absl::Status> AppendResults(std::vector<IndividualRecord> results) = 0;
  virtual std::future<absl::Status> CommitGeneration(GenerationRecord generation) = 0;
  virtual std::future<absl::Status> SetStudySimBuild(const std::string& study_id,
                                                     const std::string& sim_build) = 0;
  virtual std::future<absl::Status> SetStudyState(const std::string& study_id,
                                                  const std::string& state,
                                                  const std::string& error) = 0;

  // Stores a recording unless one with its hash exists; the future holds true if stored.
  virtual std::future<absl::StatusOr<bool>> PutRecording(const RecordingRecord& recording) = 0;

  // Inserts or replaces a diagnosis (with its files, when it has any).
  virtual std::future<absl::Status> PutDiagnosis(const DiagnosisRecord& diagnosis) = 0;

  // Reads. NotFound names the study id.
  virtual absl::StatusOr<StudyRecord> GetStudy(const std::string& study_id) = 0;
  virtual absl::StatusOr<std::vector<StudyRecord>> ListStudies() = 0;
  virtual absl::StatusOr<std::vector<GenerationRecord>> History(const std::string& study_id) = 0;
  // The hall of fame after `generation`, or after the latest committed one when unset.
  // Returns the generation it belongs to.
  virtual absl::StatusOr<std::pair<int, std::vector<HofRecord>>> HallOfFame(
      const std::string& study_id, std::optional<int> generation) = 0;
  virtual absl::StatusOr<std::vector<IndividualRecord>> Individuals(const std::string& study_id,
                                                                    int generation) = 0;
  // Engine state after the latest committed generation; nullopt if none was committed.
  virtual absl::StatusOr<std::optional<std::pair<int, std::string>>> LatestEngineState(
      const std::string& study_id) = 0;
  virtual absl::StatusOr<RecordingRecord> GetRecording(const std::string& hash,
                                                      bool with_bytes) = 0;
  virtual absl::StatusOr<std::vector<RecordingRecord>> ListRecordings() = 0;
  virtual absl::StatusOr<DiagnosisRecord> GetDiagnosis(const std::string& id,
                                                       bool with_files) = 0;
  virtual absl::StatusOr<std::vector<DiagnosisRecord>> ListDiagnoses() = 0;
  // Blocks until every write submitted so far is committed.
  virtual absl::Status Flush() = 0;
  // Called on the writer thread after each transaction with its duration in seconds. Set
  // before the first write.
  virtual void SetCommitObserver(std::function<void(double)> observer) = 0;
};

// Opens (creating if needed) the SQLite file at `path`, applies migrations, sets WAL.
absl::StatusOr<std::unique_ptr<StudyStore>> OpenSqliteStore(const std::string& path,
                                                            Durability durability = {});

}  // namespace gaitforge::storage
