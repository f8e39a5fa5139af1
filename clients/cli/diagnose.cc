// `gaitforge diagnose SPEC`: the gap finder (docs/diagnosis.md, services/diagnosis/). Reads
// and checks the spec, uploads its recordings, and runs the diagnosis library against the
// coordinator (a private one and local workers unless --coordinator names one); prints the
// report in words, or as JSON with --json.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "clients/cli/cli.h"
#include "clients/cli/processes.h"
#include "gaitforge/v1/diagnosis.pb.h"
#include "services/diagnosis/grpc_studies.h"
#include "services/diagnosis/pipeline.h"
#include "services/diagnosis/spec.h"
#include "services/diagnosis/words.h"
#include "services/spec/spec_loader.h"

namespace gaitforge::cli {

std::string DownloadRecording(Connection& conn, const std::string& hash, const std::string& dir,
                              const GlobalOptions& g);

namespace {

// The spec file, parsed, with defaults, checked; an exit code on failure.
int ReadDiagnosisSpec(const std::string& path, v1::DiagnosisSpec* d) {
  std::ifstream in(path);
  if (!in) {
    std::cerr << "gaitforge: cannot open diagnosis spec '" << path << "'\n";
    return kNotFound;
  }
  std::stringstream text;
  text << in.rdbuf();
  if (auto s = spec::ParseMessage(text.str(), path, d, nullptr); !s.ok()) {
    std::cerr << "gaitforge: " << s.message() << "\n";
    return kUsage;
  }
  diagnosis::Defaults(d);
  if (auto s = diagnosis::Validate(*d); !s.ok()) {
    std::cerr << "gaitforge: " << path << ": " << s.message() << "\n";
    return kUsage;
  }
  return kOk;
}

// Uploads the spec's recordings (files become content hashes) and downloads local copies
// of them into dir/recordings for calibration-eval.
int GatherRecordings(Connection& conn, const std::string& spec_path, const v1::DiagnosisSpec& d,
                     const GlobalOptions& g, diagnosis::Inputs* in) {
  v1::StudySpec carrier;
  for (const auto& r : d.training()) carrier.mutable_objective()->add_recordings(r);
  for (const auto& r : d.held_out()) carrier.mutable_objective()->add_held_out(r);
  if (int c = UploadSpecRecordings(conn, spec_path, &carrier, g); c) return c;
  in->train.assign(carrier.objective().recordings().begin(), carrier.objective().recordings().end());
  in->held.assign(carrier.objective().held_out().begin(), carrier.objective().held_out().end());
  std::error_code ec;
  std::filesystem::create_directories(in->dir + "/recordings", ec);
  for (auto [hashes, files] : {std::pair{&in->train, &in->train_files},
                               std::pair{&in->held, &in->held_files}})
    for (const auto& h : *hashes) {
      files->push_back(DownloadRecording(conn, h, in->dir + "/recordings", g));
      if (files->back().empty()) return kFailed;
    }
  return kOk;
}

// Progress on stderr: a bar on a terminal, a line per finished fit otherwise; nothing
// with --json but warnings.
diagnosis::Reporter TerminalReporter(const GlobalOptions& g) {
  diagnosis::Reporter r;
  const bool tty = isatty(STDERR_FILENO);
  auto shown = std::make_shared<std::pair<std::string, int>>("", -1);
  r.progress = [g, tty, shown](const diagnosis::Reporter::Progress& p) {
    if (g.json) return;
    if (tty) {
      DrawProgressBar(p.fraction, p.line);
      if (p.fits_done == p.fits) std::cerr << "\n";
    } else if (p.stage != shown->first || p.fits_done != shown->second) {
      std::cerr << p.line << "\n";
      *shown = {p.stage, p.fits_done};
    }
  };
  r.note = [g](const std::string& line) {
    if (!g.json || line.rfind("warning:", 0) == 0) std::cerr << "gaitforge: " << line << "\n";
  };
  return r;
}

}  // namespace

int CmdDiagnose(const GlobalOptions& g, const std::vector<std::string>& args, int workers,
                int threads, const std::string& out_root) {
  if (args.size() != 1) {
    std::cerr << "gaitforge: usage: gaitforge diagnose SPEC.yaml [--workers N] [--json]\n";
    return kUsage;
  }
  v1::DiagnosisSpec d;
  if (int c = ReadDiagnosisSpec(args[0], &d); c) return c;
  int code = kOk;
  auto conn = Connect(g, true, &code);
  if (!conn) return code;
  std::vector<pid_t> pids;
  if (g.coordinator.empty()) pids = StartLocalWorkers(g, conn->target(), workers, threads);
  struct Stopper {
    std::vector<pid_t>& p;
    ~Stopper() { for (pid_t x : p) Stop(x, 10); }
  } stopper{pids};
  diagnosis::Inputs in;
  in.dir = out_root + "/" + d.name() + "-diagnosis";
  if (int c = GatherRecordings(*conn, args[0], d, g, &in); c) return c;
  diagnosis::GrpcStudies studies(conn->study(), g.timeout_s);
  auto report = diagnosis::Diagnose(d, in, studies, TerminalReporter(g));
  if (!report.ok()) {
    std::cerr << "gaitforge: diagnose " << d.name() << ": " << report.status().message() << "\n";
    return report.status().code() == absl::StatusCode::kInvalidArgument ? kUsage : kFailed;
  }
  if (g.json) {
    std::cout << *report;
    return kOk;
  }
  auto words = diagnosis::ReportWords(*report);
  std::cout << (words.ok() ? *words : std::string(words.status().message()) + "\n");
  return kOk;
}

}  // namespace gaitforge::cli
