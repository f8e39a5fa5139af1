// `gaitforge diagnose SPEC`: the gap finder (docs/diagnosis.md, services/diagnosis/). Reads
// and checks the spec, uploads its recordings and asks the coordinator (a private one and
// local workers unless --coordinator names one) to run the diagnosis as a stored job; then
// waits for it as `gaitforge diagnosis ID` does (diagnoses.cc).
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>

#include "absl/strings/str_cat.h"
#include "clients/cli/cli.h"
#include "clients/cli/processes.h"
#include "gaitforge/v1/diagnosis.grpc.pb.h"
#include "services/diagnosis/spec.h"
#include "services/recording/recording.h"
#include "services/spec/robot_file.h"
#include "services/spec/spec_loader.h"

namespace gaitforge::cli {

namespace {

// A spec that names no robot diagnoses the robot its first training recording's sidecar
// names. A stored recording's hash is left to the coordinator, which knows its robot.
absl::Status InferRobot(const std::string& spec_path, v1::DiagnosisSpec* d) {
  if (!d->robot().empty() || d->training_size() == 0) return absl::OkStatus();
  std::filesystem::path csv(d->training(0));
  if (csv.is_relative()) csv = std::filesystem::path(spec_path).parent_path() / csv;
  const std::string side = csv.string() + ".json";
  std::ifstream in(side, std::ios::binary);
  if (!in) return absl::OkStatus();  // a hash, or a missing file the upload reports
  std::stringstream text;
  text << in.rdbuf();
  auto robot = recording::SidecarRobot(text.str(), side);
  if (!robot.ok())
    return absl::InvalidArgumentError(absl::StrCat(
        "field 'robot' is left out and the first training recording does not name a known "
        "robot (give 'robot:'): ", robot.status().message()));
  d->set_robot(*robot);
  return absl::OkStatus();
}

}  // namespace

// The spec file, parsed, with defaults, checked; an exit code on failure.
int ReadDiagnosisSpec(const std::string& path, v1::DiagnosisSpec* d) {
  std::ifstream in(path);
  if (!in) {
    std::cerr << "gaitforge: cannot open diagnosis spec '" << path << "'\n";
    return kNotFound;
  }
  std::stringstream text;
  text << in.rdbuf();
  std::map<std::string, spec::Mark> marks;
  if (auto s = spec::ParseMessage(text.str(), path, d, &marks); !s.ok()) {
    std::cerr << "gaitforge: " << s.message() << "\n";
    return kUsage;
  }
  // robot: a descriptor file's path makes the spec carry the descriptor.
  std::string where = path;
  if (auto it = marks.find("robot"); it != marks.end())
    where = absl::StrCat(path, ":", it->second.line, ":", it->second.column);
  std::string robot = d->robot(), descriptor = d->robot_descriptor();
  if (auto s = spec::EmbedRobotFile(path, where, "robot", &robot, &descriptor); !s.ok()) {
    std::cerr << "gaitforge: " << s.message() << "\n";
    return s.code() == absl::StatusCode::kNotFound ? kNotFound : kUsage;
  }
  d->set_robot(robot);
  d->set_robot_descriptor(descriptor);
  if (auto s = InferRobot(path, d); !s.ok()) {
    std::cerr << "gaitforge: " << path << ": " << s.message() << "\n";
    return kUsage;
  }
  if (d->robot().empty()) return kOk;  // recordings by hash: the coordinator fills and checks
  diagnosis::Defaults(d);
  if (auto s = diagnosis::Validate(*d); !s.ok()) {
    std::cerr << "gaitforge: " << path << ": " << s.message() << "\n";
    return kUsage;
  }
  return kOk;
}

namespace {

// Uploads the spec's recordings: files become content hashes.
int UploadRecordings(Connection& conn, const std::string& spec_path, const GlobalOptions& g,
                     v1::DiagnosisSpec* d) {
  v1::StudySpec carrier;
  carrier.mutable_objective()->set_robot_descriptor(d->robot_descriptor());
  for (const auto& r : d->training()) carrier.mutable_objective()->add_recordings(r);
  for (const auto& r : d->held_out()) carrier.mutable_objective()->add_held_out(r);
  if (int c = UploadSpecRecordings(conn, spec_path, &carrier, g); c) return c;
  *d->mutable_training() = carrier.objective().recordings();
  *d->mutable_held_out() = carrier.objective().held_out();
  return kOk;
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
  if (int c = UploadRecordings(*conn, args[0], g, &d); c) return c;
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::CreateDiagnosisRequest req;
  *req.mutable_spec() = d;
  v1::DiagnosisSummary created;
  auto stub = v1::DiagnosisService::NewStub(conn->channel());
  if (auto s = stub->CreateDiagnosis(&ctx, req, &created); !s.ok())
    return ReportRpcError(s, "diagnose " + d.name());
  if (!g.json)
    std::cerr << "diagnosis " << created.diagnosis_id() << " (the coordinator runs it; "
              << "gaitforge diagnosis " << created.diagnosis_id() << " shows it)\n";
  // The diagnosis, live, and its fits' studies (docs/dashboard.md).
  if (!g.json && !conn->dashboard_url().empty())
    std::cerr << "dashboard: " << conn->dashboard_url() << "#/diagnosis/" << created.diagnosis_id()
              << "\n";
  return AwaitDiagnosis(*stub, created.diagnosis_id(), out_root, g, true);
}

}  // namespace gaitforge::cli
