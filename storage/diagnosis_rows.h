// The diagnoses' rows (migration 0006): written on the store's writer thread, read on a
// reader connection, like every other row (sqlite_store.cc).
#pragma once

#include <sqlite3.h>

#include <string>
#include <vector>

#include "absl/status/statusor.h"
#include "storage/study_store.h"

namespace gaitforge::storage {

// Inserts or replaces the diagnosis; its files replace the stored ones when not empty.
absl::Status WriteDiagnosis(sqlite3* db, const DiagnosisRecord& r);
// NotFound names the id.
absl::StatusOr<DiagnosisRecord> ReadDiagnosis(sqlite3* db, const std::string& id,
                                              bool with_files);
// Oldest first, without reports or files.
absl::StatusOr<std::vector<DiagnosisRecord>> ReadDiagnoses(sqlite3* db);

}  // namespace gaitforge::storage
