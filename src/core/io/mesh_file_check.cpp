#include "cloth_hair_sim/core/io/mesh_file_check.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {

namespace {

std::string lowerExtension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return ext;
}

std::vector<std::string> tokens(const std::string& line) {
  std::istringstream s(line);
  std::vector<std::string> out;
  for (std::string t; s >> t;) out.push_back(t);
  return out;
}

bool isNumber(const std::string& t) {
  char* end = nullptr;
  std::strtod(t.c_str(), &end);
  return !t.empty() && end == t.c_str() + t.size();
}

bool isInteger(const std::string& t, long& value) {
  char* end = nullptr;
  value = std::strtol(t.c_str(), &end, 10);
  return !t.empty() && end == t.c_str() + t.size();
}

// Statements OBJ files carry besides v, vt, vn, f, l, p (free-form geometry, grouping, display):
// assimp ignores most of them, so they are accepted without a closer look.
const std::set<std::string>& otherObjStatements() {
  static const std::set<std::string> k{
      "vp",     "o",        "g",        "s",      "mg",         "usemtl",    "mtllib",
      "cstype", "deg",      "bmat",     "step",   "curv",       "curv2",     "surf",
      "parm",   "trim",     "hole",     "scrv",   "sp",         "end",       "con",
      "bevel",  "c_interp", "d_interp", "lod",    "shadow_obj", "trace_obj", "ctech",
      "stech",  "call",     "csh",      "maplib", "usemap"};
  return k;
}

void checkObj(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  long counts[3] = {0, 0, 0};  // v, vt, vn defined so far (references may only look back)
  std::size_t pos = 0;
  int line_no = 0;
  while (pos < text.size()) {
    // One statement; a backslash at the end of a line continues it on the next.
    std::string statement;
    const int first_line = ++line_no;
    bool ended = false;
    while (pos < text.size()) {
      const std::size_t eol = text.find('\n', pos);
      std::string line = text.substr(pos, eol == std::string::npos ? std::string::npos : eol - pos);
      pos = eol == std::string::npos ? text.size() : eol + 1;
      ended = eol != std::string::npos;
      if (!line.empty() && line.back() == '\r') line.pop_back();
      if (!line.empty() && line.back() == '\\' && pos < text.size()) {
        line.pop_back();
        statement += line + " ";
        ++line_no;
        continue;
      }
      statement += line;
      break;
    }
    const std::string where = path + ": line " + std::to_string(first_line) + ": ";
    // A comment is a line of its own: assimp reads a '#' after a face as a bad index.
    std::vector<std::string> t = tokens(statement);
    if (!t.empty() && t[0][0] == '#') t.clear();
    if (!ended && !statement.empty())
      throw InputError(where +
                       "the file ends in the middle of this line (truncated?); a complete "
                       "OBJ file ends with a line end");
    if (t.empty()) continue;
    const std::string& key = t[0];
    const int args = static_cast<int>(t.size()) - 1;
    if (key == "v" || key == "vt" || key == "vn") {
      const int lo = key == "v" ? 3 : key == "vt" ? 1 : 3;
      const int hi = key == "v" ? 7 : 3;
      if (args < lo || args > hi)
        throw InputError(where + "'" + key + "' needs " + std::to_string(lo) +
                         (lo == hi ? "" : " to " + std::to_string(hi)) + " numbers, it has " +
                         std::to_string(args));
      for (int k = 1; k <= args; ++k)
        if (!isNumber(t[k])) throw InputError(where + "'" + t[k] + "' is not a number");
      ++counts[key == "v" ? 0 : key == "vt" ? 1 : 2];
    } else if (key == "f" || key == "l" || key == "p") {
      const int need = key == "f" ? 3 : key == "l" ? 2 : 1;
      if (args < need)
        throw InputError(where + "'" + key + "' needs at least " + std::to_string(need) +
                         " vertices, it has " + std::to_string(args));
      for (int k = 1; k <= args; ++k) {
        // v, v/vt, v//vn or v/vt/vn; 1-based, negative counts back from the last defined.
        std::array<std::string, 3> part;
        int slot = 0;
        for (char c : t[k]) {
          if (c == '/') {
            if (++slot > 2) break;
          } else {
            part[slot] += c;
          }
        }
        if (slot > 2 || part[0].empty())
          throw InputError(where + "'" + t[k] +
                           "' is not a vertex reference (v, v/vt, v//vn or "
                           "v/vt/vn)");
        static const char* kNames[3] = {"vertex", "texture coordinate", "normal"};
        for (int s = 0; s < 3; ++s) {
          if (part[s].empty()) continue;
          long index = 0;
          if (!isInteger(part[s], index) || index == 0)
            throw InputError(where + "'" + t[k] + "' is not a vertex reference");
          if (std::labs(index) > counts[s])
            throw InputError(where + "'" + t[k] + "' names " + kNames[s] + " " +
                             std::to_string(index) + ", but only " + std::to_string(counts[s]) +
                             " are defined before this line");
        }
      }
    } else if (!otherObjStatements().count(key)) {
      throw InputError(where + "'" + key + "' is not an OBJ statement");
    }
  }
}

