#pragma once
// Travelling-wave genotypes of a phase_onoff controller whose actuators form two rows of
// pairs (a top row, then a bottom row, rear to front: the caterpillar's T1 T2 T3 B1 B2 B3):
// paper 000's "intuitive sine wave pattern" baseline (Fig. 14; the paper leaves its form
// open). Pairs fire a 1/(2 pairs) of a period apart.
#include <string>
#include <vector>

namespace gaitforge::robots {

struct WaveShape {
  bool front_first = false;  // the wave runs from the head to the tail, else forward
  bool interleaved = false;  // top and bottom of each pair in turn; else the top row, then
                             // the bottom row half a period later
  double duty = 0.5;         // ON fraction of the period, each actuator
  std::string Name() const;  // e.g. "tail-first rows 50%"
};

// The eight waves: both directions, rows or interleaved, duty 1/2 or 1/3.
const std::vector<WaveShape>& WaveFamily();
// The genotype [a_1..a_n, d_1..d_n, T] of a wave over `actuators` (even: two rows).
std::vector<double> WaveGenes(int actuators, double period_s, const WaveShape& shape);

}  // namespace gaitforge::robots
