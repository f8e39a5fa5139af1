#include "services/engines/engine.h"

namespace gaitforge::engines {

bool RanksBefore(const Evaluation& a, int member_a, const Evaluation& b, int member_b) {
  if (a.valid != b.valid) return a.valid;
  if (a.valid) {
    const bool fa = a.violation <= 0.0, fb = b.violation <= 0.0;
    if (fa != fb) return fa;
    if (!fa && a.violation != b.violation) return a.violation < b.violation;
    if (fa && a.fitness != b.fitness) return a.fitness > b.fitness;
  }
  return member_a < member_b;
}

}  // namespace gaitforge::engines
