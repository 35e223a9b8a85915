// Mesh files through Assimp (rdsim/sim/mesh_file.hpp).
#include "rdsim/sim/mesh_file.hpp"

#include <assimp/Importer.hpp>
#include <assimp/config.h>
#include <assimp/material.h>
#include <assimp/postprocess.h>
#include <assimp/scene.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <filesystem>
#include <system_error>
#include <utility>
#include <vector>

#include "assimp_input.hpp"
#include "dae_check.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/input_file.hpp"

namespace rdsim {

MeshFormat mesh_format(const std::string& file) {
  std::string ext = std::filesystem::path(file).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".dae") return MeshFormat::Dae;
  throw Error(file + ": unsupported mesh format \"" + ext + "\" (rdsim reads .stl, .obj and .dae)");
}

namespace {

using Format = MeshFormat;

const char* format_name(Format f) { return f == Format::Stl ? "STL" : f == Format::Obj ? "OBJ" : "DAE"; }

Eigen::Matrix4f to_eigen(const aiMatrix4x4& m) {
  Eigen::Matrix4f out;
  out << m.a1, m.a2, m.a3, m.a4, m.b1, m.b2, m.b3, m.b4, m.c1, m.c2, m.c3, m.c4, m.d1, m.d2, m.d3, m.d4;
  return out;
}

// Assimp turns every DAE into its own y-up convention (rotating a Z_UP file's root node); URDF is
// z-up, so the rotation taking +y to +z (90 degrees about x) undoes that for Z_UP files and
// stands a Y_UP file upright. STL and OBJ are left as they are.
Eigen::Matrix4f up_axis_fix(Format f) {
  Eigen::Matrix4f m = Eigen::Matrix4f::Identity();
  if (f == Format::Dae) m.topLeftCorner<3, 3>() = Eigen::AngleAxisf(static_cast<float>(M_PI / 2), Eigen::Vector3f::UnitX()).toRotationMatrix();
  return m;
}

// A material's diffuse colour, or none for Assimp's stand-in material of a file without any.
bool diffuse_of(const aiScene& scene, unsigned index, Eigen::Vector3f& rgb) {
  if (index >= scene.mNumMaterials) return false;
  const aiMaterial& m = *scene.mMaterials[index];
  aiString name;
  if (m.Get(AI_MATKEY_NAME, name) == AI_SUCCESS && std::string(name.C_Str()) == AI_DEFAULT_MATERIAL_NAME) return false;
  aiColor4D c;
  if (m.Get(AI_MATKEY_COLOR_DIFFUSE, c) != AI_SUCCESS) return false;
  rgb = Eigen::Vector3f(c.r, c.g, c.b).cwiseMax(0.0f).cwiseMin(1.0f);
  return rgb.allFinite();
}

// Triangles the scene's nodes place (a mesh used by two nodes counts twice), before processing.
std::size_t placed_triangles(const aiScene& scene) {
  std::size_t total = 0;
  std::vector<const aiNode*> stack{scene.mRootNode};
  while (!stack.empty()) {
    const aiNode* node = stack.back();
    stack.pop_back();
    for (unsigned i = 0; i < node->mNumMeshes; ++i)
      if (node->mMeshes[i] < scene.mNumMeshes) total += scene.mMeshes[node->mMeshes[i]]->mNumFaces;
    for (unsigned i = 0; i < node->mNumChildren; ++i) stack.push_back(node->mChildren[i]);
    if (total > max_mesh_triangles) break;
  }
  return total;
}

struct Converter {
  const aiScene& scene;
  Eigen::Matrix3f scale;  // diagonal
  TriangleMesh out;
  bool any_colour = false;
  std::vector<std::pair<std::size_t, std::size_t>> coloured;  // position ranges with file colours
  std::vector<Eigen::Vector3f> range_colour;

  void add(const aiMesh& m, const Eigen::Matrix4f& node) {
    if (!(m.mPrimitiveTypes & aiPrimitiveType_TRIANGLE) || !m.HasNormals()) return;
    const Eigen::Matrix3f linear = scale * node.topLeftCorner<3, 3>();
    const Eigen::Vector3f offset = scale * node.topRightCorner<3, 1>();
    const Eigen::Matrix3f normal_matrix = linear.inverse().transpose();
    const bool flip = linear.determinant() < 0.0f;  // a mirror: keep triangles wound outward
    const auto base = static_cast<std::uint32_t>(out.positions.size());
    for (unsigned i = 0; i < m.mNumVertices; ++i) {
      const aiVector3D& p = m.mVertices[i];
      const aiVector3D& n = m.mNormals[i];
      out.positions.push_back(linear * Eigen::Vector3f(p.x, p.y, p.z) + offset);
      Eigen::Vector3f normal = normal_matrix * Eigen::Vector3f(n.x, n.y, n.z);
      // Assimp leaves NaN normals on degenerate triangles: any direction will do there.
      normal = normal.allFinite() && normal.norm() > 0.0f ? normal.normalized() : Eigen::Vector3f::UnitZ();
      out.normals.push_back(normal);
    }
    for (unsigned f = 0; f < m.mNumFaces; ++f) {
      const aiFace& face = m.mFaces[f];
      if (face.mNumIndices != 3) continue;
      const std::uint32_t a = face.mIndices[0], b = face.mIndices[1], c = face.mIndices[2];
      if (a >= m.mNumVertices || b >= m.mNumVertices || c >= m.mNumVertices) continue;
      if (flip) out.indices.insert(out.indices.end(), {base + a, base + c, base + b});
      else out.indices.insert(out.indices.end(), {base + a, base + b, base + c});
    }
    Eigen::Vector3f rgb;
    if (diffuse_of(scene, m.mMaterialIndex, rgb)) {
      any_colour = true;
      coloured.emplace_back(base, out.positions.size());
      range_colour.push_back(rgb);
    }
  }

