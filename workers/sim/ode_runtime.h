#pragma once
// Process- and thread-level set-up of ODE 0.16 (../shared/guides/ode-notes.md).
// Debian's libode keeps internal assertions on: without these handlers a diverging model
// prints "LCP internal error" and abort()s the whole worker.
#include <stdexcept>
#include <string>

namespace gaitforge::sim {

// What ODE reported through its error, debug or message handler. Thrown out of the ODE call
// that failed; the world it was stepping must be destroyed, not stepped again.
class OdeError : public std::runtime_error {
 public:
  explicit OdeError(const std::string& what) : std::runtime_error(what) {}
};

// dInitODE2(0) and ODE's handlers. Errors and debug assertions (after which ODE would
// abort()) throw OdeError carrying ODE's message out of the failing ODE call. Messages are
// warnings after which ODE carries on (e.g. "LCP internal error, s <= 0"): they are kept
// per thread for TakeOdeMessage(), not thrown, since unwinding through a step leaves ODE's
// threading object unusable. Idempotent and thread-safe; call it before any thread uses ODE
// (the worker calls it in main()).
void InitProcess();

// The first ODE message reported on this thread since the last call ("" when none), and
// forgets it.
std::string TakeOdeMessage();

// dAllocateODEDataForThread(dAllocateMaskAll) for the calling thread, once per thread
// (later calls are free). Calls InitProcess() first. Every thread that builds or steps a
// World needs it; World's constructor calls it, so callers normally need not.
void InitThread();

}  // namespace gaitforge::sim
