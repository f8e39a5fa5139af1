#include "services/core/logging.h"

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

#include <set>
#include <sstream>

namespace gaitforge::core {
namespace {

void Escape(std::string& out, const std::string& s) {
  for (char c : s) {
    switch (c) {
      case '"': out += "\\\""; break;
      case '\\': out += "\\\\"; break;
      case '\n': out += "\\n"; break;
      case '\t': out += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char buf[8];
          std::snprintf(buf, sizeof buf, "\\u%04x", c);
          out += buf;
        } else {
          out += c;
        }
    }
  }
}

// Formats the whole record as JSON (spdlog flag %*).
class JsonFlag final : public spdlog::custom_flag_formatter {
 public:
  explicit JsonFlag(std::string program) : program_(std::move(program)) {}
  void format(const spdlog::details::log_msg& msg, const std::tm& tm,
              spdlog::memory_buf_t& dest) override {
    (void)tm;
    // UTC with milliseconds, ISO 8601.
    const auto since = msg.time.time_since_epoch();
    const auto secs = std::chrono::duration_cast<std::chrono::seconds>(since);
    const int ms = static_cast<int>(
        std::chrono::duration_cast<std::chrono::milliseconds>(since - secs).count());
    const std::time_t tt = secs.count();
    std::tm utc{};
    gmtime_r(&tt, &utc);
    char base[32], time[40];
    std::strftime(base, sizeof base, "%Y-%m-%dT%H:%M:%S", &utc);
    std::snprintf(time, sizeof time, "%s.%03dZ", base, ms);
    const auto level = spdlog::level::to_string_view(msg.level);
    const std::string line = JsonLogLine(time, std::string(level.data(), level.size()), program_,
                                         std::string(msg.payload.data(), msg.payload.size()));
    dest.append(line.data(), line.data() + line.size());
  }
  std::unique_ptr<custom_flag_formatter> clone() const override {
    return std::make_unique<JsonFlag>(program_);
  }

 private:
  std::string program_;
};

}  // namespace

std::string JsonLogLine(const std::string& time, const std::string& level,
                        const std::string& program, const std::string& message) {
  static const std::set<std::string> kFields = {"study", "generation", "member",
                                                "job",   "worker",     "lease"};
  std::string out = "{\"time\":\"" + time + "\",\"level\":\"" + level + "\",\"program\":\"";
  Escape(out, program);
  out += "\",\"msg\":\"";
  Escape(out, message);
  out += "\"";
  std::istringstream words(message);
  std::string word;
  std::set<std::string> seen;
  while (words >> word) {
    const size_t eq = word.find('=');
    if (eq == std::string::npos) continue;
    const std::string key = word.substr(0, eq);
    std::string value = word.substr(eq + 1);
    while (!value.empty() && (value.back() == ',' || value.back() == ':' || value.back() == ';'))
      value.pop_back();
    if (!kFields.count(key) || !seen.insert(key).second) continue;
    out += ",\"" + key + "\":\"";
    Escape(out, value);
    out += "\"";
  }
  return out + "}";
}

absl::Status SetupLogging(const std::string& program, const std::string& level, bool json) {
  // spdlog reads an unknown name as "off": logging would stop without a word.
  const auto parsed = spdlog::level::from_str(level);
  if (parsed == spdlog::level::off && level != "off")
    return absl::InvalidArgumentError(
        "--log-level: expected trace, debug, info, warn, error or off, got '" + level + "'");
  auto logger = spdlog::stderr_color_mt(program);
  spdlog::set_default_logger(logger);
  spdlog::set_level(parsed);
  if (json) {
    auto formatter = std::make_unique<spdlog::pattern_formatter>();
    formatter->add_flag<JsonFlag>('*', program).set_pattern("%*");
    spdlog::set_formatter(std::move(formatter));
  } else {
    spdlog::set_pattern("%Y-%m-%d %H:%M:%S.%e %^%l%$ %n[%P] %v");
  }
  return absl::OkStatus();
}

}  // namespace gaitforge::core
