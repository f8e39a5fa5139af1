#pragma once
// An ODE world with its own collision space, contact joint group and threading
// implementation. Sharing ODE's default threading object between worlds stepped in
// different threads crashes (../shared/guides/ode-notes.md, "Threads"), so each World owns
// one; it is freed after dWorldDestroy. One World per evaluation; never shared by threads.
#include <ode/ode.h>

namespace gaitforge::sim {

class World {
 public:
  // Calls InitThread() for the calling thread. Gravity is zero until set.
  World();
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  dWorldID world() const { return world_; }
  dSpaceID space() const { return space_; }
  // Joints here live for one step: Step() empties the group after stepping.
  dJointGroupID contacts() const { return contacts_; }

  // dWorldStep (deterministic; QuickStep is not, see ode-notes.md), then empties contacts().
  // Throws OdeError when ODE reports an error or a message during the step; do not step
  // again after that.
  void Step(double h);

 private:
  dWorldID world_ = nullptr;
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  dThreadingImplementationID threading_ = nullptr;
  // Set when an OdeError unwound through dWorldStep. ODE then still lists the interrupted
  // job and asserts (aborting the process) if its threading object is freed, so that
  // object, a few hundred bytes, is deliberately leaked on this rare path.
  bool interrupted_ = false;
};

}  // namespace gaitforge::sim
