// `gaitforge recording add|list`, and uploading the recordings a spec names by file.
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "absl/status/statusor.h"
#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "clients/cli/cli.h"
#include "gaitforge/v1/recording.grpc.pb.h"

namespace gaitforge::cli {
namespace {

bool ReadAll(const std::string& path, std::string* out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::stringstream ss;
  ss << in.rdbuf();
  *out = ss.str();
  return true;
}

bool LooksLikeHash(const std::string& s) {
  if (s.size() != 64) return false;
  for (char c : s)
    if (!std::isdigit(static_cast<unsigned char>(c)) && (c < 'a' || c > 'f')) return false;
  return true;
}

}  // namespace

// Adds FILE.csv with its sidecar (default FILE.csv.json); prints the hash.
absl::StatusOr<v1::AddRecordingResponse> AddRecording(Connection& conn, const std::string& csv_path,
                                                      const std::string& sidecar_path,
                                                      const GlobalOptions& g,
                                                      const std::string& robot_descriptor) {
  v1::AddRecordingRequest req;
  std::string csv, sidecar;
  const std::string side = sidecar_path.empty() ? csv_path + ".json" : sidecar_path;
  if (!ReadAll(csv_path, &csv))
    return absl::NotFoundError("cannot read recording '" + csv_path + "'");
  if (!ReadAll(side, &sidecar))
    return absl::NotFoundError("cannot read the recording's sidecar '" + side +
                               "' (name another with --sidecar)");
  req.set_name(std::filesystem::path(csv_path).filename().string());
  req.set_csv(csv);
  req.set_sidecar(sidecar);
  req.set_robot_descriptor(robot_descriptor);
  auto stub = v1::RecordingService::NewStub(conn.channel());
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::AddRecordingResponse resp;
  grpc::Status s = stub->AddRecording(&ctx, req, &resp);
  if (!s.ok()) return absl::Status(static_cast<absl::StatusCode>(s.error_code()), s.error_message());
  return resp;
}

namespace {

// " (N empty or NaN cells bridged ...)" when the upload had occluded samples, else "".
std::string MissingNote(const v1::AddRecordingResponse& added) {
  if (added.missing_cells() <= 0) return "";
  return absl::StrCat(" (", added.missing_cells(),
                      " empty or NaN cells bridged by interpolation in time)");
}

}  // namespace

int UploadSpecRecordings(Connection& conn, const std::string& spec_path, v1::StudySpec* spec,
                         const GlobalOptions& g) {
  const auto base = std::filesystem::path(spec_path).parent_path();
  for (auto* list : {spec->mutable_objective()->mutable_recordings(),
                     spec->mutable_objective()->mutable_held_out()}) {
    for (auto& entry : *list) {
      if (LooksLikeHash(entry)) continue;
      std::filesystem::path p(entry);
      if (p.is_relative()) p = base / p;
      auto added = AddRecording(conn, p.string(), "", g, spec->objective().robot_descriptor());
      if (!added.ok()) {
        std::cerr << "gaitforge: " << spec_path << ": recording '" << entry
                  << "': " << added.status().message() << "\n";
        return added.status().code() == absl::StatusCode::kNotFound ? kNotFound : kUsage;
      }
      if (!g.json)
        std::cerr << "recording " << entry << " -> " << added->recording().hash()
                  << (added->already_stored() ? " (already stored)" : "") << MissingNote(*added)
                  << "\n";
      entry = added->recording().hash();
    }
  }
  return kOk;
}

int CmdRecording(const GlobalOptions& g, const std::vector<std::string>& args,
                 const std::string& sidecar, const std::string& robot_file) {
  if (args.empty() || (args[0] == "add" && args.size() != 2) ||
      (args[0] == "list" && args.size() != 1) || (args[0] != "add" && args[0] != "list")) {
    std::cerr << "gaitforge: usage: gaitforge recording add FILE.csv [--sidecar FILE.json] "
                 "[--robot ROBOT.yaml] | gaitforge recording list\n";
    return kUsage;
  }
  std::string descriptor;
  if (!robot_file.empty() && !ReadAll(robot_file, &descriptor)) {
    std::cerr << "gaitforge: --robot: cannot read '" << robot_file << "'\n";
    return kNotFound;
  }
  int code = kOk;
  auto conn = Connect(g, args[0] == "add", &code);
  if (!conn) return code;
  if (args[0] == "add") {
    auto added = AddRecording(*conn, args[1], sidecar, g, descriptor);
    if (!added.ok()) {
      return ReportRpcError(grpc::Status(static_cast<grpc::StatusCode>(added.status().code()),
                                         std::string(added.status().message())),
                            "recording add " + args[1]);
    }
    if (g.json) {
      std::cout << ToJson(*added) << "\n";
    } else {
      std::cout << added->recording().hash() << "\n";
      if (added->missing_cells() > 0) std::cerr << args[1] << ":" << MissingNote(*added) << "\n";
    }
    return kOk;
  }
  auto stub = v1::RecordingService::NewStub(conn->channel());
  grpc::ClientContext ctx;
  SetDeadline(ctx, g.timeout_s);
  v1::ListRecordingsResponse resp;
  grpc::Status s = stub->ListRecordings(&ctx, v1::ListRecordingsRequest(), &resp);
  if (!s.ok()) return ReportRpcError(s, "recording list");
  if (g.json) {
    std::cout << ToJson(resp) << "\n";
    return kOk;
  }
  std::cout << absl::StrFormat("%-16s %-24s %-12s %8s %9s %s\n", "HASH", "NAME", "ROBOT", "ROWS",
                               "DT (s)", "CHANNELS");
  for (const auto& r : resp.recordings())
    std::cout << absl::StrFormat("%-16s %-24s %-12s %8d %9.4g %d\n", r.hash().substr(0, 16),
                                 r.name(), r.robot(), r.rows(), r.dt(), r.channels_size());
  return kOk;
}

}  // namespace gaitforge::cli
