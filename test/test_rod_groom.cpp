// Grooms (core/rod/groom.h) and strand files (core/io/strand_file.h): strands rooted on a scalp
// patch of a sphere or an ellipsoid leave it along its normal with the length asked, resampling
// keeps a polyline's shape at equal arc lengths, the text and Yuksel .hair formats read back what
// was written, and bad input (missing or truncated files, NaN, zero-length strands, duplicate
// vertices, too many strands) is refused with a message naming it.
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>

#include <gtest/gtest.h>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/mesh_writer.h"
#include "cloth_hair_sim/core/io/strand_file.h"
#include "cloth_hair_sim/core/rod/groom.h"

namespace chs::rod {
namespace {

using Vec3 = Eigen::Vector3d;

double arcLength(const std::vector<Vec3>& x) {
  double l = 0.0;
  for (std::size_t i = 1; i < x.size(); ++i) l += (x[i] - x[i - 1]).norm();
  return l;
}

std::string tempPath(const std::string& name) {
  return testing::TempDir() + "/chs_groom_" + name;
}

void writeText(const std::string& path, const std::string& text) {
  std::ofstream(path) << text;
}

// A .hair file (Yuksel's layout, strand_file.h) of the given strands, optionally without the
// segments array (every strand then has default_segments).
std::string hairBytes(const Polylines& strands, bool segments_array,
                      std::uint32_t default_segments) {
  std::string b(128, '\0');
  std::uint32_t points = 0;
  for (const auto& s : strands) points += static_cast<std::uint32_t>(s.size());
  const std::uint32_t count = static_cast<std::uint32_t>(strands.size());
  const std::uint32_t arrays = (segments_array ? 1u : 0u) | 2u;
  std::memcpy(&b[0], "HAIR", 4);
  std::memcpy(&b[4], &count, 4);
  std::memcpy(&b[8], &points, 4);
  std::memcpy(&b[12], &arrays, 4);
  std::memcpy(&b[16], &default_segments, 4);
  if (segments_array)
    for (const auto& s : strands) {
      const std::uint16_t n = static_cast<std::uint16_t>(s.size() - 1);
      b.append(reinterpret_cast<const char*>(&n), 2);
    }
  for (const auto& s : strands)
    for (const auto& x : s)
      for (int k = 0; k < 3; ++k) {
        const float f = static_cast<float>(x[k]);
        b.append(reinterpret_cast<const char*>(&f), 4);
      }
  return b;
}

void writeBytes(const std::string& path, const std::string& bytes) {
  std::ofstream(path, std::ios::binary) << bytes;
}

void expectRefused(const std::string& path, const std::string& fragment) {
  try {
    readStrandFile(path);
    ADD_FAILURE() << path << " was accepted";
  } catch (const InputError& e) {
    std::printf("refused: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find(fragment), std::string::npos) << e.what();
  }
}

TEST(Groom, SphereRootsOnTheSurfaceInTheConeAlongTheNormal) {
  GroomSettings g;
  g.scalp.centre = Vec3(0.1, -0.2, 1.0);
  g.scalp.radii = Vec3::Constant(0.09);
  g.scalp.direction = Vec3(1, 0, 1);
  g.scalp.cone_angle = 0.6;
  g.strands = 500;
  g.length = 0.15;
  g.segments = 12;
  const Polylines strands = groomScalp(g);
  ASSERT_EQ(strands.size(), 500u);
  double radius_err = 0.0, tangent_err = 0.0, length_err = 0.0, widest = 0.0;
  for (const auto& x : strands) {
    ASSERT_EQ(x.size(), 13u);
    const Vec3 n = (x[0] - g.scalp.centre).normalized();
    radius_err = std::max(radius_err, std::abs((x[0] - g.scalp.centre).norm() - 0.09));
    tangent_err = std::max(tangent_err, ((x[1] - x[0]).normalized() - n).norm());
    length_err = std::max(length_err, std::abs(arcLength(x) - g.length));
    widest = std::max(widest, std::acos(std::min(1.0, n.dot(g.scalp.direction.normalized()))));
  }
  std::printf(
      "[figure] sphere groom, 500 strands: root radius error %.2e m, tangent vs normal "
      "%.2e, length error %.2e m, widest root %.4f rad of the cone's 0.6\n",
      radius_err, tangent_err, length_err, widest);
  EXPECT_LT(radius_err, 1e-12);
  EXPECT_LT(tangent_err, 1e-12);
  EXPECT_LT(length_err, 1e-12);
  EXPECT_LE(widest, 0.6 + 1e-12);
  EXPECT_GT(widest, 0.5);  // the patch is covered, not one spot
  // The same seed draws the same groom, another seed another.
  EXPECT_EQ(groomScalp(g)[7][3], strands[7][3]);
  g.seed = 2;
  EXPECT_NE(groomScalp(g)[7][3], strands[7][3]);
}

TEST(Groom, EllipsoidRootsOnTheSurfaceAlongItsNormal) {
  GroomSettings g;
  g.scalp.radii = Vec3(0.08, 0.1, 0.12);
  g.scalp.cone_angle = M_PI;  // the whole surface
  g.strands = 300;
  const Polylines strands = groomScalp(g);
  double surface_err = 0.0, tangent_err = 0.0;
  for (const auto& x : strands) {
    const Vec3 q = x[0].cwiseQuotient(g.scalp.radii);
    surface_err = std::max(surface_err, std::abs(q.squaredNorm() - 1.0));
    const Vec3 n = x[0].cwiseQuotient(g.scalp.radii.cwiseProduct(g.scalp.radii)).normalized();
    tangent_err = std::max(tangent_err, ((x[1] - x[0]).normalized() - n).norm());
  }
  std::printf("[figure] ellipsoid groom: |x/a|^2 - 1 up to %.2e, tangent vs normal %.2e\n",
              surface_err, tangent_err);
  EXPECT_LT(surface_err, 1e-12);
  EXPECT_LT(tangent_err, 1e-12);
}

TEST(Groom, CurlsKeepTheirLengthAndRadius) {
  GroomSettings g;
  g.strands = 50;
  g.length = 0.2;
  g.segments = 80;
  g.curl_radius = 0.005;
  g.curl_pitch = 0.02;
  double length_err = 0.0, max_dist = 0.0;
  for (const auto& x : groomScalp(g)) {
    length_err = std::max(length_err, std::abs(arcLength(x) - g.length));
    for (const auto& v : x) max_dist = std::max(max_dist, (v - x[0]).norm());
  }
  // Chords of a helix are shorter than its arcs: within the curvature's (kappa ds)^2 / 24.
  const double c = g.curl_pitch / (2 * M_PI), kappa = g.curl_radius / (0.005 * 0.005 + c * c);
  const double ds = g.length / g.segments, bound = g.length * kappa * kappa * ds * ds / 24;
  std::printf(
      "[figure] curled groom: polyline length error %.2e m (bound %.2e), farthest vertex "
      "%.4f m from its root\n",
      length_err, bound, max_dist);
  EXPECT_LT(length_err, 1.01 * bound + 1e-12);
  EXPECT_LT(max_dist, g.length);  // curled, not straight
}

TEST(Groom, ResampleAtEqualArcLengths) {
  const std::vector<Vec3> bent{Vec3(0, 0, 0), Vec3(0, 0, -0.1), Vec3(0.1, 0, -0.1)};
  const std::vector<Vec3> x = resampleStrand(bent, 8);
  ASSERT_EQ(x.size(), 9u);
  double err = 0.0;
  for (std::size_t i = 1; i < x.size(); ++i)
    err = std::max(err, std::abs((x[i] - x[i - 1]).norm() - 0.025));
  std::printf("[figure] resampled L-shaped strand: segment length error %.2e m\n", err);
  EXPECT_LT(err, 1e-15);
  EXPECT_EQ(x.front(), bent.front());
  EXPECT_EQ(x.back(), bent.back());
  EXPECT_THROW(resampleStrand(bent, 0), InputError);
}

TEST(Groom, BadSettingsRefused) {
  GroomSettings g;
  g.strands = kMaxGroomStrands + 1;
  EXPECT_THROW(groomScalp(g), InputError);
  g = GroomSettings();
  g.strands = 90000;
  g.segments = 20;  // 1.89 M vertices
  EXPECT_THROW(groomScalp(g), InputError);
  g = GroomSettings();
  g.length = std::nan("");
  EXPECT_THROW(groomScalp(g), InputError);
  g = GroomSettings();
  g.scalp.radii = Vec3(0.1, 0.0, 0.1);
  EXPECT_THROW(groomScalp(g), InputError);
  g = GroomSettings();
  g.scalp.cone_angle = 4.0;
  EXPECT_THROW(groomScalp(g), InputError);
  g = GroomSettings();
  g.curl_radius = 0.01;  // pitch 0
  EXPECT_THROW(groomScalp(g), InputError);
}

TEST(StrandFile, TextReadsBack) {
  const std::string path = tempPath("ok.strands");
  writeText(path,
            "# two strands\n3\n0 0 0\n0 0 -0.05  # root to tip\n0 0 -0.1\n\n2\n1 0 0\n1 0 -1e-1\n");
  const Polylines s = readStrandFile(path);
  ASSERT_EQ(s.size(), 2u);
  ASSERT_EQ(s[0].size(), 3u);
  ASSERT_EQ(s[1].size(), 2u);
  EXPECT_EQ(s[0][1], Vec3(0, 0, -0.05));
  EXPECT_EQ(s[1][1], Vec3(1, 0, -0.1));
}

// The largest distance between the strands read from `path` and `written`; infinite when the
// file's strands or vertex counts differ (reported as a failure).
double readBackError(const std::string& path, const Polylines& written) {
  const Polylines s = readStrandFile(path);
  EXPECT_EQ(s.size(), written.size());
  if (s.size() != written.size()) return INFINITY;
  double err = 0.0;
  for (std::size_t k = 0; k < s.size(); ++k) {
    EXPECT_EQ(s[k].size(), written[k].size()) << "strand " << k;
    if (s[k].size() != written[k].size()) return INFINITY;
    for (std::size_t i = 0; i < s[k].size(); ++i)
      err = std::max(err, (s[k][i] - written[k][i]).norm());
  }
  return err;
}

TEST(StrandFile, YukselHairReadsBack) {
  GroomSettings g;
  g.strands = 20;
  g.segments = 7;
  const Polylines groom = groomScalp(g);
  for (bool segments_array : {true, false}) {
    const std::string path = tempPath(segments_array ? "seg.hair" : "noseg.hair");
    writeBytes(path, hairBytes(groom, segments_array, 7));
    const double err = readBackError(path, groom);
    std::printf("[figure] .hair %s segments array: 20 strands, largest error %.2e m (float)\n",
                segments_array ? "with" : "without", err);
    EXPECT_LT(err, 1e-7);
  }
}

// PLY strands: what the simulate tool writes (io/mesh_writer.h writeStrandsPly) reads back,
// and a binary little-endian file with float vertices, int edges and an extra property.
TEST(StrandFile, PlyReadsBack) {
  GroomSettings g;
  g.strands = 15;
  g.segments = 6;
  const Polylines groom = groomScalp(g);
  const std::string path = tempPath("strands.ply");
  writeStrandsPly(path, groom);
  const double err = readBackError(path, groom);
  std::printf("[figure] ascii PLY strands: 15 strands read back, largest error %.2e m\n", err);
  EXPECT_LT(err, 1e-9);

  std::string bin =
      "ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\n"
      "property float y\nproperty float z\nproperty uchar red\nelement edge 2\n"
      "property int vertex1\nproperty int vertex2\nend_header\n";
  auto put = [&bin](auto v) { bin.append(reinterpret_cast<const char*>(&v), sizeof v); };
  for (float z : {0.0f, -0.05f, -0.1f}) put(1.0f), put(2.0f), put(z), put(std::uint8_t(7));
  put(std::int32_t(1)), put(std::int32_t(2)), put(std::int32_t(0)), put(std::int32_t(1));
  const std::string binary = tempPath("binary.ply");
  writeBytes(binary, bin);
  const Polylines b = readStrandFile(binary);
  ASSERT_EQ(b.size(), 1u);
  ASSERT_EQ(b[0].size(), 3u);
  EXPECT_EQ(b[0][0], Vec3(1, 2, 0));  // from the lower-numbered end
  EXPECT_NEAR(b[0][2].z(), -0.1, 1e-7);

  const std::string bad = tempPath("bad.ply");
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 4\nproperty double x\nproperty double y\n"
      "property double z\n";
  writeText(bad, head +
                     "element edge 3\nproperty int vertex1\nproperty int vertex2\n"
                     "end_header\n0 0 0\n0 0 1\n0 1 0\n1 0 0\n0 1\n0 2\n0 3\n");
  expectRefused(bad, "a branch");
  writeText(bad, head +
                     "element edge 3\nproperty int vertex1\nproperty int vertex2\n"
                     "end_header\n0 0 0\n0 0 1\n0 1 0\n1 0 0\n0 1\n1 2\n2 0\n");
  expectRefused(bad, "closed loop");
  writeText(bad, head +
                     "element edge 1\nproperty int vertex1\nproperty int vertex2\n"
                     "end_header\n0 0 0\n0 0 1\n0 1 0\n1 0 0\n0 9\n");
  expectRefused(bad, "edge to vertex 9");
  writeText(bad, head +
                     "element face 1\nproperty list uchar int vertex_indices\n"
                     "end_header\n0 0 0\n0 0 1\n0 1 0\n1 0 0\n3 0 1 2\n");
  expectRefused(bad, "a mesh, not strands");
  writeText(bad, head +
                     "element edge 2\nproperty int vertex1\nproperty int vertex2\n"
                     "end_header\n0 0 0\n0 0 1\n0 1 0\n1 0 0\n0 1\n");
  expectRefused(bad, "truncated");
  writeText(bad, "ply\nformat binary_big_endian 1.0\nelement vertex 0\nend_header\n");
  expectRefused(bad, "binary_big_endian");
  writeText(bad, "solid x\n");
  expectRefused(bad, "not a PLY file");
}

TEST(StrandFile, BadFilesRefused) {
  expectRefused(tempPath("missing.strands"), "cannot be opened");
  const std::string text = tempPath("bad.strands");
  writeText(text, "3\n0 0 0\n0 0 -0.05\n");
  expectRefused(text, "truncated");
  writeText(text, "2\n0 0 0\nnan 0 -0.05\n");
  expectRefused(text, "not finite");
  writeText(text, "2\n0 0 0\n0 0 0\n");
  expectRefused(text, "zero length");
  writeText(text, "3\n0 0 0\n0 0 0\n0 0 -0.1\n");
  expectRefused(text, "duplicates");
  writeText(text, "2\n0 0 zero\n0 0 -0.1\n");
  expectRefused(text, "not a number");
  writeText(text, "1\n0 0 0\n");
  expectRefused(text, "at least two vertices");
  {
    std::ofstream many(text);
    for (int s = 0; s <= kMaxGroomStrands; ++s) many << "2\n0 0 " << s << "\n1 0 " << s << "\n";
  }
  expectRefused(text, "more than the limit");

  const Polylines two{{Vec3(0, 0, 0), Vec3(0, 0, -0.1)}, {Vec3(1, 0, 0), Vec3(1, 0, -0.1)}};
  const std::string hair = tempPath("bad.hair");
  const std::string good = hairBytes(two, true, 0);
  writeBytes(hair, good.substr(0, 100));
  expectRefused(hair, "truncated header");
  writeBytes(hair, good.substr(0, good.size() - 4));
  expectRefused(hair, "truncated");
  std::string bytes = good;
  bytes[0] = 'X';
  writeBytes(hair, bytes);
  expectRefused(hair, "signature");
  bytes = good;
  const std::uint32_t many = kMaxGroomStrands + 1;
  std::memcpy(&bytes[4], &many, 4);
  writeBytes(hair, bytes);
  expectRefused(hair, "more than the limit");
  bytes = good;
  const std::uint32_t points = 5;
  std::memcpy(&bytes[8], &points, 4);
  writeBytes(hair, bytes + std::string(12, '\0'));
  expectRefused(hair, "header says");
  writeBytes(hair, hairBytes({{Vec3(0, 0, 0), Vec3(0, 0, 0), Vec3(0, 0, 1)}}, true, 0));
  expectRefused(hair, "duplicates");
  writeBytes(hair, hairBytes({{Vec3(0, 0, 0), Vec3(std::nan(""), 0, 0)}}, true, 0));
  expectRefused(hair, "not finite");
}

}  // namespace
}  // namespace chs::rod
