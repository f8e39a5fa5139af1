// `gaitforge robots [NAME | FILE]`: the built-in robots, or one robot's descriptor (a
// built-in's name, or a descriptor file to check) with what it offers: its parameters with
// units and ranges, which a calibration may set, its scales, relations, genes and channels.
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "absl/strings/str_join.h"
#include "clients/cli/cli.h"
#include "robots/descriptor_parser.h"
#include "robots/registry.h"

namespace gaitforge::cli {
namespace {

// The shortest decimal that reads back as the same double; "infinite" (quoted) for +inf.
std::string Num(double v) {
  if (std::isinf(v)) return "\"infinite\"";
  char buf[32];
  for (int precision = 1; precision <= 17; ++precision) {
    std::snprintf(buf, sizeof buf, "%.*g", precision, v);
    if (std::strtod(buf, nullptr) == v) break;
  }
  return buf;
}

std::string QuotedList(const std::vector<std::string>& v) {
  std::vector<std::string> q;
  for (const auto& s : v) q.push_back(JsonQuote(s));
  return "[" + absl::StrJoin(q, ", ") + "]";
}

void PrintJson(const robots::RobotDescriptor& d) {
  std::cout << "{\"name\": " << JsonQuote(d.name) << ", \"model\": " << JsonQuote(d.model)
            << ", \"paper\": " << JsonQuote(d.paper) << ", \"summary\": " << JsonQuote(d.summary)
            << ",\n \"parameters\": [";
  for (size_t i = 0; i < d.parameters.size(); ++i) {
    const auto& p = d.parameters[i];
    std::cout << (i ? ",\n  " : "\n  ") << "{\"name\": " << JsonQuote(p.name)
              << ", \"value\": " << Num(p.value) << ", \"lo\": " << Num(p.lo)
              << ", \"hi\": " << Num(p.hi) << ", \"unit\": " << JsonQuote(p.unit)
              << ", \"calibratable\": " << (p.calibratable ? "true" : "false")
              << ", \"doc\": " << JsonQuote(p.doc) << "}";
  }
  std::cout << "],\n \"counts\": [";
  for (size_t i = 0; i < d.counts.size(); ++i)
    std::cout << (i ? ", " : "") << "{\"name\": " << JsonQuote(d.counts[i].name)
              << ", \"value\": " << d.counts[i].value << ", \"lo\": " << d.counts[i].lo
              << ", \"hi\": " << d.counts[i].hi << ", \"doc\": " << JsonQuote(d.counts[i].doc) << "}";
  std::cout << "],\n \"scales\": [";
  for (size_t i = 0; i < d.scales.size(); ++i) {
    std::cout << (i ? ", " : "") << "{\"name\": " << JsonQuote(d.scales[i].name)
              << ", \"multiplies\": " << QuotedList(d.scales[i].multiplies) << "}";
  }
  std::cout << "],\n \"genes\": [";
  for (size_t i = 0; i < d.controller.genes.size(); ++i) {
    const auto& g = d.controller.genes[i];
    std::cout << (i ? ", " : "") << "{\"name\": " << JsonQuote(g.name) << ", \"lo\": " << Num(g.lo)
              << ", \"hi\": " << Num(g.hi) << "}";
  }
  std::cout << "],\n \"suspects\": [";
  for (size_t i = 0; i < d.suspects.size(); ++i)
    std::cout << (i ? ", " : "") << "{\"id\": " << JsonQuote(d.suspects[i].id)
              << ", \"name\": " << JsonQuote(d.suspects[i].name) << "}";
  std::cout << "],\n \"ruled_out\": [";
  for (size_t i = 0; i < d.ruled_out.size(); ++i)
    std::cout << (i ? ", " : "") << "{\"id\": " << JsonQuote(d.ruled_out[i].id)
              << ", \"why\": " << JsonQuote(d.ruled_out[i].why) << "}";
  std::cout << "],\n \"controller\": " << JsonQuote(d.controller.kind)
            << ",\n \"channels\": " << QuotedList(d.Channels()) << "}\n";
}

void PrintText(const robots::RobotDescriptor& d) {
  std::cout << d.name << " (model " << d.model << (d.paper.empty() ? "" : ", paper ") << d.paper
            << ", " << d.source << ")\n";
  if (!d.summary.empty()) std::cout << d.summary << "\n";
  if (!d.counts.empty()) {
    std::cout << "\nCOUNT  VALUE  RANGE  (another value is another model: edit the file)\n";
    for (const auto& c : d.counts)
      std::cout << c.name << "  " << c.value << "  [" << c.lo << ", " << c.hi << "]  " << c.doc << "\n";
  }
  std::cout << "\nPARAMETER  VALUE  RANGE  CALIBRATE\n";
  for (const auto& p : d.parameters) {
    std::cout << p.name << "  " << (std::isinf(p.value) ? "infinite" : Num(p.value)) << "  "
              << p.RangeText() << "  " << (p.calibratable ? "yes" : "-") << "\n";
  }
  std::cout << "\nSCALES\n";
  for (const auto& s : d.scales)
    std::cout << s.name << "  multiplies " << absl::StrJoin(s.multiplies, ", ") << "\n";
  std::cout << "\nRELATIONS\n";
  for (const auto& r : d.relations) std::cout << r.text << "\n";
  if (!d.suspects.empty()) std::cout << "\nSUSPECTS (the gap finder tries them beside its catalog)\n";
  for (const auto& x : d.suspects) std::cout << x.id << "  " << x.name << "\n";
  if (!d.ruled_out.empty()) std::cout << "\nRULED OUT (the gap finder never offers them)\n";
  for (const auto& r : d.ruled_out) std::cout << r.id << "  " << r.why << "\n";
  std::cout << "\nGENES (" << d.controller.kind << ")\n";
  for (const auto& g : d.controller.genes)
    std::cout << g.name << "  [" << g.lo << ", " << g.hi << "]\n";
  std::cout << "\nCHANNELS\n" << absl::StrJoin(d.Channels(), " ") << "\n";
}

int ListRobots(const GlobalOptions& g) {
  const auto names = robots::RobotNames();
  if (g.json) std::cout << "[";
  for (size_t i = 0; i < names.size(); ++i) {
    const robots::RobotDescriptor& d = robots::Robot(names[i]);
    if (g.json) {
      std::cout << (i ? ", " : "") << "{\"name\": " << JsonQuote(d.name) << ", \"model\": "
                << JsonQuote(d.model) << ", \"genes\": " << d.controller.genes.size()
                << ", \"channels\": " << d.Channels().size() << "}";
    } else {
      if (i == 0) std::cout << "ROBOT  MODEL  GENES  CHANNELS  PAPER\n";
      std::cout << d.name << "  " << d.model << "  " << d.controller.genes.size() << "  "
                << d.Channels().size() << "  " << d.paper << "\n";
    }
  }
  if (g.json) std::cout << "]\n";
  return kOk;
}

}  // namespace

int CmdRobots(const GlobalOptions& g, const std::vector<std::string>& args) {
  if (args.size() > 1) {
    std::cerr << "gaitforge: robots takes at most one robot name or descriptor file\n";
    return kUsage;
  }
  if (args.empty()) return ListRobots(g);
  const std::string& what = args[0];
  const bool is_file = what.find('/') != std::string::npos ||
                       what.find(".yaml") != std::string::npos ||
                       what.find(".json") != std::string::npos;
  robots::RobotDescriptor d;
  if (is_file) {
    auto loaded = robots::LoadDescriptor(what);
    if (!loaded.ok()) {
      std::cerr << "gaitforge: " << loaded.status().message() << "\n";
      return loaded.status().code() == absl::StatusCode::kNotFound ? kNotFound : kUsage;
    }
    d = std::move(*loaded);
  } else if (const robots::RobotDescriptor* r = robots::FindRobot(what)) {
    d = *r;
  } else {
    std::cerr << "gaitforge: no built-in robot '" << what << "' (known: "
              << absl::StrJoin(robots::RobotNames(), ", ")
              << "); give a descriptor file's path to check one\n";
    return kNotFound;
  }
  if (g.json) {
    PrintJson(d);
  } else {
    PrintText(d);
  }
  return kOk;
}

}  // namespace gaitforge::cli
