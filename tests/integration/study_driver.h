#pragma once
// Plays the part of workers against an in-process Coordinator (no network): leases,
// evaluates with the real objectives and reports, in configurable batch sizes and orders.
#include <string>
#include <vector>

#include "services/coordinator/coordinator.h"
#include "workers/objectives/objective.h"

namespace gaitforge::testing {

struct DriveOptions {
  int batch = 16;
  bool reverse = false;     // report each batch in reverse member order
  int max_reports = -1;     // stop after this many Report calls (-1: until no work)
  std::string worker_id = "driver";
};

// Returns the number of Report calls made.
int Drive(coordinator::Coordinator& c, const DriveOptions& o);

// Every stored number of a study, for bit-exact comparison of two runs.
struct StudyDump {
  std::vector<std::vector<double>> genes;
  std::vector<double> fitness;
  std::vector<std::vector<double>> hof_genes;
  std::vector<double> hof_fitness;
  int generations = 0;
  bool operator==(const StudyDump&) const = default;
};
StudyDump Dump(coordinator::Coordinator& c, const std::string& id);

v1::StudySpec SmallSpec(uint64_t seed, int population = 30, int generations = 6);

}  // namespace gaitforge::testing
