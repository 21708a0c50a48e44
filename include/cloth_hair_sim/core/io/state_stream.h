#pragma once
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

namespace chs {

// Binary records of a saved simulation (io/state_file.h frames them): little-endian integers,
// doubles by their IEEE bit pattern (a restored run continues bit for bit), counted strings and
// arrays.
class StateWriter {
 public:
  void u64(std::uint64_t value);
  void real(double value);
  void text(std::string_view value);
  void ints(const std::vector<int>& values);
  void reals(const std::vector<double>& values);
  void vectors(const std::vector<Eigen::Vector3d>& values);
  void matrices(const std::vector<Eigen::Matrix3d>& values);
  void matrix(const Eigen::Matrix4d& value);

  const std::string& data() const { return data_; }

 private:
  std::string data_;
};

// Reads what StateWriter wrote, in the same order. Every read checks that the bytes are there
// and every counted array that its count is the expected one, and every double is finite (a
// simulation state holds no others): a short or mismatched record throws InputError
// "<source>: ..." naming the record, never reads past the end.
class StateReader {
 public:
  // source names the data in messages (a file path).
  StateReader(std::string data, std::string source);

  std::uint64_t u64(const char* what);
  double real(const char* what);
  std::string text(const char* what);
  // A string that must equal `expected` (a record's tag).
  void expectText(std::string_view expected, const char* what);
  // Counted arrays; `expected` is the count the receiver holds (the record is refused otherwise).
  std::vector<int> ints(const char* what);
  std::vector<double> reals(const char* what, std::size_t expected);
  std::vector<Eigen::Vector3d> vectors(const char* what);
  std::vector<Eigen::Vector3d> vectors(const char* what, std::size_t expected);
  std::vector<Eigen::Matrix3d> matrices(const char* what, std::size_t expected);
  Eigen::Matrix4d matrix(const char* what);
  // A count that must be `expected`.
  void expectCount(const char* what, std::uint64_t expected);
  // Throws unless every byte has been read.
  void expectEnd();

  // InputError "<source>: <message>".
  [[noreturn]] void fail(const std::string& message) const;

 private:
  // Bytes of the next record, after checking that they are there.
  const char* take(std::size_t bytes, const char* what);
  // An array's count, checked to fit in the bytes left (`item` bytes each).
  std::size_t count(const char* what, std::size_t item);
  // The same, refused unless it is `expected`.
  std::size_t count(const char* what, std::size_t item, std::size_t expected);

  std::string data_;
  std::size_t pos_ = 0;
  std::string source_;
};

}  // namespace chs
