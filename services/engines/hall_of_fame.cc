#include "services/engines/hall_of_fame.h"

#include <algorithm>

namespace gaitforge::engines {

bool HallOfFame::Admits(const Evaluation& eval) const {
  if (capacity_ <= 0) return false;  // a hall of no one (a sweep with top_k 0)
  if (static_cast<int>(entries_.size()) < capacity_) return true;
  // A later individual that only ties the last entry does not displace it.
  return Better(eval, entries_.back().eval);
}

void HallOfFame::Offer(int generation, int member, const std::vector<double>& genes,
                       const Evaluation& eval) {
  if (!Admits(eval)) return;
  for (auto it = entries_.begin(); it != entries_.end(); ++it) {
    if (!SameGenotype(genes, it->genes, bounds_)) continue;
    if (!Better(eval, it->eval)) return;  // the same gait is there already, as good
    entries_.erase(it);
    break;
  }
  // Insert after every entry that is not worse (earlier individuals win ties).
  auto pos = std::upper_bound(entries_.begin(), entries_.end(), eval,
                              [](const Evaluation& e, const Ranked& r) {
                                return Better(e, r.eval);
                              });
  entries_.insert(pos, Ranked{generation, member, genes, eval});
  if (static_cast<int>(entries_.size()) > capacity_) entries_.pop_back();
}

}  // namespace gaitforge::engines
