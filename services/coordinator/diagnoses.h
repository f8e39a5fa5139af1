// Diagnoses as stored jobs (docs/diagnosis.md, "Stored diagnoses"): the coordinator runs
// each one on a thread of its own with the gap finder library (services/diagnosis), its fits
// as studies of this coordinator; rows in the results database say what each is and, once
// completed, hold its report and files. A diagnosis survives the client that asked for it,
// and one that a stopped coordinator left running is run again on start: its finished fits
// are reused (same spec and seed), its interrupted ones resumed like any study.
#pragma once

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "absl/status/statusor.h"
#include "gaitforge/v1/diagnosis.pb.h"
#include "services/coordinator/coordinator.h"
#include "storage/study_store.h"

namespace gaitforge::coordinator {

class Diagnoses {
 public:
  // Each diagnosis works in work_root/ID (evaluations, figures, local copies of recordings).
  Diagnoses(Coordinator& c, std::string work_root, bool read_only);
  ~Diagnoses();
  Diagnoses(const Diagnoses&) = delete;
  Diagnoses& operator=(const Diagnoses&) = delete;

  // Runs again every diagnosis the database says is running.
  absl::Status Recover();
  // Starts one (spec validated, defaults applied, recordings stored), or returns the one
  // with the same spec that is running or completed.
  absl::StatusOr<v1::DiagnosisSummary> Create(v1::DiagnosisSpec spec);
  absl::StatusOr<v1::GetDiagnosisResponse> Get(const std::string& id, bool with_files);
  absl::StatusOr<std::vector<v1::DiagnosisSummary>> List();
  absl::StatusOr<v1::DiagnosisSummary> Cancel(const std::string& id);
  // Stops every run, leaving them running in the database (Recover takes them up again).
  void Shutdown();

 private:
  struct Run {
    std::string id;
    std::atomic<bool> cancel{false}, done{false};
    std::mutex mu;
    std::string stage, progress;  // GUARDED_BY(mu)
    double fraction = 0;          // GUARDED_BY(mu)
    std::vector<std::string> fits;  // studies it created; GUARDED_BY(mu)
    std::thread thread;
  };
  void Start(storage::DiagnosisRecord record);
  void Execute(Run& run, storage::DiagnosisRecord record);
  void CancelFits(Run& run);
  v1::DiagnosisSummary Summarize(const storage::DiagnosisRecord& r);
  absl::Status Save(storage::DiagnosisRecord r);

  Coordinator& c_;
  const std::string work_root_;
  const bool read_only_;
  std::atomic<bool> stopping_{false};
  std::mutex mu_;
  std::map<std::string, std::unique_ptr<Run>> runs_;  // GUARDED_BY(mu_)
};

}  // namespace gaitforge::coordinator
