#pragma once
// Pieces of robot descriptors that tests write as text (docs/robots.md).

namespace gaitforge::testing {

// The `simulation:` group every generic robot needs, at 1 ms with one measured cycle;
// indented to sit under `parameters:`.
inline constexpr char kSimulationParameters[] = R"(  simulation:
    timestep_s: {value: 0.001, range: [1.0e-4, 0.002], unit: s}
    gravity_m_per_s2: {value: 9.81, range: [0, 100], unit: m/s^2}
    settle_cycles: {value: 0, range: [0, 5], unit: cycles, integer: true}
    measured_cycles: {value: 1, range: [1, 5], unit: cycles, integer: true}
    max_speed_m_per_s: {value: 10, range: [0.1, 100], unit: m/s}
    max_excursion_m: {value: 1, range: [0.01, 100], unit: m}
)";

}  // namespace gaitforge::testing
