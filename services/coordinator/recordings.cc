#include "services/coordinator/recordings.h"

#include <chrono>
#include <cmath>

#include "absl/strings/str_cat.h"
#include "absl/strings/str_format.h"
#include "robots/registry.h"
#include "services/recording/recording.h"

namespace gaitforge::coordinator {
namespace {

v1::RecordingInfo Info(const storage::RecordingRecord& r) {
  v1::RecordingInfo info;
  info.set_hash(r.hash);
  info.set_name(r.name);
  info.set_robot(r.robot);
  info.set_rows(r.rows);
  for (const auto& c : r.channels) info.add_channels(c);
  info.set_dt(r.dt);
  info.set_dropped_rows(r.dropped_rows);
  info.set_bytes(r.bytes);
  info.set_added_unix_ms(r.added_ms);
  return info;
}

}  // namespace

absl::StatusOr<v1::AddRecordingResponse> Recordings::Add(const v1::AddRecordingRequest& req) {
  if (read_only_)
    return absl::FailedPreconditionError("this coordinator is read-only; it stores no recording");
  const std::string name = req.name().empty() ? "recording.csv" : req.name();
  recording::RecordingLimits limits;
  limits.max_bytes = max_bytes_;
  std::shared_ptr<const robots::RobotDescriptor> robot;
  if (!req.robot_descriptor().empty()) {
    auto resolved = robots::ResolveRobot("", req.robot_descriptor());
    if (!resolved.ok())
      return absl::InvalidArgumentError(
          absl::StrCat("field 'robot_descriptor': ", resolved.status().message()));
    robot = *resolved;
  }
  auto parsed = recording::ParseRecording(req.csv(), req.sidecar(), name, name + ".json", limits,
                                          robot.get());
  if (!parsed.ok()) return parsed.status();
  storage::RecordingRecord r;
  r.hash = recording::ContentHash(req.csv(), req.sidecar());
  r.name = name;
  r.robot = parsed->meta.robot;
  r.rows = static_cast<int64_t>(parsed->t.size());
  r.channels = parsed->channels;
  r.dt = parsed->dt;
  r.dropped_rows = parsed->dropped_rows;
  r.csv = req.csv();
  r.sidecar = req.sidecar();
  r.added_ms = std::chrono::duration_cast<std::chrono::milliseconds>(
                   std::chrono::system_clock::now().time_since_epoch())
                   .count();
  auto stored = store_.PutRecording(r).get();
  if (!stored.ok()) return stored.status();
  // The stored row (the first upload's name and time when these bytes were there already).
  auto row = store_.GetRecording(r.hash, false);
  if (!row.ok()) return row.status();
  v1::AddRecordingResponse out;
  *out.mutable_recording() = Info(*row);
  out.set_already_stored(!*stored);
  out.set_missing_cells(parsed->missing_cells);
  return out;
}

absl::StatusOr<v1::GetRecordingResponse> Recordings::Get(const std::string& hash) {
  auto r = store_.GetRecording(hash, true);
  if (!r.ok()) return r.status();
  v1::GetRecordingResponse out;
  *out.mutable_recording() = Info(*r);
  out.set_csv(r->csv);
  out.set_sidecar(r->sidecar);
  return out;
}

absl::StatusOr<v1::ListRecordingsResponse> Recordings::List() {
  auto all = store_.ListRecordings();
  if (!all.ok()) return all.status();
  v1::ListRecordingsResponse out;
  for (const auto& r : *all) *out.add_recordings() = Info(r);
  return out;
}

absl::Status Recordings::CheckExist(const google::protobuf::RepeatedPtrField<std::string>& hashes,
                                    const std::string& field) {
  for (int i = 0; i < hashes.size(); ++i) {
    auto r = store_.GetRecording(hashes[i], false);
    if (r.ok()) continue;
    if (r.status().code() != absl::StatusCode::kNotFound) return r.status();
    return absl::InvalidArgumentError(absl::StrCat(
        "field '", field, "[", i, "]': no recording with hash '", hashes[i],
        "' is stored; add it with 'gaitforge recording add FILE.csv' (or name the file in the "
        "spec and submit it with the CLI)"));
  }
  return absl::OkStatus();
}

absl::Status Recordings::CheckOneRobotAndRate(
    const std::string& robot,
    const std::vector<std::pair<std::string, const google::protobuf::RepeatedPtrField<std::string>*>>&
        fields) {
  double dt = 0;
  std::string first;
  for (const auto& [field, hashes] : fields)
    for (int i = 0; i < hashes->size(); ++i) {
      auto r = store_.GetRecording((*hashes)[i], false);
      if (!r.ok()) return r.status();
      const std::string path = absl::StrCat(field, "[", i, "]");
      if (r->robot != robot)
        return absl::InvalidArgumentError(absl::StrCat(
            "field '", path, "': recording '", r->name, "' is of robot '", r->robot,
            "', the diagnosis's robot is '", robot, "': one spec diagnoses one robot"));
      if (dt == 0) {
        dt = r->dt;
        first = path;
      } else if (!recording::SameRate(r->dt, dt)) {
        return absl::InvalidArgumentError(absl::StrFormat(
            "field '%s': recording '%s' is sampled every %g s, %s every %g s: one spec's "
            "recordings share a rate (resample them to one)",
            path, r->name, r->dt, first, dt));
      }
    }
  return absl::OkStatus();
}

}  // namespace gaitforge::coordinator
