#include "cloth_hair_sim/core/io/state_stream.h"

#include <cmath>
#include <cstring>
#include <utility>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {
namespace {

std::uint64_t bitsOf(double value) {
  std::uint64_t bits = 0;
  std::memcpy(&bits, &value, sizeof bits);
  return bits;
}

double fromBits(std::uint64_t bits) {
  double value = 0.0;
  std::memcpy(&value, &bits, sizeof value);
  return value;
}

}  // namespace

void StateWriter::u64(std::uint64_t value) {
  for (int k = 0; k < 8; ++k) data_.push_back(static_cast<char>((value >> (8 * k)) & 0xff));
}

void StateWriter::real(double value) {
  u64(bitsOf(value));
}

void StateWriter::text(std::string_view value) {
  u64(value.size());
  data_.append(value);
}

void StateWriter::ints(const std::vector<int>& values) {
  u64(values.size());
  for (int v : values) u64(static_cast<std::uint64_t>(static_cast<std::int64_t>(v)));
}

void StateWriter::reals(const std::vector<double>& values) {
  u64(values.size());
  for (double v : values) real(v);
}

void StateWriter::vectors(const std::vector<Eigen::Vector3d>& values) {
  u64(values.size());
  for (const auto& v : values)
    for (int k = 0; k < 3; ++k) real(v[k]);
}

void StateWriter::matrices(const std::vector<Eigen::Matrix3d>& values) {
  u64(values.size());
  for (const auto& m : values)
    for (int k = 0; k < 9; ++k) real(m(k));
}

void StateWriter::matrix(const Eigen::Matrix4d& value) {
  for (int k = 0; k < 16; ++k) real(value(k));
}

StateReader::StateReader(std::string data, std::string source)
    : data_(std::move(data)), source_(std::move(source)) {}

void StateReader::fail(const std::string& message) const {
  throw InputError(source_ + ": " + message);
}

const char* StateReader::take(std::size_t bytes, const char* what) {
  if (bytes > data_.size() - pos_)
    fail(std::string("truncated in ") + what + " (" + std::to_string(data_.size() - pos_) +
         " bytes left, " + std::to_string(bytes) + " needed)");
  const char* p = data_.data() + pos_;
  pos_ += bytes;
  return p;
}

std::uint64_t StateReader::u64(const char* what) {
  const auto* p = reinterpret_cast<const unsigned char*>(take(8, what));
  std::uint64_t value = 0;
  for (int k = 0; k < 8; ++k) value |= static_cast<std::uint64_t>(p[k]) << (8 * k);
  return value;
}

double StateReader::real(const char* what) {
  const double value = fromBits(u64(what));
  if (!std::isfinite(value)) fail(std::string("non-finite value in ") + what);
  return value;
}

std::size_t StateReader::count(const char* what, std::size_t item) {
  const std::uint64_t n = u64(what);
  if (n > (data_.size() - pos_) / item)
    fail(std::string("truncated in ") + what + " (" + std::to_string(n) + " entries recorded, " +
         std::to_string(data_.size() - pos_) + " bytes left)");
  return static_cast<std::size_t>(n);
}

std::size_t StateReader::count(const char* what, std::size_t item, std::size_t expected) {
  const std::size_t start = pos_;
  expectCount(what, expected);
  pos_ = start;
  return count(what, item);
}

std::string StateReader::text(const char* what) {
  const std::size_t n = count(what, 1);
  return std::string(take(n, what), n);
}

void StateReader::expectText(std::string_view expected, const char* what) {
  const std::string found = text(what);
  if (found != expected)
    fail(std::string(what) + ": expected '" + std::string(expected) + "', found '" + found + "'");
}

void StateReader::expectCount(const char* what, std::uint64_t expected) {
  const std::uint64_t n = u64(what);
  if (n != expected)
    fail(std::string(what) + ": " + std::to_string(n) + " saved, " + std::to_string(expected) +
         " here (the state belongs to a different model)");
}

std::vector<int> StateReader::ints(const char* what) {
  std::vector<int> out(count(what, 8));
  for (auto& v : out) v = static_cast<int>(static_cast<std::int64_t>(u64(what)));
  return out;
}

std::vector<double> StateReader::reals(const char* what, std::size_t expected) {
  std::vector<double> out(count(what, 8, expected));
  for (auto& v : out) v = real(what);
  return out;
}

std::vector<Eigen::Vector3d> StateReader::vectors(const char* what) {
  std::vector<Eigen::Vector3d> out(count(what, 24));
  for (auto& v : out)
    for (int k = 0; k < 3; ++k) v[k] = real(what);
  return out;
}

std::vector<Eigen::Vector3d> StateReader::vectors(const char* what, std::size_t expected) {
  const std::size_t start = pos_;
  expectCount(what, expected);
  pos_ = start;
  return vectors(what);
}

std::vector<Eigen::Matrix3d> StateReader::matrices(const char* what, std::size_t expected) {
  std::vector<Eigen::Matrix3d> out(count(what, 72, expected));
  for (auto& m : out)
    for (int k = 0; k < 9; ++k) m(k) = real(what);
  return out;
}

Eigen::Matrix4d StateReader::matrix(const char* what) {
  Eigen::Matrix4d m;
  for (int k = 0; k < 16; ++k) m(k) = real(what);
  return m;
}

void StateReader::expectEnd() {
  if (pos_ != data_.size())
    fail(std::to_string(data_.size() - pos_) + " unread bytes after the last record");
}

}  // namespace chs
