// Paper 004's resolution trade-off (issue 29): the continuum arm as N lumps (counts.lumps),
// its error against a fine reference and its cost, per N. The paper chose N = 5 because its
// model then ran one step fast enough for control above 50 Hz (MATLAB 2020a, Ryzen 5 2600),
// while finer models ran below 5 Hz; that is the anchor printed beside the figures.
//
// For each N, the arm (the descriptor's Table 2 P, which scales with N / 5) is driven from
// rest by two playbacks of rod forces: the paper's Table 2 step held for 1 s, and the three
// rods swinging at 1.3 Hz for 3 s. Against the reference (N = 40 at 0.25 ms) it reports the
// tip's RMS position error (mm) and paper 004's acceleration error 1 - F (Savitzky-Golay,
// 100 Hz), and its cost: simulated seconds per CPU second and the rate at which it can run
// one 20 ms control step (Hz), each the fastest of 3 runs.
//   build/bin/gaitforge-bench-arm-resolution [--json]
#include <time.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "robots/count_override.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"
#include "workers/models/generic/generic_playback.h"
#include "workers/models/generic/generic_world.h"
#include "workers/objectives/acceleration_error.h"
#include "workers/sim/ode_runtime.h"

namespace {

using gaitforge::calibration::SimRun;

double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

gaitforge::robots::RobotDescriptor Arm(int lumps) {
  const std::string source = "continuum_arm (N = " + std::to_string(lumps) + ")";
  auto text = gaitforge::robots::WithCount(gaitforge::robots::BuiltinText("continuum_arm"), "lumps",
                                           lumps, source);
  auto d = text.ok() ? gaitforge::robots::ParseDescriptor(*text, source)
                     : absl::StatusOr<gaitforge::robots::RobotDescriptor>(text.status());
  if (!d.ok()) {
    std::fprintf(stderr, "%s\n", std::string(d.status().message()).c_str());
    std::exit(1);
  }
  return *d;
}

// Rod forces at 1 kHz: Table 2's step, or the rods swinging at 1.3 Hz, 120 degrees apart.
gaitforge::recording::Recording Inputs(bool swing) {
  gaitforge::recording::Recording r;
  r.meta.robot = "continuum_arm";
  r.meta.command_kind = "playback";
  r.channels = {"rod1.force", "rod2.force", "rod3.force"};
  r.columns.resize(3);
  r.dt = 1e-3;
  const double step[3] = {0.3025, 0.3263, -0.1265};
  for (int k = 0; k <= (swing ? 3000 : 1000); ++k) {
    r.t.push_back(k * 1e-3);
    for (int i = 0; i < 3; ++i)
      r.columns[i].push_back(swing ? 0.3 * std::sin(2 * M_PI * 1.3 * k * 1e-3 + 2.1 * i) : step[i]);
  }
  return r;
}

struct Tip {
  std::vector<std::vector<double>> xyz;  // tip.x, .y, .z at 100 Hz
  double cpu_s = 0, simulated_s = 0;
};

// The fastest of `repeats` runs counts (the others only add the machine's noise).
Tip Run(int lumps, double h, const gaitforge::recording::Recording& in, int repeats = 3) {
  const auto d = Arm(lumps);
  gaitforge::generic::ParamValues v(d);
  SimRun run;
  Tip tip;
  for (int r = 0; r < repeats; ++r) {
    const double t0 = CpuSeconds();
    run = gaitforge::generic::SimulatePlayback(d, v, in, 0, in.t.back(), 100, h);
    const double cpu = CpuSeconds() - t0;
    tip.cpu_s = r == 0 ? cpu : std::min(tip.cpu_s, cpu);
  }
  tip.simulated_s = run.simulated_s;
  if (!run.valid) {
    std::fprintf(stderr, "N = %d diverged: %s\n", lumps, run.reason.c_str());
    std::exit(1);
  }
  for (const char* c : {"tip.x", "tip.y", "tip.z"}) tip.xyz.push_back(run.trajectory.columns[run.trajectory.Index(c)]);
  return tip;
}

// RMS distance (mm) and paper 004's 1 - F between the tips.
std::pair<double, double> Errors(const Tip& a, const Tip& ref) {
  const size_t n = std::min(a.xyz[0].size(), ref.xyz[0].size());
  double sum = 0;
  for (size_t i = 0; i < n; ++i)
    for (int k = 0; k < 3; ++k) sum += std::pow(a.xyz[k][i] - ref.xyz[k][i], 2);
  std::vector<gaitforge::calibration::Vectors> acc_a(1), acc_r(1);
  for (int k = 0; k < 3; ++k) {
    acc_a[0].push_back(gaitforge::calibration::SavitzkyGolaySecondDerivative(
        std::vector<double>(a.xyz[k].begin(), a.xyz[k].begin() + n), 0.01));
    acc_r[0].push_back(gaitforge::calibration::SavitzkyGolaySecondDerivative(
        std::vector<double>(ref.xyz[k].begin(), ref.xyz[k].begin() + n), 0.01));
  }
  const double rel = gaitforge::calibration::RelativeAccelerationError(
      gaitforge::calibration::Metric::kMae, acc_r, acc_a, 0, static_cast<int64_t>(n));
  return {1000 * std::sqrt(sum / n), rel};
}

}  // namespace

