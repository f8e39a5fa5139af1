#include "storage/diagnosis_rows.h"

#include "absl/strings/str_cat.h"
#include "storage/sqlite_util.h"

namespace gaitforge::storage {
namespace {

constexpr const char* kColumns =
    "diagnosis_id, name, spec, state, verdict, error, created_ms, updated_ms";

DiagnosisRecord Read(Statement& q) {
  DiagnosisRecord r;
  r.diagnosis_id = q.Text(0);
  r.name = q.Text(1);
  r.spec = q.Blob(2);
  r.state = q.Text(3);
  r.verdict = q.Text(4);
  r.error = q.Text(5);
  r.created_ms = q.Int(6);
  r.updated_ms = q.Int(7);
  return r;
}

}  // namespace

absl::Status WriteDiagnosis(sqlite3* db, const DiagnosisRecord& r) {
  Statement q(db,
              "INSERT OR REPLACE INTO diagnoses(diagnosis_id, name, spec, state, verdict, error, "
              "report, created_ms, updated_ms) VALUES (?,?,?,?,?,?,?,?,?)");
  if (auto s = q.Bind(1, r.diagnosis_id)
                   .Bind(2, r.name)
                   .BindBlob(3, r.spec)
                   .Bind(4, r.state)
                   .Bind(5, r.verdict)
                   .Bind(6, r.error)
                   .Bind(7, r.report)
                   .Bind(8, r.created_ms)
                   .Bind(9, r.updated_ms)
                   .Run();
      !s.ok())
    return s;
  if (r.files.empty()) return absl::OkStatus();
  Statement drop(db, "DELETE FROM diagnosis_files WHERE diagnosis_id = ?");
  if (auto s = drop.Bind(1, r.diagnosis_id).Run(); !s.ok()) return s;
  Statement put(db, "INSERT INTO diagnosis_files(diagnosis_id, name, content) VALUES (?,?,?)");
  for (const auto& [name, content] : r.files)
    if (auto s = put.Bind(1, r.diagnosis_id).Bind(2, name).BindBlob(3, content).Run(); !s.ok())
      return s;
  return absl::OkStatus();
}

absl::StatusOr<DiagnosisRecord> ReadDiagnosis(sqlite3* db, const std::string& id,
                                              bool with_files) {
  Statement q(db, absl::StrCat("SELECT ", kColumns, ", report FROM diagnoses WHERE diagnosis_id = ?"));
  q.Bind(1, id);
  if (!q.Step()) {
    if (!q.status().ok()) return q.status();
    return absl::NotFoundError(absl::StrCat("no diagnosis with id '", id, "'"));
  }
  DiagnosisRecord r = Read(q);
  r.report = q.Text(8);
  if (!with_files) return r;
  Statement f(db, "SELECT name, content FROM diagnosis_files WHERE diagnosis_id = ? ORDER BY name");
  f.Bind(1, id);
  while (f.Step()) r.files.emplace_back(f.Text(0), f.Blob(1));
  if (!f.status().ok()) return f.status();
  return r;
}

absl::StatusOr<std::vector<DiagnosisRecord>> ReadDiagnoses(sqlite3* db) {
  Statement q(db, absl::StrCat("SELECT ", kColumns,
                               " FROM diagnoses ORDER BY created_ms, diagnosis_id"));
  std::vector<DiagnosisRecord> out;
  while (q.Step()) out.push_back(Read(q));
  if (!q.status().ok()) return q.status();
  return out;
}

}  // namespace gaitforge::storage
