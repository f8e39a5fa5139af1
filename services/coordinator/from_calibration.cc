#include "services/coordinator/from_calibration.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "absl/strings/str_join.h"
#include "robots/registry.h"
#include "services/coordinator/corrected_model.h"
#include "services/core/objective_catalog.h"
#include "spdlog/spdlog.h"

namespace gaitforge::coordinator {
namespace {

const std::string kField = "objective.from_calibration";

// The gait objective of the robot a calibration objective fits: a built-in robot's own
// distance objective, else robot.distance (with that robot).
std::string GaitObjectiveOf(const core::ObjectiveInfo& calibration) {
  if (calibration.calibrates.empty()) return "robot.distance";
  const std::string& own = robots::Robot(calibration.calibrates).distance_objective;
  return own.empty() ? "robot.distance" : own;
}

bool IsNuisance(const core::ObjectiveInfo& info, const std::string& gene) {
  return std::find(info.nuisance.begin(), info.nuisance.end(), gene) != info.nuisance.end();
}

// The genes of every evaluation of calibration `id` (generations 0 .. last) that fits its
// recordings as well as its best (open_ranges.h), best first; empty when the best has no
// per-recording errors.
std::vector<std::vector<double>> FitsOf(storage::StudyStore& store, const std::string& id,
                                        int last, const storage::HofRecord& best) {
  std::vector<storage::IndividualRecord> evaluated;
  for (int g = 0; g <= last; ++g) {
    auto members = store.Individuals(id, g);
    if (!members.ok()) continue;
    for (auto& m : *members) evaluated.push_back(std::move(m));
  }
  const storage::IndividualRecord* found = nullptr;
  for (const auto& r : evaluated)
    if (r.generation == best.origin_generation && r.member == best.origin_member) found = &r;
  if (found == nullptr) return {};
  auto out = FitsLeftOpen(evaluated, *found, best.genes.size());
  spdlog::info("from_calibration {}: {} of {} evaluations fit the recordings as well as its best",
               id, out.size(), evaluated.size());
  return out;
}

}  // namespace

std::vector<GeneRange> SpreadRanges(const std::vector<double>& best,
                                    const std::vector<double>& spread,
                                    const std::vector<bool>& log) {
  std::vector<GeneRange> out(std::min(best.size(), spread.size()));
  for (size_t i = 0; i < out.size(); ++i) {
    if (!std::isfinite(spread[i])) continue;
    if (i < log.size() && log[i] && best[i] > 0) {
      const double s = std::asinh(spread[i] / best[i]);
      out[i] = {best[i] * std::exp(-2 * s), best[i] * std::exp(2 * s)};
    } else {
      out[i] = {best[i] - 2 * spread[i], best[i] + 2 * spread[i]};
    }
  }
  return out;
}

absl::Status ApplyCalibration(const std::string& id, const v1::StudySpec& calibration,
                              const std::vector<double>& best,
                              const std::vector<GeneRange>& ranges, v1::StudySpec* spec) {
  const auto& fit = calibration.objective();
  const core::ObjectiveInfo* info = core::FindObjective(fit.name());
  if (info == nullptr || !info->calibration)
    return absl::FailedPreconditionError(absl::StrCat(
        kField, ": study ", id, " is a ", fit.name(), " study, not a calibration"));
  if (best.size() != static_cast<size_t>(calibration.bounds_size()))
    return absl::FailedPreconditionError(
        absl::StrCat(kField, ": study ", id, "'s best has ", best.size(), " genes for ",
                     calibration.bounds_size(), " bounds"));
  const std::string name = GaitObjectiveOf(*info);
  auto* o = spec->mutable_objective();
  if (!o->name().empty() && o->name() != name)
    return absl::InvalidArgumentError(absl::StrCat(
        kField, ": study ", id, " calibrates a model whose gait objective is '", name,
        "', not '", o->name(), "'"));
  o->set_name(name);
  if (name == "robot.distance" && o->robot().empty() && o->robot_descriptor().empty()) {
    o->set_robot(info->calibrates.empty() ? fit.robot() : info->calibrates);
    o->set_robot_descriptor(fit.robot_descriptor());
  }
  std::vector<std::string> set;
  if (fit.options().count("set") && !fit.options().at("set").empty())
    set.push_back(fit.options().at("set"));
  for (int i = 0; i < calibration.bounds_size(); ++i)
    if (!IsNuisance(*info, calibration.bounds(i).name()))
      set.push_back(absl::StrFormat("%s=%.9g", calibration.bounds(i).name(), best[i]));
  PrependSet(o, absl::StrJoin(set, ","));
  if (fit.params().count("timestep_ms") && !o->params().count("timestep_ms"))
    (*o->mutable_params())["timestep_ms"] = fit.params().at("timestep_ms");
  if (!o->has_robust() || o->robust().sampling() == "fits") return absl::OkStatus();
  for (int i = 0; i < calibration.bounds_size() && i < static_cast<int>(ranges.size()); ++i) {
    const auto& b = calibration.bounds(i);
    if (IsNuisance(*info, b.name()) || !ranges[i].ok()) continue;
    const double lo = std::max(b.lo(), ranges[i].lo);
    const double hi = std::min(b.hi(), ranges[i].hi);
    // Sampled linearly even for a gene searched by its logarithm: sampled by their
    // logarithm, the ranges put the members near a fit that had underestimated the
    // build's creep, and transfer fell on both independent builds (objectives.md).
    if (lo < hi) AddEnsembleRange(o, b.name(), lo, hi);
  }
  return absl::OkStatus();
}

absl::Status ApplyFits(const std::string& id, const v1::StudySpec& calibration,
                       const std::vector<std::vector<double>>& fits, v1::StudySpec* spec) {
  const core::ObjectiveInfo* info = core::FindObjective(calibration.objective().name());
  auto* r = spec->mutable_objective()->mutable_robust();
  std::vector<int> genes;  // the calibrated values: every bound but the nuisances
  for (int i = 0; i < calibration.bounds_size(); ++i)
    if (info == nullptr || !IsNuisance(*info, calibration.bounds(i).name())) genes.push_back(i);
  for (const auto& p : r->parameters())
    if (std::none_of(genes.begin(), genes.end(),
                     [&](int i) { return calibration.bounds(i).name() == p.name(); }))
      return absl::InvalidArgumentError(absl::StrCat(
          "objective.robust.parameters: '", p.name(), "' is not a value calibration ", id,
          " fits; sampling: fits draws every fitted value from its fits, so list none"));
  if (fits.empty())
    return absl::FailedPreconditionError(absl::StrCat(
        "objective.robust.sampling: fits needs per-recording errors (metrics error_0, "
        "error_1, ...) of at least two recordings; calibration ", id, " has none"));
  std::vector<GeneRange> scale;
  std::vector<bool> log;
  for (const auto& b : calibration.bounds()) {
    scale.push_back({b.lo(), b.hi()});
    log.push_back(b.log());
  }
  std::vector<std::vector<double>> pool;
  for (size_t k : Cover(fits, scale, log, kFitsPool)) pool.push_back(fits[k]);
  const std::vector<GeneRange> extent = Extent(pool);
  r->clear_parameters();
  r->clear_samples();
  for (int i : genes) {
    auto* p = r->add_parameters();
    p->set_name(calibration.bounds(i).name());
    p->set_lo(extent[i].lo);
    p->set_hi(extent[i].hi);
  }
  for (const auto& x : pool) {
    auto* sample = r->add_samples();
    for (int i : genes) sample->add_values(x[i]);
  }
  return absl::OkStatus();
}

absl::Status ResolveFromCalibration(storage::StudyStore& store, const SpreadFn& spread_after,
                                    v1::StudySpec* spec) {
  const std::string id = spec->objective().from_calibration();
  if (id.empty()) return absl::OkStatus();
  if (!spec->objective().from_diagnosis().empty())
    return absl::InvalidArgumentError(absl::StrCat(
        kField, ": a study starts from a calibration or from a diagnosis, not both"));
  auto rec = store.GetStudy(id);
  if (!rec.ok()) return absl::NotFoundError(absl::StrCat(kField, ": no study with id '", id, "'"));
  if (rec->state != "completed")
    return absl::FailedPreconditionError(absl::StrCat(
        kField, ": study ", id, " is ", rec->state, "; a study starts from a completed one"));
  v1::StudySpec calibration;
  if (!calibration.ParseFromString(rec->spec))
    return absl::DataLossError(absl::StrCat(kField, ": study ", id, "'s stored spec is unreadable"));
  if (auto s = store.Flush(); !s.ok()) return s;
  auto hof = store.HallOfFame(id, std::nullopt);
  if (!hof.ok() || hof->second.empty() || !hof->second[0].valid)
    return absl::FailedPreconditionError(
        absl::StrCat(kField, ": study ", id, " has no valid fit in its hall of fame"));
  const storage::HofRecord& best = hof->second[0];
  std::vector<bool> log;
  for (const auto& b : calibration.bounds()) log.push_back(b.log());
  std::vector<GeneRange> ranges = SpreadRanges(best.genes, spread_after(id, hof->first), log);
  std::vector<std::vector<double>> fits;
  if (spec->objective().has_robust()) fits = FitsOf(store, id, hof->first, best);
  ranges = Hull(ranges, Extent(fits));
  if (auto s = ApplyCalibration(id, calibration, best.genes, ranges, spec); !s.ok()) return s;
  if (spec->objective().robust().sampling() != "fits") return absl::OkStatus();
  return ApplyFits(id, calibration, fits, spec);
}

}  // namespace gaitforge::coordinator
