#pragma once
// The dashboard's static files (services/dashboard/web/), embedded into the binary at build
// time by embed_web.cmake: no network, no npm, no files to install beside the binary.
#include <cstddef>
#include <string_view>
#include <vector>

namespace gaitforge::dashboard {

struct WebAsset {
  const char* path;          // "/index.html", "/vendor/uPlot.iife.min.js"
  const char* content_type;  // "text/javascript; charset=utf-8"
  const char* etag;          // quoted, from the content's SHA-256
  const unsigned char* data;
  size_t size;
  std::string_view bytes() const { return {reinterpret_cast<const char*>(data), size}; }
};

const std::vector<WebAsset>& WebAssets();
// nullptr when there is no such file; "/" is "/index.html".
const WebAsset* FindWebAsset(std::string_view path);

}  // namespace gaitforge::dashboard
