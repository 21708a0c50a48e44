#include "cloth_hair_sim/core/io/state_file.h"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>

#include <boost/crc.hpp>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {
namespace {

constexpr char kMagic[8] = {'C', 'H', 'S', 'S', 'T', 'A', 'T', 'E'};
constexpr std::size_t kHeaderBytes = sizeof kMagic + 4 + 8 + 4;

std::uint32_t crc32(const std::string& bytes) {
  boost::crc_32_type crc;
  crc.process_bytes(bytes.data(), bytes.size());
  return crc.checksum();
}

void put(std::string& out, std::uint64_t value, int bytes) {
  for (int k = 0; k < bytes; ++k) out.push_back(static_cast<char>((value >> (8 * k)) & 0xff));
}

std::uint64_t get(const std::string& in, std::size_t at, int bytes) {
  std::uint64_t value = 0;
  for (int k = 0; k < bytes; ++k)
    value |= static_cast<std::uint64_t>(static_cast<unsigned char>(in[at + k])) << (8 * k);
  return value;
}

}  // namespace

std::string encodeStateFile(const std::string& payload) {
  std::string out(kMagic, sizeof kMagic);
  put(out, kStateFormatVersion, 4);
  put(out, payload.size(), 8);
  put(out, crc32(payload), 4);
  return out + payload;
}

std::string decodeStateFile(const std::string& bytes, const std::string& source) {
  const auto fail = [&](const std::string& why) { throw InputError(source + ": " + why); };
  if (bytes.size() < sizeof kMagic || bytes.compare(0, sizeof kMagic, kMagic, sizeof kMagic) != 0)
    fail("not a cloth_hair_sim state file (no CHSSTATE header)");
  if (bytes.size() < kHeaderBytes)
    fail("truncated: " + std::to_string(bytes.size()) + " bytes, shorter than the header");
  const std::uint64_t version = get(bytes, 8, 4);
  if (version != kStateFormatVersion)
    fail("state format version " + std::to_string(version) + ", this build reads version " +
         std::to_string(kStateFormatVersion) + " only (saved by a different build)");
  const std::uint64_t length = get(bytes, 12, 8);
  const std::uint64_t stored = bytes.size() - kHeaderBytes;
  if (stored < length)
    fail("truncated: " + std::to_string(stored) + " of " + std::to_string(length) +
         " payload bytes");
  if (stored > length)
    fail("corrupt: " + std::to_string(stored - length) + " bytes after the " +
         std::to_string(length) + "-byte payload");
  std::string payload = bytes.substr(kHeaderBytes);
  const std::uint32_t expected = static_cast<std::uint32_t>(get(bytes, 20, 4));
  if (crc32(payload) != expected) fail("corrupt: the payload's CRC-32 does not match its header");
  return payload;
}

void writeStateFile(const std::string& path, const std::string& payload) {
  const std::string tmp = path + ".tmp";
  const std::string bytes = encodeStateFile(payload);
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError(path + ": cannot be written (" + std::strerror(errno) + ")");
    out.write(bytes.data(), static_cast<std::streamsize>(bytes.size()));
    out.close();
    if (!out) {
      std::remove(tmp.c_str());
      throw InputError(path + ": writing failed (" + std::strerror(errno) + ")");
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    const std::string why = std::strerror(errno);
    std::remove(tmp.c_str());
    throw InputError(path + ": cannot be written (" + why + ")");
  }
}

std::string readStateFile(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot be read (" + std::strerror(errno) + ")");
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (in.bad()) throw InputError(path + ": reading failed");
  return decodeStateFile(bytes, path);
}

}  // namespace chs
