// The gap finder's fits as studies (studies.h).
#include "services/diagnosis/studies.h"

#include <algorithm>
#include <chrono>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "google/protobuf/util/message_differencer.h"
#include "services/spec/spec_validation.h"

namespace gaitforge::diagnosis {
namespace {

std::string Eta(double seconds) {
  const int s = static_cast<int>(seconds + 0.5);
  return s >= 3600 ? absl::StrFormat("%dh%02dm", s / 3600, s / 60 % 60)
                   : absl::StrFormat("%dm%02ds", s / 60, s % 60);
}

// A study already in the database that fits spec: completed preferred over running.
std::string Existing(const std::vector<v1::StudySummary>& existing, const v1::StudySpec& spec) {
  v1::StudySpec normalised = spec;
  spec::ApplyDefaults(&normalised);
  std::string id;
  for (const auto& st : existing)
    if ((st.state() == v1::STUDY_STATE_COMPLETED || st.state() == v1::STUDY_STATE_RUNNING) &&
        google::protobuf::util::MessageDifferencer::Equals(st.spec(), normalised) &&
        (id.empty() || st.state() == v1::STUDY_STATE_COMPLETED))
      id = st.study_id();
  return id;
}

// Polls the studies until every one has finished, reporting progress.
absl::Status Wait(Studies& studies, const std::vector<Candidate*>& cands, int evaluations,
                  const Reporter& r, const std::string& stage) {
  const auto started = std::chrono::steady_clock::now();
  const double budget = static_cast<double>(evaluations) * cands.size();
  for (;;) {
    Reporter::Progress p{stage, 0, static_cast<int>(cands.size()), 0, ""};
    double spent = 0;
    for (auto* c : cands) {
      auto sum = studies.Get(c->study_id);
      if (!sum.ok()) return sum.status();
      const bool finished = sum->state() != v1::STUDY_STATE_RUNNING;
      p.fits_done += finished;
      // A fit that stopped early (CMA-ES tolerances) has used its budget.
      spent += finished ? evaluations : std::min<double>(sum->evaluations(), evaluations);
    }
    p.fraction = budget > 0 ? spent / budget : 1.0;
    const double elapsed =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    p.line = absl::StrFormat("%s: %d/%d fits done, %.0f/%.0f evaluations, ETA %s", stage,
                             p.fits_done, p.fits, spent, budget,
                             p.fraction > 0.02 ? Eta(elapsed * (1 - p.fraction) / p.fraction)
                                               : std::string("--"));
    r.progress(p);
    if (p.fits_done == p.fits) return absl::OkStatus();
    if (r.stopped()) return absl::CancelledError(stage + ": stopped");
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
}

}  // namespace

absl::Status RunFits(Studies& studies, const v1::DiagnosisSpec& d, std::vector<Candidate*> cands,
                     int evaluations, const StudyInputs& in, const Reporter& r,
                     const std::string& stage, int* reused_total) {
  // A study's result depends only on its spec and seed, so an interrupted diagnosis run
  // again picks up its completed fits and waits for its interrupted ones (a restarted
  // coordinator resumes them) instead of computing them twice.
  auto existing = studies.List();
  if (!existing.ok()) return existing.status();
  int reused = 0;
  for (auto* c : cands) {
    const v1::StudySpec spec = StudyFor(d, *c, evaluations, in);
    c->study_id = Existing(*existing, spec);
    if (!c->study_id.empty()) {
      ++reused;
      continue;
    }
    auto id = studies.Create(spec);
    if (!id.ok())
      return absl::Status(id.status().code(), absl::StrCat(c->label, ": ", id.status().message()));
    c->study_id = *id;
    r.fit_created(*id);
  }
  if (reused)
    r.note(absl::StrFormat("%s: %d of %d fits reused from the database (same spec and seed)",
                           stage, reused, cands.size()));
  *reused_total += reused;
  if (auto s = Wait(studies, cands, evaluations, r, stage); !s.ok()) return s;
  for (auto* c : cands) {
    auto hof = studies.HallOfFame(c->study_id);
    if (!hof.ok() || hof->entries_size() == 0 ||
        !hof->entries(0).individual().evaluation().valid()) {
      c->reason = hof.ok() ? "no valid fit" : std::string(hof.status().message());
      continue;
    }
    const auto& best = hof->entries(0).individual();
    c->values.assign(best.genes().begin(), best.genes().end());
    c->spread.assign(hof->spread().begin(), hof->spread().end());
    c->train = -best.evaluation().fitness();
    c->ok = true;
  }
  return absl::OkStatus();
}

}  // namespace gaitforge::diagnosis
