#include "cloth_hair_sim/core/io/mesh_reader.h"

#include <cmath>
#include <filesystem>
#include <string>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/mesh_file_check.h"
#include "cloth_hair_sim/core/mesh/mesh_check.h"
#include "cloth_hair_sim/core/mesh/mesh_weld.h"
#include "cloth_hair_sim/core/subdiv/quad_conversion.h"

namespace chs {

namespace {

void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, double scale,
             const std::string& path, PolygonMesh& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[i]];
    const int base = static_cast<int>(out.vertices.size());
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out.vertices.emplace_back(scale * p.x, scale * p.y, scale * p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices < 3) continue;  // stray points and lines carry no cloth
      std::vector<int> corners;
      for (unsigned k = 0; k < face.mNumIndices; ++k)
        corners.push_back(base + static_cast<int>(face.mIndices[k]));
      out.faces.push_back(std::move(corners));
    }
  }
  for (unsigned c = 0; c < node.mNumChildren; ++c)
    collect(scene, *node.mChildren[c], transform, scale, path, out);
}

}  // namespace

QuadMesh readQuadMesh(const std::string& path, double scale) {
  if (!std::isfinite(scale) || scale <= 0.0)
    throw InputError(path + ": scale must be positive, got " + std::to_string(scale));
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such mesh file");
  checkMeshFileComplete(path);
  Assimp::Importer importer;
  // No post-processing: any triangulating preset would destroy the quads.
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw InputError(path + ": cannot read mesh: " + importer.GetErrorString());
  PolygonMesh polygons;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), scale, path, polygons);
  if (polygons.faces.empty()) throw InputError(path + ": the file holds no faces");
  // Weld relative to the garment's size: exporters round positions to ~6-7 digits.
  Eigen::Vector3d lo = polygons.vertices.front(), hi = lo;
  for (const auto& p : polygons.vertices) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  weldVertices(polygons, 1e-7 * (hi - lo).norm());
  try {
    // Quads are kept as they are; any other polygon makes the whole mesh take one
    // Catmull-Clark step (Han section 5.4), which gives quads with the same limit surface.
    QuadMesh mesh = toQuadControlMesh(polygons);
    checkMesh(mesh);
    return mesh;
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
}

}  // namespace chs
