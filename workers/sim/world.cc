#include "workers/sim/world.h"

#include "workers/sim/ode_runtime.h"

namespace gaitforge::sim {

World::World() {
  InitThread();
  world_ = dWorldCreate();
  space_ = dSimpleSpaceCreate(nullptr);
  contacts_ = dJointGroupCreate(0);
  threading_ = dThreadingAllocateSelfThreadedImplementation();
  dWorldSetStepThreadingImplementation(
      world_, dThreadingImplementationGetFunctions(threading_), threading_);
  dWorldSetGravity(world_, 0, 0, 0);
  // No auto-disable: a resting lump must keep reacting to its actuators.
  dWorldSetAutoDisableFlag(world_, 0);
}

World::~World() {
  dJointGroupDestroy(contacts_);
  dSpaceDestroy(space_);
  dWorldDestroy(world_);
  if (!interrupted_) dThreadingFreeImplementation(threading_);
}

void World::Step(double h) {
  TakeOdeMessage();  // drop what earlier, unrelated calls reported
  try {
    dWorldStep(world_, h);
  } catch (const OdeError&) {
    interrupted_ = true;
    throw;
  }
  dJointGroupEmpty(contacts_);
  const std::string message = TakeOdeMessage();
  if (!message.empty()) throw OdeError(message);
}

}  // namespace gaitforge::sim