// PLY (Paul Bourke's format, as assimp reads it): a header of elements with scalar and list
// properties, then the body in ASCII or binary.
struct PlyProperty {
  bool list = false;
  int count_size = 0;  // bytes of a list's count
  int size = 0;        // bytes of a scalar or of each list item
};
struct PlyElement {
  std::string name;
  long count = 0;
  std::vector<PlyProperty> properties;
};

int plyTypeSize(const std::string& type) {
  if (type == "char" || type == "uchar" || type == "int8" || type == "uint8") return 1;
  if (type == "short" || type == "ushort" || type == "int16" || type == "uint16") return 2;
  if (type == "int" || type == "uint" || type == "float" || type == "int32" || type == "uint32" ||
      type == "float32")
    return 4;
  if (type == "double" || type == "float64") return 8;
  return 0;
}

std::uint64_t readUnsigned(const unsigned char* p, int size, bool big_endian) {
  std::uint64_t v = 0;
  for (int k = 0; k < size; ++k) v |= std::uint64_t(p[big_endian ? size - 1 - k : k]) << (8 * k);
  return v;
}

void checkPly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(path + ": cannot open");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::size_t pos = 0;
  auto nextLine = [&](std::string& line) {
    if (pos >= text.size()) return false;
    const std::size_t eol = text.find('\n', pos);
    line = text.substr(pos, eol == std::string::npos ? std::string::npos : eol - pos);
    pos = eol == std::string::npos ? text.size() : eol + 1;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    return true;
  };
  std::string line, format;
  std::vector<PlyElement> elements;
  int line_no = 0;
  bool header_ended = false;
  while (nextLine(line)) {
    ++line_no;
    const std::string where = path + ": header line " + std::to_string(line_no) + ": ";
    const std::vector<std::string> t = tokens(line);
    if (t.empty()) continue;
    if (t[0] == "end_header") {
      header_ended = true;
      break;
    }
    if (t[0] == "format" && t.size() >= 2) {
      format = t[1];
    } else if (t[0] == "element") {
      long count = 0;
      if (t.size() != 3 || !isInteger(t[2], count) || count < 0)
        throw InputError(where + "an element needs a name and a count");
      elements.push_back({t[1], count, {}});
    } else if (t[0] == "property") {
      if (elements.empty()) throw InputError(where + "a property before any element");
      PlyProperty p;
      if (t.size() == 5 && t[1] == "list") {
        p.list = true;
        p.count_size = plyTypeSize(t[2]);
        p.size = plyTypeSize(t[3]);
        if (!p.count_size || !p.size) throw InputError(where + "unknown list type");
      } else if (t.size() == 3) {
        p.size = plyTypeSize(t[1]);
        if (!p.size) throw InputError(where + "unknown property type '" + t[1] + "'");
      } else {
        throw InputError(where +
                         "a property is 'property TYPE NAME' or 'property list COUNT_TYPE "
                         "ITEM_TYPE NAME'");
      }
      elements.back().properties.push_back(p);
    }
  }
  if (!header_ended) throw InputError(path + ": the PLY header has no end_header (truncated?)");
  if (format == "ascii") {
    // Each element instance is one line in practice, but the format only orders the values:
    // count tokens across lines.
    std::istringstream body(text.substr(pos));
    for (const auto& e : elements)
      for (long i = 0; i < e.count; ++i)
        for (const auto& p : e.properties) {
          long n = 1;
          std::string value;
          if (p.list) {
            if (!(body >> value) || !isInteger(value, n) || n < 0)
              throw InputError(path + ": " + e.name + " " + std::to_string(i) + " of " +
                               std::to_string(e.count) +
                               (body ? ": a list count is not a count" : ": the file ends here"));
          }
          for (long k = 0; k < n; ++k)
            if (!(body >> value) || !isNumber(value))
              throw InputError(path + ": " + e.name + " " + std::to_string(i) + " of " +
                               std::to_string(e.count) +
                               (body ? ": '" + value + "' is not a number"
                                     : ": the file ends here (truncated?)"));
        }
    return;
  }
  if (format != "binary_little_endian" && format != "binary_big_endian")
    throw InputError(path + ": PLY format '" + format +
                     "' is not ascii, binary_little_endian or binary_big_endian");
  const bool big = format == "binary_big_endian";
  const auto* data = reinterpret_cast<const unsigned char*>(text.data());
  std::size_t at = pos;
  for (const auto& e : elements)
    for (long i = 0; i < e.count; ++i) {
      const auto truncated = [&] {
        return InputError(path + ": the file ends in " + e.name + " " + std::to_string(i) + " of " +
                          std::to_string(e.count) + " (truncated?)");
      };
      for (const auto& p : e.properties) {
        std::size_t bytes = p.size;
        if (p.list) {
          if (at + p.count_size > text.size()) throw truncated();
          bytes = p.count_size + readUnsigned(data + at, p.count_size, big) * p.size;
        }
        if (at + bytes > text.size()) throw truncated();
        at += bytes;
      }
    }
}

}  // namespace

void checkMeshFileComplete(const std::string& path) {
  const std::string ext = lowerExtension(path);
  if (ext == ".obj") checkObj(path);
  if (ext == ".ply") checkPly(path);
}

}  // namespace chs