  void walk(const Eigen::Matrix4f& root) {
    std::vector<std::pair<const aiNode*, Eigen::Matrix4f>> stack{{scene.mRootNode, root}};
    while (!stack.empty()) {
      auto [node, parent] = stack.back();
      stack.pop_back();
      const Eigen::Matrix4f here = parent * to_eigen(node->mTransformation);
      for (unsigned i = 0; i < node->mNumMeshes; ++i)
        if (node->mMeshes[i] < scene.mNumMeshes) add(*scene.mMeshes[node->mMeshes[i]], here);
      for (unsigned i = 0; i < node->mNumChildren; ++i) stack.emplace_back(node->mChildren[i], here);
    }
    if (any_colour) {  // parts without a colour of their own draw in the element's colour (white here)
      out.colors.assign(out.positions.size(), Eigen::Vector3f::Ones());
      for (std::size_t r = 0; r < coloured.size(); ++r)
        std::fill(out.colors.begin() + static_cast<std::ptrdiff_t>(coloured[r].first),
                  out.colors.begin() + static_cast<std::ptrdiff_t>(coloured[r].second), range_colour[r]);
    }
  }
};

// The file's bytes under rdsim's rule for input files; "file not found" said plainly.
std::string read_whole(const std::string& file) {
  std::string bytes;
  try {
    InputFile in(file, max_mesh_bytes);
    bytes = in.read_rest();
  } catch (const FileOpenError& e) {
    if (e.code() == ENOENT) throw Error(file + ": file not found");
    throw;
  }
  if (bytes.empty()) throw Error(file + ": empty file");
  return bytes;
}

}  // namespace

TriangleMesh read_mesh_file(const std::string& file, const Eigen::Vector3d& scale) {
  const Format format = mesh_format(file);
  if (!scale.allFinite() || !(scale.cwiseAbs().minCoeff() > 0.0))
    throw Error(file + ": scale (" + std::to_string(scale.x()) + " " + std::to_string(scale.y()) + " " +
                std::to_string(scale.z()) + ") must be finite and non-zero in x, y and z");
  std::string bytes = read_whole(file);
  if (format == Format::Dae) check_dae_file(bytes, file);

  Assimp::Importer importer;
  // Files the mesh names (an OBJ's .mtl) share the mesh's byte budget.
  const std::uint64_t left = max_mesh_bytes - bytes.size();
  importer.SetIOHandler(new AssimpInput(file, std::move(bytes), left));  // the importer owns it
  importer.SetPropertyInteger(AI_CONFIG_PP_SBP_REMOVE, aiPrimitiveType_POINT | aiPrimitiveType_LINE);
  importer.SetPropertyFloat(AI_CONFIG_PP_GSN_MAX_SMOOTHING_ANGLE, 45.0f);
  // Read first, count, then process: the processing steps cost far more than the reading.
  const aiScene* scene = importer.ReadFile(file, aiProcess_ValidateDataStructure);
  const std::string what = std::string("not a readable ") + format_name(format) + " file: ";
  if (!scene || !scene->mRootNode) {
    std::string why = importer.GetErrorString();
    if (why.empty()) why = "Assimp read nothing";
    throw Error(file + ": " + what + one_line(why, 200));
  }
  if (scene->mFlags & AI_SCENE_FLAGS_INCOMPLETE) throw Error(file + ": " + what + "the file holds no complete mesh");
  const std::size_t triangles = placed_triangles(*scene);
  if (triangles > max_mesh_triangles)
    throw Error(file + ": more than " + std::to_string(max_mesh_triangles) + " triangles (the limit for one mesh file)");
  scene = importer.ApplyPostProcessing(aiProcess_Triangulate | aiProcess_SortByPType | aiProcess_DropNormals |
                                       aiProcess_GenSmoothNormals | aiProcess_JoinIdenticalVertices);
  if (!scene || !scene->mRootNode) throw Error(file + ": " + what + one_line(importer.GetErrorString(), 200));

  Converter convert{*scene, scale.cast<float>().asDiagonal().toDenseMatrix(), {}, false, {}, {}};
  convert.walk(up_axis_fix(format));
  TriangleMesh& mesh = convert.out;
  if (mesh.indices.empty()) throw Error(file + ": no triangles in the file");
  if (mesh.indices.size() / 3 > max_mesh_triangles)
    throw Error(file + ": more than " + std::to_string(max_mesh_triangles) + " triangles (the limit for one mesh file)");
  for (const Eigen::Vector3f& p : mesh.positions)
    if (!p.allFinite() || !(p.cwiseAbs().maxCoeff() <= max_mesh_extent))
      throw Error(file + ": a vertex is not finite or lies beyond " + std::to_string(static_cast<int>(max_mesh_extent)) +
                  " m of the origin after scaling");
  return std::move(mesh);
}

}  // namespace rdsim
