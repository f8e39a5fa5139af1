#include "services/core/build_info.h"

namespace gaitforge::core {

std::string BuildId() { return GAITFORGE_BUILD_ID; }

}  // namespace gaitforge::core
