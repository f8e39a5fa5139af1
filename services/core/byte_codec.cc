#include "services/core/byte_codec.h"

#include <cstring>

#include "absl/strings/str_cat.h"

namespace gaitforge::core {

void ByteWriter::U32(uint32_t v) {
  for (int i = 0; i < 4; ++i) data_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

void ByteWriter::U64(uint64_t v) {
  for (int i = 0; i < 8; ++i) data_.push_back(static_cast<char>((v >> (8 * i)) & 0xff));
}

void ByteWriter::F64(double v) {
  uint64_t bits;
  std::memcpy(&bits, &v, sizeof bits);
  U64(bits);
}

void ByteWriter::Str(std::string_view s) {
  U64(s.size());
  data_.append(s);
}

void ByteWriter::F64s(const std::vector<double>& v) {
  U64(v.size());
  for (double x : v) F64(x);
}

bool ByteReader::Take(size_t n, const char** p) {
  if (!ok_ || data_.size() - pos_ < n) {
    ok_ = false;
    return false;
  }
  *p = data_.data() + pos_;
  pos_ += n;
  return true;
}

uint32_t ByteReader::U32() {
  const char* p;
  if (!Take(4, &p)) return 0;
  uint32_t v = 0;
  for (int i = 0; i < 4; ++i) v |= static_cast<uint32_t>(static_cast<uint8_t>(p[i])) << (8 * i);
  return v;
}

uint64_t ByteReader::U64() {
  const char* p;
  if (!Take(8, &p)) return 0;
  uint64_t v = 0;
  for (int i = 0; i < 8; ++i) v |= static_cast<uint64_t>(static_cast<uint8_t>(p[i])) << (8 * i);
  return v;
}

double ByteReader::F64() {
  uint64_t bits = U64();
  double v;
  std::memcpy(&v, &bits, sizeof v);
  return v;
}

std::string ByteReader::Str() {
  uint64_t n = U64();
  const char* p;
  if (n > data_.size() || !Take(n, &p)) {
    ok_ = false;
    return {};
  }
  return std::string(p, n);
}

std::vector<double> ByteReader::F64s() {
  uint64_t n = U64();
  if (n > (data_.size() - pos_) / 8) {
    ok_ = false;
    return {};
  }
  std::vector<double> v(n);
  for (auto& x : v) x = F64();
  return v;
}

absl::Status ByteReader::status(std::string_view what) const {
  if (!ok_) return absl::DataLossError(absl::StrCat(std::string(what), ": truncated or corrupt state"));
  if (!AtEnd()) return absl::DataLossError(absl::StrCat(std::string(what), ": trailing bytes in state"));
  return absl::OkStatus();
}

}  // namespace gaitforge::core
