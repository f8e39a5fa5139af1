#include "services/engines/engine.h"

namespace gaitforge::engines {

bool RanksBefore(const Evaluation& a, int member_a, const Evaluation& b, int member_b) {
  if (a.valid != b.valid) return a.valid;
  if (a.valid && a.fitness != b.fitness) return a.fitness > b.fitness;
  return member_a < member_b;
}

}  // namespace gaitforge::engines
