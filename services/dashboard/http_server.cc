#include "services/dashboard/http_server.h"

#include <civetweb.h>
#include <strings.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_split.h"

namespace gaitforge::dashboard {
namespace {

const char* Reason(int status) {
  switch (status) {
    case 200: return "OK";
    case 304: return "Not Modified";
    case 400: return "Bad Request";
    case 401: return "Unauthorized";
    case 403: return "Forbidden";
    case 404: return "Not Found";
    case 405: return "Method Not Allowed";
    case 409: return "Conflict";
    case 503: return "Service Unavailable";
    default: return "Internal Server Error";
  }
}

std::string Decode(const std::string& s) {
  std::string out(s.size() + 1, '\0');
  const int n = mg_url_decode(s.data(), static_cast<int>(s.size()), out.data(),
                              static_cast<int>(out.size()), /*is_form_url_encoded=*/1);
  out.resize(n < 0 ? 0 : n);
  return out;
}

HttpRequest ReadRequest(mg_connection* conn, std::string* authorization) {
  const mg_request_info* ri = mg_get_request_info(conn);
  HttpRequest req;
  req.method = ri->request_method ? ri->request_method : "";
  req.path = ri->local_uri ? ri->local_uri : "/";
  if (ri->query_string) {
    for (absl::string_view pair : absl::StrSplit(ri->query_string, '&', absl::SkipEmpty())) {
      const size_t eq = pair.find('=');
      req.query[Decode(std::string(pair.substr(0, eq)))] =
          eq == std::string_view::npos ? "" : Decode(std::string(pair.substr(eq + 1)));
    }
  }
  if (const char* a = mg_get_header(conn, "Authorization")) {
    *authorization = a;
    req.authorization = authorization;
  }
  if (const char* e = mg_get_header(conn, "If-None-Match")) req.if_none_match = e;
  return req;
}

void WriteResponse(mg_connection* conn, const HttpResponse& r, bool head) {
  std::string h = absl::StrCat("HTTP/1.1 ", r.status, " ", Reason(r.status), "\r\n");
  if (r.status != 304)
    absl::StrAppend(&h, "Content-Type: ", r.content_type, "\r\nContent-Length: ", r.body.size(),
                    "\r\n");
  if (!r.etag.empty()) absl::StrAppend(&h, "ETag: ", r.etag, "\r\n");
  // Always revalidated (an ETag makes that a 304), never stored by proxies: studies change.
  absl::StrAppend(&h,
                  "Cache-Control: no-cache, private\r\n"
                  "X-Content-Type-Options: nosniff\r\n"
                  "X-Frame-Options: DENY\r\n"
                  "Referrer-Policy: no-referrer\r\n"
                  "Connection: close\r\n");
  // The page's own files only; blob: for the figures it fetches with the token (<img>).
  if (!r.headers.count("Content-Security-Policy"))
    absl::StrAppend(&h,
                    "Content-Security-Policy: default-src 'self'; style-src 'self' "
                    "'unsafe-inline'; img-src 'self' data: blob:\r\n");
  for (const auto& [k, v] : r.headers) absl::StrAppend(&h, k, ": ", v, "\r\n");
  h += "\r\n";
  mg_write(conn, h.data(), h.size());
  if (!head && r.status != 304) mg_write(conn, r.body.data(), r.body.size());
}

int HandleRequest(mg_connection* conn, void* cbdata) {
  const auto* api = static_cast<const DashboardApi*>(cbdata);
  std::string authorization;
  const HttpRequest req = ReadRequest(conn, &authorization);
  HttpResponse r;
  try {
    r = api->Handle(req);
  } catch (const std::exception& e) {
    r = ErrorResponse(absl::InternalError(e.what()));
  }
  WriteResponse(conn, r, req.method == "HEAD");
  return r.status;
}

}  // namespace

absl::StatusOr<std::unique_ptr<HttpServer>> HttpServer::Start(const std::string& listen,
                                                              const DashboardApi& api) {
  static std::once_flag once;
  std::call_once(once, [] { mg_init_library(0); });
  std::unique_ptr<HttpServer> s(new HttpServer(api));
  const char* options[] = {"listening_ports", listen.c_str(),
                           // Page loads and live polls of a few viewers at once.
                           "num_threads", "8",
                           "request_timeout_ms", "10000",
                           nullptr};
  mg_callbacks callbacks = {};
  mg_init_data init = {&callbacks, nullptr, options};
  char text[256] = {0};
  unsigned code = 0;
  mg_error_data error = {&code, text, sizeof text};
  s->ctx_ = mg_start2(&init, &error);
  if (s->ctx_ == nullptr)
    return absl::UnavailableError(absl::StrCat("cannot serve the dashboard on ", listen, ": ",
                                               text[0] ? text : "civetweb did not start"));
  mg_set_request_handler(s->ctx_, "/", &HandleRequest, const_cast<DashboardApi*>(&api));
  mg_server_port ports[4] = {};
  const int n = mg_get_server_ports(s->ctx_, 4, ports);
  s->port_ = n > 0 ? ports[0].port : 0;
  const std::string host = listen.substr(0, listen.rfind(':'));
  const bool any = host.empty() || host == "0.0.0.0" || host == "[::]";
  s->url_ = absl::StrCat("http://", any ? "127.0.0.1" : host, ":", s->port_, "/");
  return s;
}

HttpServer::~HttpServer() {
  if (!ctx_) return;
  // civetweb's listener notices the stop only between polls of up to 2 s; a connection to
  // it wakes it at once, so that a coordinator stops without that wait.
  std::atomic<bool> stopped{false};
  std::thread waker([&] {
    const std::string host = url_.substr(7, url_.rfind(':') - 7);
    while (!stopped.load()) {
      char err[128];
      if (mg_connection* c = mg_connect_client(host.c_str(), port_, 0, err, sizeof err))
        mg_close_connection(c);
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
    }
  });
  mg_stop(ctx_);
  stopped = true;
  waker.join();
}

}  // namespace gaitforge::dashboard
