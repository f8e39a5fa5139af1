#pragma once
// A gait study that starts from a calibration study (objective.from_calibration;
// docs/objectives.md, "From a calibration"): the fitted parameters become the gait
// objective's model, and with objective.robust their search spread becomes ensemble ranges,
// so gaits are evolved for the robot the recordings describe (its structure too: friction,
// contact, stiffness), over what the fit leaves open.
#include <functional>
#include <string>
#include <vector>

#include "absl/status/status.h"
#include "gaitforge/v1/study.pb.h"
#include "services/coordinator/open_ranges.h"
#include "storage/study_store.h"

namespace gaitforge::coordinator {

// The final search distribution's sd per gene of study `id` after generation `g` (empty
// when its engine keeps none).
using SpreadFn = std::function<std::vector<double>(const std::string& id, int g)>;

// best +- 2 spread per gene (a gene with a non-finite spread gets none). A gene searched by
// its logarithm (log[i]; engines::LogGenesEngine reports its spread as x sinh(s)) gets
// [x e^-2s, x e^2s]: two log-space sd on each side, never below zero.
std::vector<GeneRange> SpreadRanges(const std::vector<double>& best,
                                    const std::vector<double>& spread,
                                    const std::vector<bool>& log = {});

// Fills spec->objective from calibration study `id` (its stored spec, the best genes of its
// hall of fame and the ranges around them): the gait objective of the calibrated robot
// (a built-in robot's own calibration objective -> its descriptor's distance objective,
// robot.calibration -> robot.distance with its robot; a spec naming another is an error), option set = the calibration's own set, the
// fitted values (not the nuisances), then the spec's own items (which win); the
// calibration's timestep_ms unless the spec sets one; with robust, one parameter per fitted
// value over its range inside the calibration's bounds, unless the spec lists it.
absl::Status ApplyCalibration(const std::string& id, const v1::StudySpec& calibration,
                              const std::vector<double>& best,
                              const std::vector<GeneRange>& ranges, v1::StudySpec* spec);

// The most fits sampling: fits keeps as joint samples (Cover's first ones).
constexpr size_t kFitsPool = 64;

// For objective.robust.sampling "fits", after ApplyCalibration: the ensemble's parameters
// become every fitted value (not the nuisances), each over the extent of the pool, and its
// samples the pool: up to kFitsPool of `fits` (the calibration's genes of every evaluation
// that fits its recordings as well as its best, best first) spread over the set they fill
// (Cover). Replaces what the spec's robust lists (a resolved spec submitted again) but
// refuses a parameter that is not a fitted value; FailedPrecondition without fits.
absl::Status ApplyFits(const std::string& id, const v1::StudySpec& calibration,
                       const std::vector<std::vector<double>>& fits, v1::StudySpec* spec);

// ApplyCalibration for objective.from_calibration (no-op when unset). With robust, each
// gene's range is the hull of best +- 2 sd of the final search spread and of what the
// recordings leave open: the values of every evaluation the calibration made whose
// per-recording errors are indistinguishable from its best's (FitsLeftOpen); with sampling
// "fits", ApplyFits. NotFound for an
// unknown study; FailedPrecondition for one not completed, not a calibration, or without a
// valid best; InvalidArgument when from_diagnosis is set too.
absl::Status ResolveFromCalibration(storage::StudyStore& store, const SpreadFn& spread_after,
                                    v1::StudySpec* spec);

}  // namespace gaitforge::coordinator
