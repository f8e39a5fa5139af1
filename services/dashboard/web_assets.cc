#include "services/dashboard/web_assets.h"

namespace gaitforge::dashboard {

const WebAsset* FindWebAsset(std::string_view path) {
  if (path == "/") path = "/index.html";
  for (const auto& a : WebAssets())
    if (path == a.path) return &a;
  return nullptr;
}

}  // namespace gaitforge::dashboard
