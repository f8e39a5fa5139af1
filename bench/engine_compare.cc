// The legged robots on two engines (issues 27, 28): each robot's descriptor built by the ODE
// builder (what studies run) and by MuJoCo 2.2.2 (workers/models/mujoco/), in one run. Per
// robot and engine: the travel of three gaits (the robot's own gait metric: the walker's
// 5 s from rest, the Tigrillo's and the Go2's measured cycles) at a reference step 10x finer than
// the robot's own, then at coarser steps; the largest step whose travel stays within 5% of that
// reference (max over the gaits of |travel - reference|, over the mean |reference|, so a
// gait that barely moves does not divide by zero), and the simulated seconds per CPU
// second at that step and at the robot's own. Prints a table, and --json FILE writes it.
//
//   build/bin/gaitforge-bench-engines [--json FILE]
#include <time.h>

#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "robots/registry.h"
#include "workers/models/generic/generic_gait.h"
#include "workers/models/mujoco/mujoco_world.h"
#include "workers/sim/ode_runtime.h"

namespace {

using namespace gaitforge;

double CpuSeconds() {
  timespec ts;
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + 1e-9 * ts.tv_nsec;
}

struct Robot {
  std::string name;
  std::vector<std::vector<double>> gaits;  // the diagnosis cases' gait set 1
};

const std::vector<Robot> kRobots = {
    {"walker", {{2.2, 0.52, 0.35, 0.1}, {1.2, 0.35, 0.0, 0.05}, {1.7, 0.45, 0.2, 0.15}}},
    {"tigrillo",
     {{1.0, 0.35, 0.35, 0.1, 0.1, 0.5, 0.25, 5},
      {1.5, 0.3, 0.3, 0, 0, 0, 0.5, 5},
      {0.8, 0.4, 0.3, 0, 0.15, 0.5, 0.5, 5}}},
    // Paper 002's trot at 0.22 and 0.34 m/s and its slide at 0.16 m/s (robots/go2_castors).
    {"go2_castors",
     {{0.6, 0.5, 0.08, 0.22, 0.30, 1, 0.5, 0.5},
      {0.8, 0.6, 0.03, 0.16, 0.1, 0.3, 0, 0.5},
      {0.6, 0.5, 0.08, 0.34, 0.30, 1, 0.5, 0.5}}},
};
const std::vector<double> kSteps = {0.25, 0.5, 1, 1.5, 2, 3, 4};  // x the robot's own step

struct Point {
  double h = 0, deviation = NAN, sim_per_cpu = NAN;
  std::vector<double> travel;
  std::string invalid;  // the first invalid run's reason
};

Point Measure(const robots::RobotDescriptor& d, const Robot& r, const generic::WorldBuilder& engine,
              double h) {
  Point p;
  p.h = h;
  generic::ParamValues v(d);
  generic::GaitOptions o;
  o.engine = engine;
  o.timestep_s = h;
  o.duration_s = d.FindParameter("simulation.duration_s") ? v("simulation.duration_s") : 0;
  double simulated = 0;
  const double t0 = CpuSeconds();
  for (const auto& g : r.gaits) {
    const generic::GaitResult e = generic::EvaluateGait(d, v, g, o);
    if (!e.valid && p.invalid.empty()) p.invalid = e.reason;
    p.travel.push_back(e.valid ? e.travel_m : NAN);
    simulated += e.simulated_s;
  }
  p.sim_per_cpu = simulated / (CpuSeconds() - t0);
  return p;
}

double Deviation(const Point& p, const Point& ref) {
  double worst = 0, scale = 0;
  for (size_t i = 0; i < ref.travel.size(); ++i) {
    const double off = std::fabs(p.travel[i] - ref.travel[i]);
    if (!std::isfinite(off)) return INFINITY;  // an invalid run at either step
    worst = std::max(worst, off);
    scale += std::fabs(ref.travel[i]) / ref.travel.size();
  }
  return worst / scale;
}

std::string Row(const std::string& robot, const std::string& engine, const Point& p, bool ref) {
  std::string travel;
  for (double t : p.travel) travel += (travel.empty() ? "" : ", ") + std::to_string(t);
  char buf[512];
  snprintf(buf, sizeof buf,
           "{\"robot\": \"%s\", \"engine\": \"%s\", \"h_s\": %.6g, \"reference\": %s, "
           "\"travel_m\": [%s], \"deviation\": %.6g, \"sim_s_per_cpu_s\": %.6g%s}",
           robot.c_str(), engine.c_str(), p.h, ref ? "true" : "false", travel.c_str(),
           std::isfinite(p.deviation) ? p.deviation : -1.0, p.sim_per_cpu,
           p.invalid.empty() ? "" : (", \"invalid\": \"" + p.invalid + "\"").c_str());
  return buf;
}

}  // namespace

int main(int argc, char** argv) {
  std::string json_path;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--json" && i + 1 < argc) {
      json_path = argv[++i];
    } else {
      std::printf("usage: gaitforge-bench-engines [--json FILE]\n");
      return a == "-h" || a == "--help" ? 0 : 2;
    }
  }
  sim::InitProcess();
  sim::InitThread();
  std::vector<std::string> rows;
  std::printf("%-11s %-7s %8s %26s %9s %10s\n", "robot", "engine", "h (ms)", "travel (mm) per gait",
              "dev", "sim s/cpu s");
  for (const Robot& r : kRobots) {
    const robots::RobotDescriptor& d = robots::Robot(r.name);
    const double own = d.Value("simulation.timestep_s");
    for (const std::string engine : {"ode", "mujoco"}) {
      const generic::WorldBuilder build = engine == "mujoco" ? mujoco::Engine() : nullptr;
      const Point ref = Measure(d, r, build, own / 10);
      rows.push_back(Row(r.name, engine, ref, true));
      std::printf("%-11s %-7s %8.3f %8.1f %8.1f %8.1f %9s %10.1f  (reference)\n", r.name.c_str(),
                  engine.c_str(), 1e3 * ref.h, 1e3 * ref.travel[0], 1e3 * ref.travel[1],
                  1e3 * ref.travel[2], "-", ref.sim_per_cpu);
      double largest = 0, speed = NAN;
      for (double k : kSteps) {
        Point p = Measure(d, r, build, k * own);
        p.deviation = Deviation(p, ref);
        rows.push_back(Row(r.name, engine, p, false));
        std::printf("%-11s %-7s %8.3f %8.1f %8.1f %8.1f %8.1f%% %10.1f%s\n", r.name.c_str(),
                    engine.c_str(), 1e3 * p.h, 1e3 * p.travel[0], 1e3 * p.travel[1],
                    1e3 * p.travel[2], 100 * p.deviation, p.sim_per_cpu,
                    p.invalid.empty() ? "" : ("  invalid: " + p.invalid).c_str());
        if (p.deviation <= 0.05 && p.h > largest) largest = p.h, speed = p.sim_per_cpu;
      }
      std::printf("%-11s %-7s largest step within 5%%: %s ms, %.1f sim s per CPU s\n\n",
                  r.name.c_str(), engine.c_str(),
                  largest > 0 ? std::to_string(1e3 * largest).c_str() : "none", speed);
    }
  }
  if (!json_path.empty()) {
    std::ofstream out(json_path);
    out << "{\"rows\": [\n";
    for (size_t i = 0; i < rows.size(); ++i) out << "  " << rows[i] << (i + 1 < rows.size() ? ",\n" : "\n");
    out << "]}\n";
  }
  return 0;
}
