#include "services/core/db_path.h"

#include <filesystem>

#include "absl/strings/str_cat.h"

namespace gaitforge::core {

absl::Status CheckDbPath(const std::string& db) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(db, ec))
    return absl::InvalidArgumentError(absl::StrCat("--db ", db,
                                                   " is a directory; name the database file, "
                                                   "e.g. ",
                                                   (fs::path(db) / "gaitforge.db").string()));
  const fs::path folder = fs::path(db).parent_path();
  if (!folder.empty() && !fs::is_directory(folder, ec))
    return absl::InvalidArgumentError(absl::StrCat("--db ", db, ": folder ", folder.string(),
                                                   " does not exist; create it first"));
  return absl::OkStatus();
}

}  // namespace gaitforge::core
