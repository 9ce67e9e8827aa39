// Host-only simulation: the true geometry of a simulated world (a table and objects made
// of analytic primitives and triangle meshes). Used to render depth images and to judge grasps.
// Internally double precision; fg::Pose / fg::Vec3 (float) convert at the interfaces.
#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "fg/core/types.hpp"

namespace fg::sim {

using V3 = Eigen::Vector3d;
using M3 = Eigen::Matrix3d;

//! Rigid transform a_T_b (double): a point p in b is R p + t in a.
struct Rigid {
  M3 R = M3::Identity();
  V3 t = V3::Zero();

  V3 apply(const V3& p) const { return R * p + t; }
  V3 inverse_apply(const V3& p) const { return R.transpose() * (p - t); }
  Rigid inverse() const;
  Rigid operator*(const Rigid& b) const;

  static Rigid from_pose(const fg::Pose& p);
  fg::Pose to_pose() const;
  static Rigid translation(const V3& t);
  static Rigid rot_x(double angle);
  static Rigid rot_y(double angle);
  static Rigid rot_z(double angle);
};

//! Axis-aligned box in world.
struct Aabb {
  V3 lo = V3::Constant(1e30);
  V3 hi = V3::Constant(-1e30);

  bool empty() const { return lo.x() > hi.x(); }
  void extend(const Aabb& b);
  void extend(const V3& p);
  V3 centre() const { return 0.5 * (lo + hi); }
  V3 size() const { return hi - lo; }
  //! Slab test with a precomputed 1/d (components may be +-inf). Narrows [t0, t1].
  [[nodiscard]] bool ray_overlap(const V3& o, const V3& inv_d, double& t0, double& t1) const;
};

class TriangleMesh;  // sim/obj_mesh.hpp

enum class Shape { box, cylinder, sphere, ellipsoid, mesh };
const char* shape_name(Shape s);
[[nodiscard]] bool shape_from_name(const std::string& name, Shape& out);

//! One primitive solid or triangle mesh with its world_T_shape pose.
//! size: box = half extents; cylinder = (radius, radius, half height), axis = shape z;
//! sphere = (radius, radius, radius); ellipsoid = semi-axes along shape x, y, z;
//! mesh = half the size of the mesh's own bounding box (for information only).
struct Part {
  std::string name;
  Shape shape = Shape::box;
  V3 size = V3::Zero();
  Rigid world_T_shape;
  //! Can be gripped on its own (false for small features such as nozzles and stands).
  bool graspable = true;
  //! Shape::mesh: the mesh in shape coordinates (shared, never modified).
  std::shared_ptr<const TriangleMesh> triangle_mesh;

  static Part box(std::string name, const V3& half_extents, const Rigid& pose);
  static Part cylinder(std::string name, double radius, double half_height, const Rigid& pose);
  static Part sphere(std::string name, double radius, const V3& centre);
  static Part ellipsoid(std::string name, const V3& semi_axes, const Rigid& pose);
  //! Throws std::invalid_argument when mesh is null.
  static Part mesh(std::string name, std::shared_ptr<const TriangleMesh> mesh, const Rigid& pose);

  double radius() const { return size.x(); }       //!< cylinder, sphere
  double half_height() const { return size.z(); }  //!< cylinder

  Aabb aabb() const;
  //! Signed distance (negative inside). Exact for box, cylinder and sphere; for an
  //! ellipsoid a 1-Lipschitz lower bound of |distance| with the exact sign; for a mesh
  //! TriangleMesh::signed_distance (exact outside; a union of groups: min over them).
  double sdf(const V3& p) const;
  //! First point of the solid along o + t d (d need not be unit) with t in [tmin, tmax]:
  //! the entry point, or tmin when o + tmin d is already inside (then *inside = true).
  //! normal: outward unit normal at the entry (undefined when inside).
  [[nodiscard]] bool intersect(const V3& o, const V3& d, double tmin, double tmax, double& t, V3& normal,
                               bool* inside = nullptr) const;
  //! Extent of the part along the unit direction u (its width between two planes normal to u).
  double width_along(const V3& u) const;
  //! Exact distance from p to the solid (0 inside), for every shape: unlike sdf, exact for
  //! an ellipsoid too, where sdf's bound can be half the distance a few centimetres out.
  double distance(const V3& p) const;
  //! [lo, hi] of the part's points projected on the unit direction u.
  void project(const V3& u, double& lo, double& hi) const;
};

//! A named object: a union of parts.
struct Object {
  std::string name;
  std::string kind;
  std::vector<Part> parts;
  //! Share of the sensor's infrared light the surface sends back (1: white; a dark
  //! surface returns too little and its pixels go missing: NoiseModel::dark_dropout).
  double albedo = 1.0;

  Aabb aabb() const;
  double sdf(const V3& p) const;                        //!< min over parts
  double distance(const V3& p) const;                   //!< exact, 0 inside (Part::distance)
  V3 sdf_gradient(const V3& p, double h = 1e-4) const;  //!< central differences (unnormalized)
  V3 normal(const V3& p, double h = 1e-4) const;        //!< normalized gradient
  [[nodiscard]] bool intersect(const V3& o, const V3& d, double tmin, double tmax, double& t, V3& normal,
                               int* part = nullptr) const;
  double width_along(const V3& u) const;  //!< extent of the union along u
};

//! The table: a box whose top face is z = height, finite in x and y (legs not modelled).
struct Table {
  double height = 0.0;
  double x_min = 0.1, x_max = 1.1;
  double y_min = -0.6, y_max = 0.6;
  double thickness = 0.03;
  double albedo = 1.0;  //!< as Object::albedo
  Part as_part() const;
};

struct RayHit {
  double t = 0.0;
  V3 normal = V3::Zero();
  int object = -2;  //!< index into World::objects; -1 = table; -2 = nothing
  int part = -1;
  bool inside = false;  //!< the ray started inside the solid
};

constexpr int kHitTable = -1;
constexpr int kHitNothing = -2;

struct World {
  Table table;
  bool has_table = true;
  std::vector<Object> objects;

  double sdf_objects(const V3& p) const;  //!< min over objects (table excluded)
};

//! Ray casting against a world with per-object and per-part bounding-box early-outs.
//! Keeps a reference to the world: the world must outlive it and not change.
class Raycaster {
 public:
  explicit Raycaster(const World& world);
  //! First hit along o + t d, t in [tmin, tmax]. only_object >= 0 restricts to one object
  //! (table excluded); -1 = everything.
  [[nodiscard]] bool cast(const V3& o, const V3& d, double tmin, double tmax, RayHit& hit, int only_object = -1) const;

 private:
  const World& world_;
  Part table_part_;
  Aabb table_box_;
  std::vector<Aabb> object_boxes_;
  std::vector<std::vector<Aabb>> part_boxes_;
};

//! Optical-frame world_T_sensor (z forward to the target, x right, y down) for a camera at
//! eye looking at target; up is the world up (z). Falls back to another up when degenerate.
Rigid look_at(const V3& eye, const V3& target, const V3& up = V3(0, 0, 1));

inline V3 to_v3(const fg::Vec3& v) { return v.cast<double>(); }
inline fg::Vec3 to_vec3(const V3& v) { return v.cast<float>(); }

}  // namespace fg::sim
