#include "unit_meshes.hpp"

#include <cmath>

namespace rdsim::render {
namespace {

using Eigen::Vector3f;

struct MeshBuilder {
  UnitMeshes& m;
  int first_vertex = 0;  // of the mesh being built: indices are relative to it

  int vertex(const Vector3f& p, const Vector3f& n) {
    m.positions.push_back(p);
    m.normals.push_back(n);
    return static_cast<int>(m.positions.size()) - 1 - first_vertex;
  }
  void triangle(int a, int b, int c) {
    m.indices.insert(m.indices.end(), {static_cast<std::uint16_t>(a), static_cast<std::uint16_t>(b),
                                       static_cast<std::uint16_t>(c)});
  }
};

Vector3f on_sphere(float polar, float azimuth) {
  return {std::sin(polar) * std::cos(azimuth), std::sin(polar) * std::sin(azimuth),
          std::cos(polar)};
}

void add_box(MeshBuilder& b) {
  for (int axis = 0; axis < 3; ++axis) {
    for (float sign : {1.0f, -1.0f}) {
      Vector3f n = Vector3f::Zero();
      n[axis] = sign;
      // u, v span the face with u x v = n: counter-clockwise seen from outside.
      Vector3f u = Vector3f::Zero(), v = Vector3f::Zero();
      u[(axis + 1) % 3] = 1.0f;
      v[(axis + 2) % 3] = sign;
      const int i0 = b.vertex(n - u - v, n), i1 = b.vertex(n + u - v, n);
      const int i2 = b.vertex(n + u + v, n), i3 = b.vertex(n - u + v, n);
      b.triangle(i0, i1, i2);
      b.triangle(i0, i2, i3);
    }
  }
}

void add_cylinder(MeshBuilder& b) {
  constexpr int n = kCylinderSegments;
  const float step = 2.0f * static_cast<float>(M_PI) / n;
  auto radial = [&](int i) { return Vector3f(std::cos(step * i), std::sin(step * i), 0.0f); };
  const Vector3f up(0, 0, 1);
  // Side: smooth radial normals; caps get their own flat-normal copies of the rim.
  const int side = b.vertex(radial(0) - up, radial(0));
  for (int i = 0; i < n; ++i) {
    if (i > 0) b.vertex(radial(i) - up, radial(i));
    b.vertex(radial(i) + up, radial(i));
  }
  auto side_bottom = [&](int i) { return side + 2 * (i % n); };
  for (int i = 0; i < n; ++i) {
    b.triangle(side_bottom(i), side_bottom(i + 1), side_bottom(i + 1) + 1);
    b.triangle(side_bottom(i), side_bottom(i + 1) + 1, side_bottom(i) + 1);
  }
  for (float sign : {1.0f, -1.0f}) {
    const Vector3f normal = sign * up;
    const int centre = b.vertex(normal, normal);
    for (int i = 0; i < n; ++i) b.vertex(radial(i) + normal, normal);
    for (int i = 0; i < n; ++i) {
      const int a = centre + 1 + i, c = centre + 1 + (i + 1) % n;
      if (sign > 0) b.triangle(centre, a, c);
      else b.triangle(centre, c, a);
    }
  }
}

// Rows 0..last_stack of a kSphereStacks x kSphereSlices sphere; polar angle 0 is +z.
void add_sphere_rows(MeshBuilder& b, int last_stack) {
  const float dp = static_cast<float>(M_PI) / kSphereStacks;
  const float da = 2.0f * static_cast<float>(M_PI) / kSphereSlices;
  const int pole = b.vertex(Vector3f::UnitZ(), Vector3f::UnitZ());
  const int ring0 = pole + 1;
  for (int s = 1; s <= last_stack; ++s) {
    const bool south_pole = s == kSphereStacks;
    for (int k = 0; k < (south_pole ? 1 : kSphereSlices); ++k) {
      const Vector3f p = on_sphere(dp * static_cast<float>(s), da * static_cast<float>(k));
      b.vertex(p, p);
    }
  }
  // Index of row s, slice k; the poles are single vertices.
  auto at = [&](int s, int k) {
    if (s == 0) return pole;
    if (s == kSphereStacks) return ring0 + (s - 1) * kSphereSlices;
    return ring0 + (s - 1) * kSphereSlices + k % kSphereSlices;
  };
  for (int s = 0; s < last_stack; ++s) {
    for (int k = 0; k < kSphereSlices; ++k) {
      const int upper0 = at(s, k), upper1 = at(s, k + 1);
      const int lower0 = at(s + 1, k), lower1 = at(s + 1, k + 1);
      // The pole rows would give zero-area triangles; skip them.
      if (s != 0) b.triangle(upper0, lower1, upper1);
      if (s + 1 != kSphereStacks) b.triangle(upper0, lower0, lower1);
    }
  }
}

void add_quad(MeshBuilder& b) {
  const Vector3f n(0, 0, 1);
  const int i0 = b.vertex({-1, -1, 0}, n), i1 = b.vertex({1, -1, 0}, n);
  const int i2 = b.vertex({1, 1, 0}, n), i3 = b.vertex({-1, 1, 0}, n);
  b.triangle(i0, i1, i2);
  b.triangle(i0, i2, i3);
}

}  // namespace

UnitMeshes build_unit_meshes() {
  UnitMeshes meshes;
  MeshBuilder builder{meshes};
  auto record = [&](UnitMesh which, auto&& add) {
    const int first_vertex = static_cast<int>(meshes.positions.size());
    const int first_index = static_cast<int>(meshes.indices.size());
    builder.first_vertex = first_vertex;
    add();
    meshes.ranges[static_cast<int>(which)] = {
        first_vertex, static_cast<int>(meshes.positions.size()) - first_vertex, first_index,
        static_cast<int>(meshes.indices.size()) - first_index};
  };
  record(UnitMesh::Box, [&] { add_box(builder); });
  record(UnitMesh::Cylinder, [&] { add_cylinder(builder); });
  record(UnitMesh::Sphere, [&] { add_sphere_rows(builder, kSphereStacks); });
  record(UnitMesh::Hemisphere, [&] { add_sphere_rows(builder, kSphereStacks / 2); });
  record(UnitMesh::Quad, [&] { add_quad(builder); });
  return meshes;
}

}  // namespace rdsim::render
