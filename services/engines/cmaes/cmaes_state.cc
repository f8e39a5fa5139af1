// CmaesEngine::SaveState / LoadState: the complete state in core::ByteWriter's binary
// form (doubles as IEEE bits), so save -> load -> continue is bit-identical. The strategy
// parameters are not stored: they are a deterministic function of (n, lambda).
#include <cmath>

#include "services/core/byte_codec.h"
#include "services/engines/cmaes/cmaes_engine.h"

namespace gaitforge::engines::cmaes {
namespace {

constexpr uint32_t kStateMagic = 0x31414d43;  // "CMA1"


void WriteMat(core::ByteWriter& w, const Eigen::MatrixXd& m) {
  w.U32(static_cast<uint32_t>(m.rows()));
  w.U32(static_cast<uint32_t>(m.cols()));
  w.F64s(std::vector<double>(m.data(), m.data() + m.size()));
}

// False when the stored shape is not rows x cols (cols < 0: any).
bool ReadMat(core::ByteReader& r, Eigen::MatrixXd& m, int rows, int cols) {
  const int64_t nr = r.U32(), nc = r.U32();
  const std::vector<double> v = r.F64s();
  if (nr != rows || (cols >= 0 && nc != cols) || static_cast<int64_t>(v.size()) != nr * nc)
    return false;
  m = Eigen::Map<const Eigen::MatrixXd>(v.data(), nr, nc);
  return true;
}

bool ReadVec(core::ByteReader& r, Eigen::VectorXd& v, int n) {
  const std::vector<double> d = r.F64s();
  if (static_cast<int>(d.size()) != n) return false;
  v = Eigen::Map<const Eigen::VectorXd>(d.data(), n);
  return true;
}

void WriteConfig(core::ByteWriter& w, const CmaesConfig& c) {
  w.U64(c.seed);
  w.F64s(c.bounds.lo);
  w.F64s(c.bounds.hi);
  w.F64s(c.mean0);
  w.F64(c.sigma0_fraction);
  w.U32(c.population);
  w.I64(c.max_evaluations);
  w.U32(static_cast<uint32_t>(c.restarts));
  w.U32(c.max_restarts);
  w.F64(c.tolfun);
  w.F64(c.tolx);
  w.F64(c.max_condition);
  w.U32(c.stop_fitness ? 1 : 0);
  w.F64(c.stop_fitness.value_or(0.0));
}

}  // namespace

std::string CmaesEngine::SaveState() const {
  core::ByteWriter w;
  w.U32(kStateMagic);
  WriteConfig(w, config_);
  w.U32(generation_);
  w.I64(evaluations_);
  w.U32(done_ ? 1 : 0);
  w.Str(stop_reason_);
  w.U32(run_);
  w.U32(doublings_);
  w.I64(evals_large_);
  w.I64(evals_small_);
  w.I64(last_large_evals_);
  w.U32(small_run_ ? 1 : 0);
  w.I64(run_start_evals_);
  w.I64(run_budget_);
  w.U32(params_.lambda);
  w.F64s(std::vector<double>(mean_.data(), mean_.data() + n_));
  w.F64(sigma_);
  w.F64(run_sigma0_);
  WriteMat(w, C_);
  WriteMat(w, B_);
  w.F64s(std::vector<double>(D_.data(), D_.data() + n_));
  w.F64s(std::vector<double>(pc_.data(), pc_.data() + n_));
  w.F64s(std::vector<double>(ps_.data(), ps_.data() + n_));
  w.U32(run_generation_);
  w.I64(eigen_evals_);
  w.F64s(best_history_);
  WriteMat(w, Z_);
  WriteMat(w, Y_);
  WriteRanked(w, hof_.entries());
  return w.data();
}

absl::Status CmaesEngine::LoadState(std::string_view state) {
  core::ByteReader r(state);
  if (r.U32() != kStateMagic) return absl::DataLossError("CMA-ES state: wrong magic number");
  core::ByteWriter mine, theirs;
  WriteConfig(mine, config_);
  CmaesConfig c;
  c.seed = r.U64();
  c.bounds.lo = r.F64s();
  c.bounds.hi = r.F64s();
  c.mean0 = r.F64s();
  c.sigma0_fraction = r.F64();
  c.population = static_cast<int>(r.U32());
  c.max_evaluations = r.I64();
  c.restarts = static_cast<Restarts>(r.U32());
  c.max_restarts = static_cast<int>(r.U32());
  c.tolfun = r.F64();
  c.tolx = r.F64();
  c.max_condition = r.F64();
  const bool has_stop = r.U32() != 0;
  const double stop = r.F64();
  if (has_stop) c.stop_fitness = stop;
  WriteConfig(theirs, c);
  if (!r.ok() || mine.data() != theirs.data())
    return absl::FailedPreconditionError("CMA-ES state belongs to a different configuration");

  const int generation = static_cast<int>(r.U32());
  const int64_t evaluations = r.I64();
  const bool done = r.U32() != 0;
  std::string stop_reason = r.Str();
  const int run = static_cast<int>(r.U32());
  const int doublings = static_cast<int>(r.U32());
  const int64_t evals_large = r.I64(), evals_small = r.I64(), last_large = r.I64();
  const bool small_run = r.U32() != 0;
  const int64_t run_start = r.I64(), run_budget = r.I64();
  const int lambda = static_cast<int>(r.U32());
  if (lambda < 4 || lambda > (1 << 24)) return absl::DataLossError("CMA-ES state: bad lambda");
  Eigen::VectorXd mean, d, pc, ps;
  Eigen::MatrixXd cov, b, z, y;
  bool shapes = ReadVec(r, mean, n_);
  const double sigma = r.F64(), run_sigma0 = r.F64();
  shapes = ReadMat(r, cov, n_, n_) && shapes;
  shapes = ReadMat(r, b, n_, n_) && shapes;
  shapes = ReadVec(r, d, n_) && shapes;
  shapes = ReadVec(r, pc, n_) && shapes;
  shapes = ReadVec(r, ps, n_) && shapes;
  const int run_generation = static_cast<int>(r.U32());
  const int64_t eigen_evals = r.I64();
  std::vector<double> history = r.F64s();
  shapes = ReadMat(r, z, n_, -1) && shapes;
  shapes = ReadMat(r, y, n_, -1) && shapes;
  std::vector<Ranked> hof;
  if (!ReadRanked(r, hof, hof_.capacity(), n_) && r.ok())
    return absl::DataLossError("CMA-ES state: malformed hall of fame");
  if (auto s = r.status("CMA-ES state"); !s.ok()) return s;
  if (!r.AtEnd()) return absl::DataLossError("CMA-ES state: trailing bytes");
  if (!shapes || z.cols() != lambda || y.cols() != lambda)
    return absl::DataLossError("CMA-ES state: malformed matrices");

  generation_ = generation;
  evaluations_ = evaluations;
  done_ = done;
  stop_reason_ = std::move(stop_reason);
  run_ = run;
  doublings_ = doublings;
  evals_large_ = evals_large;
  evals_small_ = evals_small;
  last_large_evals_ = last_large;
  small_run_ = small_run;
  run_start_evals_ = run_start;
  run_budget_ = run_budget;
  params_ = DefaultStrategyParams(n_, lambda);
  mean_ = mean;
  sigma_ = sigma;
  run_sigma0_ = run_sigma0;
  C_ = cov;
  B_ = b;
  D_ = d;
  pc_ = pc;
  ps_ = ps;
  run_generation_ = run_generation;
  eigen_evals_ = eigen_evals;
  best_history_ = std::move(history);
  Z_ = z;
  Y_ = y;
  hof_.set_entries(std::move(hof));
  // The candidates are a pure function of (mean, sigma, Y) and the bounds.
  candidates_.clear();
  if (!done_) FillCandidates();
  return absl::OkStatus();
}

}  // namespace gaitforge::engines::cmaes
