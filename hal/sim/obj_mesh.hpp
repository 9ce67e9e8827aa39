// Host-only simulation: triangle meshes read from Wavefront OBJ files (the YCB objects), with
// a bounding-volume hierarchy for ray casts and distance queries. Coordinates are the
// file's own (metres for the YCB files); a Part places the mesh in the world.
#pragma once
#include <array>
#include <memory>
#include <string>
#include <vector>

#include "sim/sim_world.hpp"

namespace fg::sim {

//! A triangle mesh made of one or more groups (OBJ `o` / `g`). Each group is taken as a
//! closed solid of its own and the mesh as their union (a V-HACD file is a set of
//! overlapping convex hulls). Immutable once built: share it as shared_ptr<const>.
//! Outward normals are the winding normals (b - a) x (c - a), reversed for a group whose
//! winding encloses a negative volume.
class TriangleMesh {
 public:
  using Triangle = std::array<int, 3>;

  TriangleMesh() = default;
  //! Builds the hierarchy and the pseudo-normals. The indices must be valid vertex indices;
  //! groups holds one id in [0, group_names.size()) per triangle. source names the file.
  TriangleMesh(std::vector<V3> vertices, std::vector<Triangle> triangles, std::vector<int> groups,
               std::vector<std::string> group_names, std::string source);

  const std::string& source() const { return source_; }
  const std::vector<V3>& vertices() const { return vertices_; }
  const std::vector<Triangle>& triangles() const { return triangles_; }
  const std::vector<int>& groups() const { return groups_; }  //!< group id of each triangle
  const std::vector<std::string>& group_names() const { return group_names_; }

  const Aabb& bounds() const { return bounds_; }
  //! [lo, hi] of the vertices projected on u.
  void project(const V3& u, double& lo, double& hi) const;
  //! max - min of the vertices projected on the unit direction u.
  double extent_along(const V3& u) const;

  //! First triangle met by o + t d with t in [tmin, tmax] (d need not be unit; Moller-Trumbore).
  //! normal: that triangle's outward unit normal.
  [[nodiscard]] bool intersect(const V3& o, const V3& d, double tmin, double tmax, double& t, V3& normal,
                               int* triangle = nullptr) const;
  //! Distance to the nearest triangle.
  double distance(const V3& p) const;
  //! Signed distance, negative inside: per group, the distance to its nearest triangle with
  //! the sign of the angle-weighted pseudo-normal of the nearest feature (face, edge or
  //! vertex; Baerentzen & Aanaes 2005); the min over the groups (their union).
  double signed_distance(const V3& p) const;
  bool inside(const V3& p) const { return signed_distance(p) < 0.0; }

  //! Enclosed volume and its centroid (the centre of mass at uniform density); overlapping
  //! groups count twice. Centroid = vertex mean when the volume is zero.
  double volume() const { return volume_; }
  const V3& centroid() const { return centroid_; }

 private:
  struct Node {
    Aabb box;
    int first = 0;  //!< leaf: first index into order_
    int count = 0;  //!< leaf: number of triangles (0 = inner node: children this + 1 and right)
    int right = 0;
  };
  struct Nearest;

  int build(int begin, int end, const std::vector<V3>& centres);
  void nearest_in_group(int group, const V3& p, Nearest& best) const;
  double sign_of(const V3& p, const Nearest& n) const;

  std::string source_;
  std::vector<V3> vertices_;
  std::vector<Triangle> triangles_;
  std::vector<int> groups_;
  std::vector<std::string> group_names_;
  std::vector<V3> face_normals_;                   //!< unit outward (zero when degenerate)
  std::vector<std::array<V3, 3>> corner_normals_;  //!< vertex pseudo-normals at each corner
  std::vector<std::array<V3, 3>> edge_normals_;    //!< edge k runs from corner k to k + 1
  std::vector<Node> nodes_;
  std::vector<int> order_;  //!< triangle indices in leaf order, grouped by group
  std::vector<int> roots_;  //!< root node of each group
  Aabb bounds_;
  double volume_ = 0.0;
  V3 centroid_ = V3::Zero();
};

//! Largest vertex count load_obj accepts.
constexpr size_t kObjMaxVertices = 2'000'000;

//! Reads `v` and `f` lines of an OBJ file (faces `f 1 2 3`, `1/2`, `1//3`, `1/2/3`, negative
//! = relative indices, polygons fan-triangulated); `o` / `g` start groups; `vt`, `vn`,
//! `mtllib`, `usemtl`, `s`, comments and unknown lines are ignored (a missing .mtl is
//! normal). On failure returns false with "FILE:LINE: problem" in error; out is untouched.
[[nodiscard]] bool load_obj(const std::string& path, TriangleMesh& out, std::string& error);
//! The same from the text of a file; name stands for the file in messages and source().
[[nodiscard]] bool load_obj_text(const std::string& text, const std::string& name, TriangleMesh& out,
                                 std::string& error);
//! load_obj once per path and process (thread-safe); nullptr and error on failure.
std::shared_ptr<const TriangleMesh> load_obj_cached(const std::string& path, std::string& error);

//! A face of the convex hull on which the mesh rests stably: the centroid, projected along
//! down, falls inside it. down = the face's outward unit normal (towards the table).
struct RestingFace {
  V3 down = -V3::UnitZ();
  double area = 0.0;
};
//! Every stable resting face of the mesh's convex hull (coplanar hull triangles merged).
//! Empty when the vertices are flat.
std::vector<RestingFace> resting_faces(const TriangleMesh& mesh);

}  // namespace fg::sim
