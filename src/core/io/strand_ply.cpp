#include "strand_ply.h"

#include <array>
#include <cstdint>
#include <cstring>
#include <map>
#include <sstream>
#include <vector>

#include "cloth_hair_sim/core/common/input_error.h"

namespace chs {
namespace {

// PLY scalar types and their sizes (both the old names and the sized ones).
const std::map<std::string, int>& typeSizes() {
  static const std::map<std::string, int> sizes{
      {"char", 1},  {"uchar", 1},   {"int8", 1},   {"uint8", 1},  {"short", 2}, {"ushort", 2},
      {"int16", 2}, {"uint16", 2},  {"int", 4},    {"uint", 4},   {"int32", 4}, {"uint32", 4},
      {"float", 4}, {"float32", 4}, {"double", 8}, {"float64", 8}};
  return sizes;
}

struct Property {
  std::string name, type;
};
struct Element {
  std::string name;
  long count = 0;
  std::vector<Property> properties;
  bool has_list = false;
};

// One element's rows as numbers, from ascii text or little-endian binary.
class Reader {
 public:
  Reader(const std::string& who, const std::string& bytes, std::size_t start, bool binary)
      : who_(who), bytes_(bytes), pos_(start), binary_(binary) {
    if (!binary) text_.str(bytes.substr(start));
  }
  double value(const std::string& type) {
    if (!binary_) {
      std::string t;
      if (!(text_ >> t))
        throw InputError(who_ + "truncated: the data ends before the header's counts");
      try {
        return std::stod(t);
      } catch (const std::exception&) {
        throw InputError(who_ + "'" + t + "' is not a number");
      }
    }
    const int size = typeSizes().at(type);
    if (pos_ + size > bytes_.size())
      throw InputError(who_ + "truncated: the data ends before the header's counts");
    const char* p = bytes_.data() + pos_;
    pos_ += size;
    auto get = [p](auto v) {
      std::memcpy(&v, p, sizeof v);
      return static_cast<double>(v);
    };
    if (type == "float" || type == "float32") return get(float());
    if (type == "double" || type == "float64") return get(double());
    if (type == "char" || type == "int8") return get(std::int8_t());
    if (type == "uchar" || type == "uint8") return get(std::uint8_t());
    if (type == "short" || type == "int16") return get(std::int16_t());
    if (type == "ushort" || type == "uint16") return get(std::uint16_t());
    if (type == "int" || type == "int32") return get(std::int32_t());
    return get(std::uint32_t());
  }

 private:
  std::string who_;
  const std::string& bytes_;
  std::size_t pos_;
  bool binary_;
  std::istringstream text_;
};

}  // namespace

rod::Polylines readStrandPly(const std::string& path, const std::string& bytes) {
  const std::string who = "PLY strand file '" + path + "': ";
  const std::size_t end = bytes.find("end_header");
  if (bytes.compare(0, 3, "ply") != 0 || end == std::string::npos)
    throw InputError(who + "not a PLY file (no \"ply\" ... \"end_header\")");
  const std::size_t data = bytes.find('\n', end);
  if (data == std::string::npos) throw InputError(who + "truncated after its header");
  std::istringstream header(bytes.substr(0, end));
  std::string line, format;
  std::vector<Element> elements;
  while (std::getline(header, line)) {
    std::istringstream f(line);
    std::string word;
    f >> word;
    if (word == "format") {
      f >> format;
    } else if (word == "element") {
      Element e;
      if (!(f >> e.name >> e.count) || e.count < 0)
        throw InputError(who + "bad header line \"" + line + "\"");
      elements.push_back(e);
    } else if (word == "property") {
      if (elements.empty()) throw InputError(who + "a property before any element");
      Property p;
      f >> p.type;
      if (p.type == "list") {
        elements.back().has_list = true;
        continue;
      }
      f >> p.name;
      if (!typeSizes().count(p.type))
        throw InputError(who + "unknown property type '" + p.type + "'");
      elements.back().properties.push_back(p);
    }
  }
  if (format != "ascii" && format != "binary_little_endian")
    throw InputError(who + "format '" + format + "' is not read (ascii or binary_little_endian)");
  std::vector<Eigen::Vector3d> vertices;
  std::vector<std::array<long, 2>> edges;
  Reader in(who, bytes, data + 1, format != "ascii");
  for (const Element& e : elements) {
    if (e.count == 0) continue;
    if (e.name == "face")
      throw InputError(who + "holds faces: a mesh, not strands (give vertices and edges)");
    if (e.has_list)
      throw InputError(who + "element '" + e.name + "' has a list property, which is not read");
    if (e.name == "vertex" && e.count > rod::kMaxStrandFileVertices)
      throw InputError(who + std::to_string(e.count) + " vertices, more than the limit " +
                       std::to_string(rod::kMaxStrandFileVertices));
    int ix[3] = {-1, -1, -1}, iv[2] = {-1, -1};
    for (std::size_t k = 0; k < e.properties.size(); ++k) {
      const std::string& n = e.properties[k].name;
      if (n == "x" || n == "y" || n == "z") ix[n[0] - 'x'] = static_cast<int>(k);
      if (n == "vertex1" || n == "vertex2") iv[n == "vertex2"] = static_cast<int>(k);
    }
    if (e.name == "vertex" && (ix[0] < 0 || ix[1] < 0 || ix[2] < 0))
      throw InputError(who + "its vertices lack x, y or z");
    if (e.name == "edge" && (iv[0] < 0 || iv[1] < 0))
      throw InputError(who + "its edges lack vertex1 or vertex2");
    std::vector<double> row(e.properties.size());
    for (long r = 0; r < e.count; ++r) {
      for (std::size_t k = 0; k < row.size(); ++k) row[k] = in.value(e.properties[k].type);
      if (e.name == "vertex") vertices.emplace_back(row[ix[0]], row[ix[1]], row[ix[2]]);
      if (e.name == "edge")
        edges.push_back({static_cast<long>(row[iv[0]]), static_cast<long>(row[iv[1]])});
    }
  }
  if (edges.empty()) throw InputError(who + "holds no edges (strands are chains of edges)");
  // Chains: every vertex on at most two edges; walk each from its lower-numbered end.
  const long n = static_cast<long>(vertices.size());
  std::vector<std::vector<long>> next(n);
  for (const auto& e : edges) {
    for (long v : e)
      if (v < 0 || v >= n)
        throw InputError(who + "edge to vertex " + std::to_string(v) + " of " + std::to_string(n));
    if (e[0] == e[1])
      throw InputError(who + "an edge from vertex " + std::to_string(e[0]) + " to itself");
    next[e[0]].push_back(e[1]);
    next[e[1]].push_back(e[0]);
  }
  for (long v = 0; v < n; ++v)
    if (next[v].size() > 2)
      throw InputError(who + "vertex " + std::to_string(v) + " is on " +
                       std::to_string(next[v].size()) + " edges (a branch, not a strand)");
  rod::Polylines out;
  std::vector<char> used(n, 0);
  for (long v = 0; v < n; ++v) {
    if (used[v] || next[v].size() != 1) continue;
    std::vector<Eigen::Vector3d> strand;
    long prev = -1, at = v;
    while (at >= 0) {
      used[at] = 1;
      strand.push_back(vertices[at]);
      long step = -1;
      for (long w : next[at])
        if (w != prev) step = w;
      prev = at;
      at = step;
    }
    out.push_back(std::move(strand));
  }
  for (long v = 0; v < n; ++v)
    if (!used[v] && !next[v].empty())
      throw InputError(who + "vertex " + std::to_string(v) + " is on a closed loop of edges");
  return out;
}

}  // namespace chs
