#include "cloth_hair_sim/core/io/mesh_reader.h"

#include <cmath>
#include <filesystem>
#include <string>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/mesh/mesh_check.h"
#include "cloth_hair_sim/core/mesh/mesh_weld.h"

namespace chs {

namespace {

void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, double scale,
             const std::string& path, QuadMesh& out) {
  const aiMatrix4x4 transform = parent * node.mTransformation;
  for (unsigned i = 0; i < node.mNumMeshes; ++i) {
    const aiMesh& mesh = *scene.mMeshes[node.mMeshes[i]];
    const int base = out.numVertices();
    for (unsigned v = 0; v < mesh.mNumVertices; ++v) {
      const aiVector3D p = transform * mesh.mVertices[v];
      out.vertices.emplace_back(scale * p.x, scale * p.y, scale * p.z);
    }
    for (unsigned f = 0; f < mesh.mNumFaces; ++f) {
      const aiFace& face = mesh.mFaces[f];
      if (face.mNumIndices < 3) continue;  // stray points and lines carry no cloth
      if (face.mNumIndices != 4)
        throw InputError(path + ": face " + std::to_string(f) + " of mesh '" + mesh.mName.C_Str() +
                         "' has " + std::to_string(face.mNumIndices) +
                         " corners; only quads are supported (the FEM shell is quad-based; "
                         "remesh the garment with quads)");
      out.quads.push_back(
          {base + static_cast<int>(face.mIndices[0]), base + static_cast<int>(face.mIndices[1]),
           base + static_cast<int>(face.mIndices[2]), base + static_cast<int>(face.mIndices[3])});
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
  Assimp::Importer importer;
  // No post-processing: any triangulating preset would destroy the quads.
  const aiScene* scene = importer.ReadFile(path, 0);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw InputError(path + ": cannot read mesh: " + importer.GetErrorString());
  QuadMesh mesh;
  collect(*scene, *scene->mRootNode, aiMatrix4x4(), scale, path, mesh);
  if (mesh.quads.empty()) throw InputError(path + ": the file holds no quads");
  // Weld relative to the garment's size: exporters round positions to ~6-7 digits.
  Eigen::Vector3d lo = mesh.vertices.front(), hi = lo;
  for (const auto& p : mesh.vertices) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  weldVertices(mesh, 1e-7 * (hi - lo).norm());
  try {
    checkMesh(mesh);
  } catch (const InputError& e) {
    throw InputError(path + ": " + e.what());
  }
  return mesh;
}

}  // namespace chs
