#pragma once
// What the dashboard's unit tests share: the tokens they configure, a GET through
// DashboardApi::Handle as the HTTP server makes it, and a substring check.
#include <map>
#include <string>

#include "services/dashboard/dashboard_api.h"

namespace gaitforge::testing {

inline constexpr char kClient[] = "client-token-0123456789";
inline constexpr char kWorker[] = "worker-token-0123456789";
inline constexpr char kAdmin[] = "admin-token-01234567890";

inline dashboard::HttpResponse GetFrom(const dashboard::DashboardApi& api, const std::string& path,
                                       const std::string& token = "",
                                       std::map<std::string, std::string> query = {},
                                       const std::string& if_none_match = "") {
  dashboard::HttpRequest r;
  r.method = "GET";
  r.path = path;
  r.query = std::move(query);
  r.if_none_match = if_none_match;
  const std::string header = "Bearer " + token;
  if (!token.empty()) r.authorization = &header;
  return api.Handle(r);
}

inline bool Has(const std::string& body, const std::string& part) {
  return body.find(part) != std::string::npos;
}

}  // namespace gaitforge::testing
