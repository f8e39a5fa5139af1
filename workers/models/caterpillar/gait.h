#pragma once
// The open-loop gait of the paper (section 5): genotype
// G = [a_T1 a_T2 a_T3 a_B1 a_B2 a_B3 d_T1 d_T2 d_T3 d_B1 d_B2 d_B3 T].
// Actuator j is ON while the phase (t mod T)/T lies in [a_j, d_j), wrapping round when
// d_j < a_j; never ON when a_j == d_j.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "robots/onoff_waves.h"

namespace gaitforge::caterpillar {

// Actuator order everywhere: T1 T2 T3 B1 B2 B3 (bit j of an on-mask is actuator j).
inline constexpr int kActuators = 6;
inline constexpr int kGenes = 13;

class Gait {
 public:
  // Phases are reduced modulo 1 (so 1.0 means 0.0); T must lie in [kMinPeriodS, kMaxPeriodS]
  // (wider than the paper's [0.2, 2.0] so that studies may explore beyond it).
  static absl::StatusOr<Gait> FromGenes(const std::vector<double>& genes);
  static constexpr double kMinPeriodS = 0.05;
  static constexpr double kMaxPeriodS = 10.0;

  // Bit j set when actuator j is ON at time t >= 0 (s).
  uint32_t OnMask(double t) const;
  double period_s() const { return period_s_; }

 private:
  std::array<double, kActuators> on_{}, off_{};
  double period_s_ = 1;
};

// Paper 000's travelling waves (robots/onoff_waves.h) over the six actuators.
using robots::WaveFamily;
using robots::WaveShape;
inline std::vector<double> WaveGenes(double period_s, const WaveShape& shape) {
  return robots::WaveGenes(kActuators, period_s, shape);
}
// The tail-first, row-by-row, half-duty wave (WaveFamily()[0]): a plain test gait.
inline std::vector<double> TravellingWaveGenes(double period_s) { return WaveGenes(period_s, {}); }

}  // namespace gaitforge::caterpillar
