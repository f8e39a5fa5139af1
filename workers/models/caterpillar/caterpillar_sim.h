#pragma once
// Steps the caterpillar: per step, actuator forces (ON push plus return spring), stroke
// stops, ground and lump-lump contacts, the candidate effects of params.effects (tether,
// drag, slope, anisotropic friction, actuator lag, delay and deadband, softening springs,
// deformable half-lumps; all OFF at zero), one dWorldStep, then a divergence check.
#include <cstdint>
#include <deque>
#include <memory>

#include "workers/models/caterpillar/caterpillar_body.h"
#include "workers/sim/sim_outcome.h"
#include "workers/sim/world.h"

namespace gaitforge::caterpillar {

class CaterpillarSim {
 public:
  // timestep_s <= 0 means params.simulation.timestep_s.
  CaterpillarSim(const CaterpillarParams& params, const BuildOptions& options = {},
                 double timestep_s = 0);

  // Advances one timestep with the actuators in `on_mask` (bit j: actuator j of T1 T2 T3 B1
  // B2 B3) ON. Forces added to lump bodies before the call act during this step. Returns
  // !ok once the state has diverged (NaN, absurd speed or excursion, stroke overrun, ODE
  // error); do not step again after that.
  sim::SimOutcome Step(uint32_t on_mask);

  double time() const { return steps_ * h_; }
  int64_t steps() const { return steps_; }
  double timestep() const { return h_; }
  const CaterpillarBody& body() const { return *body_; }
  sim::World& world() { return world_; }

  // Measured during the last Step.
  int ground_contacts() const { return ground_contacts_; }
  // Work (J) of the ON actuator forces during the last step: F times the length change
  // (with actuator lag or delay: the push actually applied, which may act while OFF).
  double last_actuator_work() const { return last_work_; }
  // Actuator lengths (m) after the last step, in actuators() order.
  const std::vector<double>& actuator_lengths() const { return lengths_; }

 private:
  void ApplyActuators(uint32_t on_mask);
  // Fraction (0..1) of actuator `index`'s push commanded during this step after the
  // transport delay; the current mask must already be in mask_history_.
  double DelayedCommand(int index) const;
  void AddActuatorDeadband(const ActuatorGeometry& act, const Vec3& r, const Vec3& f,
                           double ux, double uy, double uz);
  void ApplyEffects();
  void AddGroundContacts();
  void AddLumpContacts();
  sim::SimOutcome CheckState();
  void MeasureLengths();

  const CaterpillarParams params_;
  const double h_;
  sim::World world_;
  std::unique_ptr<CaterpillarBody> body_;
  int64_t steps_ = 0;
  int ground_contacts_ = 0;
  double last_work_ = 0;
  std::vector<double> lengths_;
  std::vector<Vec3> start_;       // lump centres at the start
  std::vector<Vec3> body_start_;  // every body's centre at the start

  // Effects state (params.effects).
  bool shaped_push_ = false;              // actuator lag or delay is on
  double lag_keep_ = 0;                   // exp(-h / tau): share of the old push kept
  int delay_steps_ = 0;                   // whole steps of the delay ...
  double delay_frac_ = 0;                 // ... and the fraction of one more
  std::deque<uint32_t> mask_history_;     // commanded masks, newest last
  std::vector<double> push_;              // applied ON push per actuator (N)
  std::vector<dJointID> axial_joints_;    // per link, for spring softening
  std::vector<double> axial_erp_;         // their linear-spring ERP
};

}  // namespace gaitforge::caterpillar
