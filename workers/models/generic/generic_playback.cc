// A recording's input columns driving a generic robot (generic_playback.h).
#include "workers/models/generic/generic_playback.h"

#include <algorithm>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_join.h"
#include "workers/models/generic/generic_run.h"
#include "workers/objectives/calibration_error.h"

namespace gaitforge::generic {

calibration::SimRun SimulatePlayback(const robots::RobotDescriptor& d, const ParamValues& v,
                                     const recording::Recording& rec, double offset_s,
                                     double duration_s, double rate_hz, double timestep_s,
                                     const WorldBuilder& engine) {
  calibration::SimRun run;
  std::vector<int> columns;
  for (const robots::Actuator& a : d.actuators) {
    columns.push_back(rec.ChannelIndex(a.InputChannel()));
    if (columns.back() < 0) {
      run.reason = absl::StrCat("the recording has no column ", a.InputChannel(), " to drive ",
                                a.name, " (a playback needs ",
                                absl::StrJoin(d.InputChannels(), ", "), ")");
      return run;
    }
  }
  calibration::Trajectory& tr = run.trajectory;
  tr.channels = d.Channels();
  tr.columns.resize(tr.channels.size());
  int64_t every = 1;
  const auto steps = [&](const RobotWorld& w) {
    every = std::max<int64_t>(1, std::llround(1.0 / (rate_hz * w.timestep())));
    return static_cast<int64_t>(std::ceil(duration_s / w.timestep() - 1e-9));
  };
  const auto sample = [&](const RobotWorld& w, int64_t i) {
    if (i % every != 0) return;
    tr.t.push_back(w.time());
    for (size_t c = 0; c < tr.channels.size(); ++c) tr.columns[c].push_back(*w.Channel(tr.channels[c]));
  };
  const double delay = v.Effect("effect.actuator_delay_s");
  const auto source = [&](const RobotWorld& w) -> Source {
    const double h = w.timestep();
    return [&, h](int64_t i, std::vector<double>& out) {
      const double t = static_cast<double>(i) * h - delay - offset_s;
      out.resize(columns.size());
      for (size_t k = 0; k < columns.size(); ++k)
        out[k] = calibration::Interpolate(rec.t, rec.columns[columns[k]], t);
    };
  };
  run.valid = RunWorld(d, v, timestep_s, engine, steps, sample, source, &run.reason, &run.simulated_s);
  return run;
}

}  // namespace gaitforge::generic
