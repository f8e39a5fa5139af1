#pragma once
// Thin RAII helpers over the SQLite C API, used only inside storage/.
#include <sqlite3.h>

#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"

namespace gaitforge::storage {

class Statement {
 public:
  Statement(sqlite3* db, std::string_view sql);
  ~Statement();
  Statement(const Statement&) = delete;
  Statement& operator=(const Statement&) = delete;

  absl::Status status() const { return status_; }
  Statement& Bind(int i, int64_t v);
  Statement& Bind(int i, int v) { return Bind(i, static_cast<int64_t>(v)); }
  Statement& Bind(int i, double v);
  Statement& Bind(int i, std::optional<double> v);
  Statement& Bind(int i, std::string_view text);
  Statement& BindBlob(int i, std::string_view bytes);
  // SQLITE_ROW: true; SQLITE_DONE: false; errors land in status().
  bool Step();
  absl::Status Run();  // Step to completion, then Reset
  void Reset();

  int64_t Int(int col) const;
  double Real(int col) const;
  std::optional<double> OptReal(int col) const;
  std::string Text(int col) const;
  std::string Blob(int col) const;

 private:
  sqlite3* db_;
  sqlite3_stmt* stmt_ = nullptr;
  absl::Status status_;
};

absl::Status Exec(sqlite3* db, const std::string& sql);
absl::Status SqliteError(sqlite3* db, std::string_view what);

std::string EncodeDoubles(const std::vector<double>& v);
std::vector<double> DecodeDoubles(std::string_view bytes);
std::string DoublesJson(const std::vector<double>& v);

}  // namespace gaitforge::storage
