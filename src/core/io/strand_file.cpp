#include "cloth_hair_sim/core/io/strand_file.h"

#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <sstream>

#include "cloth_hair_sim/core/common/input_error.h"
#include "strand_ply.h"

namespace chs {
namespace {

constexpr std::size_t kHairHeader = 128;

bool endsWith(const std::string& s, const std::string& tail) {
  return s.size() >= tail.size() && s.compare(s.size() - tail.size(), tail.size(), tail) == 0;
}

std::string readAll(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("strand file '" + path + "': cannot be opened (missing?)");
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

template <typename T>
T at(const std::string& bytes, std::size_t offset) {  // little endian, as the format is
  T value;
  std::memcpy(&value, bytes.data() + offset, sizeof(T));
  return value;
}

rod::Polylines readHair(const std::string& path, const std::string& bytes) {
  const std::string who = "HAIR file '" + path + "': ";
  if (bytes.size() < kHairHeader) throw InputError(who + "truncated header");
  if (bytes.compare(0, 4, "HAIR") != 0) throw InputError(who + "no \"HAIR\" signature");
  const std::uint32_t strands = at<std::uint32_t>(bytes, 4), points = at<std::uint32_t>(bytes, 8);
  const std::uint32_t arrays = at<std::uint32_t>(bytes, 12);
  const std::uint32_t default_segments = at<std::uint32_t>(bytes, 16);
  if (strands > static_cast<std::uint32_t>(rod::kMaxGroomStrands))
    throw InputError(who + std::to_string(strands) + " strands, more than the limit " +
                     std::to_string(rod::kMaxGroomStrands));
  if (points > static_cast<std::uint64_t>(rod::kMaxStrandFileVertices))
    throw InputError(who + std::to_string(points) + " points, more than the limit " +
                     std::to_string(rod::kMaxStrandFileVertices));
  if (!(arrays & 2u)) throw InputError(who + "holds no points array");
  const bool has_segments = arrays & 1u;
  std::size_t offset = kHairHeader;
  const std::size_t needed = offset + (has_segments ? 2ull * strands : 0) + 12ull * points;
  if (bytes.size() < needed)
    throw InputError(who + "truncated: " + std::to_string(bytes.size()) +
                     " bytes, the arrays need " + std::to_string(needed));
  std::vector<std::uint32_t> segments(strands, default_segments);
  if (has_segments) {
    for (std::uint32_t s = 0; s < strands; ++s)
      segments[s] = at<std::uint16_t>(bytes, offset + 2 * s);
    offset += 2ull * strands;
  }
  std::uint64_t total = 0;
  for (std::uint32_t n : segments) total += n + 1;
  if (total != points)
    throw InputError(who + "the strands' segments make " + std::to_string(total) +
                     " points, the header says " + std::to_string(points));
  rod::Polylines out(strands);
  for (std::uint32_t s = 0; s < strands; ++s) {
    out[s].resize(segments[s] + 1);
    for (auto& x : out[s]) {
      for (int k = 0; k < 3; ++k) x[k] = at<float>(bytes, offset + 4 * k);
      offset += 12;
    }
  }
  return out;
}

rod::Polylines readText(const std::string& path, const std::string& bytes) {
  const std::string who = "strand file '" + path + "': ";
  std::istringstream in(bytes);
  std::string line;
  int line_no = 0;
  long total = 0;
  rod::Polylines out;
  std::size_t expected = 0;  // vertices still to read for the current strand
  while (std::getline(in, line)) {
    ++line_no;
    line = line.substr(0, line.find('#'));
    std::istringstream fields(line);
    std::string first;
    if (!(fields >> first)) continue;
    fields.clear();
    fields.seekg(0);
    const std::string at_line = who + "line " + std::to_string(line_no) + ": ";
    std::string rest;
    if (expected == 0) {
      long count = 0;
      if (!(fields >> count) || (fields >> rest))
        throw InputError(at_line + "expected a strand's vertex count");
      if (count < 2) throw InputError(at_line + "a strand needs at least two vertices");
      total += count;
      if (out.size() >= static_cast<std::size_t>(rod::kMaxGroomStrands) ||
          total > rod::kMaxStrandFileVertices)
        throw InputError(at_line + "more than the limit of " +
                         std::to_string(rod::kMaxGroomStrands) + " strands or " +
                         std::to_string(rod::kMaxStrandFileVertices) + " vertices");
      out.emplace_back();
      out.back().reserve(count);
      expected = count;
      continue;
    }
    // Read as text so that "nan" and "inf" reach checkStrands, which names them.
    std::string t[3];
    if (!(fields >> t[0] >> t[1] >> t[2]) || (fields >> rest))
      throw InputError(at_line + "expected a vertex \"x y z\"");
    Eigen::Vector3d x;
    for (int k = 0; k < 3; ++k) {
      try {
        std::size_t used = 0;
        x[k] = std::stod(t[k], &used);
        if (used != t[k].size()) throw std::invalid_argument(t[k]);
      } catch (const std::exception&) {
        throw InputError(at_line + "'" + t[k] + "' is not a number");
      }
    }
    out.back().push_back(x);
    --expected;
  }
  if (expected > 0)
    throw InputError(who + "truncated: strand " + std::to_string(out.size() - 1) + " lacks " +
                     std::to_string(expected) + " vertices");
  return out;
}

}  // namespace

rod::Polylines readStrandFile(const std::string& path) {
  const std::string bytes = readAll(path);
  rod::Polylines strands = endsWith(path, ".hair")  ? readHair(path, bytes)
                           : endsWith(path, ".ply") ? readStrandPly(path, bytes)
                                                    : readText(path, bytes);
  try {
    rod::checkStrands(strands, rod::kMaxStrandFileVertices);
  } catch (const InputError& e) {
    throw InputError("strand file '" + path + "': " + e.what());
  }
  return strands;
}

}  // namespace chs
