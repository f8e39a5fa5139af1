#include "services/engines/log_genes.h"

#include <algorithm>
#include <cmath>

namespace gaitforge::engines {

double ToLogSpace(double x) { return std::log(x); }

LogGenesEngine::LogGenesEngine(std::unique_ptr<Engine> inner, std::vector<bool> log,
                               Bounds natural)
    : inner_(std::move(inner)), log_(std::move(log)), natural_(std::move(natural)) {
  MapAsked();
}

std::vector<double> LogGenesEngine::Natural(std::vector<double> genes) const {
  for (size_t i = 0; i < genes.size() && i < log_.size(); ++i)
    if (log_[i]) genes[i] = std::clamp(std::exp(genes[i]), natural_.lo[i], natural_.hi[i]);
  return genes;
}

void LogGenesEngine::MapAsked() {
  asked_ = inner_->Ask();
  for (auto& c : asked_) c.genes = Natural(std::move(c.genes));
}

absl::Status LogGenesEngine::Tell(const std::vector<Evaluation>& by_member) {
  absl::Status s = inner_->Tell(by_member);
  MapAsked();
  return s;
}

absl::Status LogGenesEngine::LoadState(std::string_view state) {
  absl::Status s = inner_->LoadState(state);
  MapAsked();
  return s;
}

std::vector<Ranked> LogGenesEngine::HallOfFame() const {
  std::vector<Ranked> hof = inner_->HallOfFame();
  for (auto& r : hof) r.genes = Natural(std::move(r.genes));
  return hof;
}

std::vector<double> LogGenesEngine::Spread() const {
  std::vector<double> spread = inner_->Spread();
  const std::vector<Ranked> hof = HallOfFame();
  for (size_t i = 0; i < spread.size() && i < log_.size(); ++i) {
    if (!log_[i]) continue;
    const double x = hof.empty() ? std::sqrt(natural_.lo[i] * natural_.hi[i]) : hof[0].genes[i];
    spread[i] = x * std::sinh(spread[i]);
  }
  return spread;
}

}  // namespace gaitforge::engines
