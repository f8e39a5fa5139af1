#pragma once
// A small, explicit binary encoding for engine state (little-endian, doubles as IEEE bits),
// so that save -> load restores every number bit for bit. No protobuf here: engines must
// not depend on it (design.md, dependency rule).
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "absl/status/status.h"

namespace gaitforge::core {

class ByteWriter {
 public:
  void U32(uint32_t v);
  void U64(uint64_t v);
  void I64(int64_t v) { U64(static_cast<uint64_t>(v)); }
  void F64(double v);
  void Str(std::string_view s);
  void F64s(const std::vector<double>& v);
  const std::string& data() const { return data_; }

 private:
  std::string data_;
};

// Reads what ByteWriter wrote. Every read checks bounds; after a failed read ok() is false
// and further reads return zeros, so a caller checks status() once at the end.
class ByteReader {
 public:
  explicit ByteReader(std::string_view data) : data_(data) {}
  uint32_t U32();
  uint64_t U64();
  int64_t I64() { return static_cast<int64_t>(U64()); }
  double F64();
  std::string Str();
  std::vector<double> F64s();
  bool ok() const { return ok_; }
  bool AtEnd() const { return pos_ == data_.size(); }
  absl::Status status(std::string_view what) const;

 private:
  bool Take(size_t n, const char** p);
  std::string_view data_;
  size_t pos_ = 0;
  bool ok_ = true;
};

}  // namespace gaitforge::core
