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

void WriteEvaluation(core::ByteWriter& w, const Evaluation& e) {
  w.U32(e.valid ? 1 : 0);
  w.F64(e.fitness);
  w.Str(e.reason);
  w.F64(e.violation);
}

Evaluation ReadEvaluation(core::ByteReader& r) {
  Evaluation e;
  e.valid = r.U32() != 0;
  e.fitness = r.F64();
  e.reason = r.Str();
  e.violation = r.F64();
  return e;
}

}  // namespace gaitforge::engines
