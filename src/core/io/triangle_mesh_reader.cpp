#include "cloth_hair_sim/core/io/triangle_mesh_reader.h"

#include <array>
#include <filesystem>
#include <map>
#include <sstream>

#include <assimp/postprocess.h>
#include <assimp/scene.h>
#include <assimp/Importer.hpp>

#include "cloth_hair_sim/core/common/input_error.h"
#include "cloth_hair_sim/core/io/mesh_file_check.h"

namespace chs {

namespace {

struct Collector {
  Eigen::Vector3d scale;
  TriangleMesh mesh;
  std::map<std::array<double, 3>, int> index;  // merges corners written with equal coordinates

  int vertex(const aiVector3D& p) {
    const std::array<double, 3> key{scale.x() * p.x, scale.y() * p.y, scale.z() * p.z};
    const auto [it, added] = index.emplace(key, mesh.numVertices());
    if (added) mesh.vertices.emplace_back(key[0], key[1], key[2]);
    return it->second;
  }

  void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent) {
    const aiMatrix4x4 transform = parent * node.mTransformation;
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      const aiMesh& m = *scene.mMeshes[node.mMeshes[i]];
      for (unsigned f = 0; f < m.mNumFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines bound no volume
        std::array<int, 3> tri;
        for (int k = 0; k < 3; ++k) tri[k] = vertex(transform * m.mVertices[face.mIndices[k]]);
        mesh.triangles.push_back(tri);
      }
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c) collect(scene, *node.mChildren[c], transform);
  }
};

}  // namespace

TriangleMesh readTriangleMesh(const std::string& path, const Eigen::Vector3d& scale) {
  if (!scale.allFinite() || !(scale.array() > 0.0).all()) {
    std::ostringstream s;
    s << path << ": mesh scale must be positive and finite, got (" << scale.transpose() << ")";
    throw InputError(s.str());
  }
  std::error_code ec;
  if (!std::filesystem::is_regular_file(path, ec)) throw InputError(path + ": no such mesh file");
  checkMeshFileComplete(path);
  Assimp::Importer importer;
  const aiScene* scene = importer.ReadFile(path, aiProcess_Triangulate);
  if (!scene || !scene->mRootNode || (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE))
    throw InputError(path + ": cannot read mesh: " + importer.GetErrorString());
  Collector c{scale, {}, {}};
  c.collect(*scene, *scene->mRootNode, aiMatrix4x4());
  if (c.mesh.triangles.empty()) throw InputError(path + ": the file holds no triangles");
  return std::move(c.mesh);
}

}  // namespace chs
