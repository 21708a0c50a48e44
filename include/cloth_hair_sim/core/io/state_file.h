#pragma once
#include <cstdint>
#include <string>

namespace chs {

// Version of the saved-simulation format (the records of io/state_stream.h a backend or the ROS
// node writes): raised whenever they change, so a file of an older build is refused by name
// instead of being misread.
constexpr std::uint32_t kStateFormatVersion = 3;  // 2: hair; 3: its accelerations

// A state file: the magic bytes "CHSSTATE", the format version (u32), the payload's length
// (u64) and its CRC-32 (u32), little-endian, then the payload.
std::string encodeStateFile(const std::string& payload);
// The payload of a state file's bytes; throws InputError "<source>: ..." for something that is
// not a state file, another format version, a truncated or overlong payload, or a checksum
// mismatch (corruption).
std::string decodeStateFile(const std::string& bytes, const std::string& source);

// Writes the file beside its destination and renames it into place, so that a crash while
// saving leaves the previous file whole. Throws InputError naming the path if it cannot.
void writeStateFile(const std::string& path, const std::string& payload);
// Reads and checks a file as decodeStateFile does; throws InputError naming the path.
std::string readStateFile(const std::string& path);

}  // namespace chs
