// What the gap finder needs of a coordinator: to create calibration studies, watch them and
// read their best fit. The coordinator that runs stored diagnoses gives it in process
// (services/coordinator/diagnoses.cc); tests give it in memory.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "absl/status/statusor.h"
#include "gaitforge/v1/study.pb.h"
#include "services/diagnosis/fits.h"

namespace gaitforge::diagnosis {

class Studies {
 public:
  virtual ~Studies() = default;
  virtual absl::StatusOr<std::vector<v1::StudySummary>> List() = 0;
  // The new study's id.
  virtual absl::StatusOr<std::string> Create(const v1::StudySpec& spec) = 0;
  virtual absl::StatusOr<v1::StudySummary> Get(const std::string& id) = 0;
  virtual absl::StatusOr<v1::GetHallOfFameResponse> HallOfFame(const std::string& id) = 0;
};

// Where a diagnosis says how it goes: a stage's progress (fraction of its evaluation budget
// spent, and a line saying so), remarks and warnings (one line each, no newline), and
// whether to stop (the coordinator shuts down, the user cancels): then the running stage
// returns Cancelled and the fits already done stay in the database.
struct Reporter {
  struct Progress {
    std::string stage;
    int fits_done = 0, fits = 0;
    double fraction = 0;
    std::string line;
  };
  std::function<void(const Progress&)> progress = [](const Progress&) {};
  std::function<void(const std::string&)> note = [](const std::string&) {};
  std::function<bool()> stopped = [] { return false; };
  // A fit's study was created for this diagnosis (not reused): its id.
  std::function<void(const std::string&)> fit_created = [](const std::string&) {};
};

// Creates (or reuses: a completed or running study with the same spec, seed included) the
// calibration studies that fit `cands` and waits for all of them; fills each candidate's
// study_id, values, spread and train (ok false with a reason when a fit has no valid
// member). `reused` counts the fits found in the database.
absl::Status RunFits(Studies& studies, const v1::DiagnosisSpec& d, std::vector<Candidate*> cands,
                     int evaluations, const StudyInputs& in, const Reporter& r,
                     const std::string& stage, int* reused);

}  // namespace gaitforge::diagnosis