int main(int argc, char** argv) {
  const bool json = argc > 1 && std::strcmp(argv[1], "--json") == 0;
  gaitforge::sim::InitProcess();
  gaitforge::sim::InitThread();
  const std::vector<int> ns = {2, 3, 4, 5, 6, 8, 10, 15, 20, 30};
  const gaitforge::recording::Recording step = Inputs(false), swing = Inputs(true);
  const Tip ref_step = Run(40, 2.5e-4, step, 1), ref_swing = Run(40, 2.5e-4, swing, 1);
  if (!json) {
    std::printf("continuum arm, N lumps at h = 1 ms against N = 40 at 0.25 ms (paper 004: N = 5 ran\n"
                "one model step above 50 Hz in MATLAB, finer models below 5 Hz)\n\n");
    std::printf("%4s  %14s %10s  %14s %10s  %14s %12s\n", "N", "step tip (mm)", "step 1-F",
                "swing tip (mm)", "swing 1-F", "sim s / CPU s", "20 ms steps/s");
  } else {
    std::printf("{\"reference\": {\"lumps\": 40, \"timestep_s\": 0.00025}, \"anchor_control_hz_at_5\": 50, \"rows\": [");
  }
  for (size_t i = 0; i < ns.size(); ++i) {
    const Tip a = Run(ns[i], 1e-3, step), b = Run(ns[i], 1e-3, swing);
    const auto [step_mm, step_f] = Errors(a, ref_step);
    const auto [swing_mm, swing_f] = Errors(b, ref_swing);
    const double speed = (a.simulated_s + b.simulated_s) / (a.cpu_s + b.cpu_s);
    const double control_hz = speed / 0.02;
    if (json) {
      std::printf("%s\n {\"lumps\": %d, \"step_tip_rms_mm\": %.4g, \"step_accel_error\": %.4g, "
                  "\"swing_tip_rms_mm\": %.4g, \"swing_accel_error\": %.4g, "
                  "\"sim_s_per_cpu_s\": %.4g, \"control_steps_per_s\": %.4g}",
                  i ? "," : "", ns[i], step_mm, step_f, swing_mm, swing_f, speed, control_hz);
    } else {
      std::printf("%4d  %14.3f %10.4f  %14.3f %10.4f  %14.1f %12.0f\n", ns[i], step_mm, step_f,
                  swing_mm, swing_f, speed, control_hz);
    }
  }
  if (json) std::printf("]}\n");
  return 0;
}
