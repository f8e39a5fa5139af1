#include "workers/sim/ode_runtime.h"

#include <ode/ode.h>

#include <cstdarg>
#include <cstdio>
#include <mutex>

namespace gaitforge::sim {
namespace {

[[noreturn]] void Throw(const char* kind, int errnum, const char* msg, va_list ap) {
  char text[512];
  std::vsnprintf(text, sizeof(text), msg, ap);
  throw OdeError(std::string("ODE ") + kind + " " + std::to_string(errnum) + ": " + text);
}

void OnError(int errnum, const char* msg, va_list ap) { Throw("error", errnum, msg, ap); }
void OnDebug(int errnum, const char* msg, va_list ap) { Throw("debug", errnum, msg, ap); }
thread_local std::string pending_message;

void OnMessage(int errnum, const char* msg, va_list ap) {
  if (!pending_message.empty()) return;
  char text[512];
  std::vsnprintf(text, sizeof(text), msg, ap);
  pending_message = "ODE message " + std::to_string(errnum) + ": " + text;
}

}  // namespace

void InitProcess() {
  static std::once_flag once;
  std::call_once(once, [] {
    dSetErrorHandler(&OnError);
    dSetDebugHandler(&OnDebug);
    dSetMessageHandler(&OnMessage);
    if (!dInitODE2(0)) throw OdeError("dInitODE2 failed");
  });
}

std::string TakeOdeMessage() {
  std::string m;
  m.swap(pending_message);
  return m;
}

void InitThread() {
  thread_local bool allocated = false;
  if (allocated) return;
  InitProcess();
  if (!dAllocateODEDataForThread(dAllocateMaskAll)) {
    throw OdeError("dAllocateODEDataForThread failed");
  }
  allocated = true;
}

}  // namespace gaitforge::sim
