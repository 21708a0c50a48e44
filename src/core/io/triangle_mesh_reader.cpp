#include "cloth_hair_sim/core/io/triangle_mesh_reader.h"

#include <array>
#include <filesystem>
#include <map>
#include <set>
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
  std::set<std::string> parts;  // node or mesh names to keep; empty keeps all
  TriangleMesh mesh;
  std::map<std::array<double, 3>, int> index;  // merges corners written with equal coordinates
  std::set<std::string> found, names;          // parts met; every node and mesh name

  int vertex(const aiVector3D& p) {
    const std::array<double, 3> key{scale.x() * p.x, scale.y() * p.y, scale.z() * p.z};
    const auto [it, added] = index.emplace(key, mesh.numVertices());
    if (added) mesh.vertices.emplace_back(key[0], key[1], key[2]);
    return it->second;
  }

  // A kept node keeps its meshes and its whole subtree.
  bool keep(const aiString& name, bool inherited) {
    names.insert(name.C_Str());
    if (!parts.count(name.C_Str())) return inherited;
    found.insert(name.C_Str());
    return true;
  }

  void collect(const aiScene& scene, const aiNode& node, const aiMatrix4x4& parent, bool kept) {
    const aiMatrix4x4 transform = parent * node.mTransformation;
    kept = keep(node.mName, kept);
    for (unsigned i = 0; i < node.mNumMeshes; ++i) {
      const aiMesh& m = *scene.mMeshes[node.mMeshes[i]];
      if (!keep(m.mName, kept)) continue;
      for (unsigned f = 0; f < m.mNumFaces; ++f) {
        const aiFace& face = m.mFaces[f];
        if (face.mNumIndices != 3) continue;  // points and lines bound no volume
        std::array<int, 3> tri;
        for (int k = 0; k < 3; ++k) tri[k] = vertex(transform * m.mVertices[face.mIndices[k]]);
        mesh.triangles.push_back(tri);
      }
    }
    for (unsigned c = 0; c < node.mNumChildren; ++c)
      collect(scene, *node.mChildren[c], transform, kept);
  }
};

}  // namespace

TriangleMesh readTriangleMesh(const std::string& path, const Eigen::Vector3d& scale,
                              const std::vector<std::string>& parts) {
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
  Collector c{scale, {parts.begin(), parts.end()}, {}, {}, {}, {}};
  c.collect(*scene, *scene->mRootNode, aiMatrix4x4(), parts.empty());
  for (const auto& p : parts)
    if (!c.found.count(p)) {
      std::string known;
      for (const auto& n : c.names)
        if (!n.empty()) known += (known.empty() ? "" : ", ") + n;
      throw InputError(path + ": no node or mesh named '" + p + "' (the file has: " + known + ")");
    }
  if (c.mesh.triangles.empty()) throw InputError(path + ": the file holds no triangles");
  return std::move(c.mesh);
}

}  // namespace chs
