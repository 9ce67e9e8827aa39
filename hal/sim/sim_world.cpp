#include "sim/sim_world.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <utility>

#include "sim/obj_mesh.hpp"

namespace fg::sim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

// Real roots of a t^2 + b t + c = 0 (a > 0), t1 <= t2, computed in the stable form.
[[nodiscard]] bool solve_quadratic(double a, double b, double c, double& t1, double& t2) {
  const double disc = b * b - 4.0 * a * c;
  if (disc < 0.0) return false;
  const double sq = std::sqrt(disc);
  const double q = -0.5 * (b + (b >= 0.0 ? sq : -sq));
  if (q == 0.0) {
    t1 = t2 = -b / (2.0 * a);
    return true;
  }
  t1 = q / a;
  t2 = c / q;
  if (t1 > t2) std::swap(t1, t2);
  return true;
}

// Narrows [t_enter, t_exit] with the slab |o + t d| <= h on one axis. Returns false when empty.
// enter_changed is set when the lower bound moved.
[[nodiscard]] bool clip_slab(double o, double d, double h, double& t_enter, double& t_exit, bool& enter_changed) {
  enter_changed = false;
  if (d == 0.0) return std::abs(o) <= h;
  double ta = (-h - o) / d;
  double tb = (h - o) / d;
  if (ta > tb) std::swap(ta, tb);
  if (ta > t_enter) {
    t_enter = ta;
    enter_changed = true;
  }
  if (tb < t_exit) t_exit = tb;
  return t_enter <= t_exit;
}

// From the solid's interval [ta, tb] along the ray, picks the first point in [tmin, tmax].
[[nodiscard]] bool finish(double ta, double tb, double tmin, double tmax, double& t, bool& inside) {
  if (tb < tmin || ta > tmax || ta > tb) return false;
  if (ta >= tmin) {
    t = ta;
    inside = false;
  } else {
    t = tmin;
    inside = true;
  }
  return true;
}

}  // namespace

// ---------------------------------------------------------------------------- Rigid

Rigid Rigid::inverse() const {
  Rigid r;
  r.R = R.transpose();
  r.t = -(r.R * t);
  return r;
}

Rigid Rigid::operator*(const Rigid& b) const {
  Rigid r;
  r.R = R * b.R;
  r.t = R * b.t + t;
  return r;
}

Rigid Rigid::from_pose(const fg::Pose& p) {
  Rigid r;
  r.R = p.R.cast<double>();
  r.t = p.t.cast<double>();
  return r;
}

fg::Pose Rigid::to_pose() const {
  fg::Pose p;
  p.R = R.cast<float>();
  p.t = t.cast<float>();
  return p;
}

Rigid Rigid::translation(const V3& tt) {
  Rigid r;
  r.t = tt;
  return r;
}

Rigid Rigid::rot_x(double a) {
  Rigid r;
  r.R = Eigen::AngleAxisd(a, V3::UnitX()).toRotationMatrix();
  return r;
}

Rigid Rigid::rot_y(double a) {
  Rigid r;
  r.R = Eigen::AngleAxisd(a, V3::UnitY()).toRotationMatrix();
  return r;
}

Rigid Rigid::rot_z(double a) {
  Rigid r;
  r.R = Eigen::AngleAxisd(a, V3::UnitZ()).toRotationMatrix();
  return r;
}

// ---------------------------------------------------------------------------- Aabb

void Aabb::extend(const Aabb& b) {
  if (b.empty()) return;
  lo = lo.cwiseMin(b.lo);
  hi = hi.cwiseMax(b.hi);
}

void Aabb::extend(const V3& p) {
  lo = lo.cwiseMin(p);
  hi = hi.cwiseMax(p);
}

bool Aabb::ray_overlap(const V3& o, const V3& inv_d, double& t0, double& t1) const {
  for (int i = 0; i < 3; ++i) {
    if (std::isinf(inv_d[i])) {
      if (o[i] < lo[i] || o[i] > hi[i]) return false;
      continue;
    }
    double ta = (lo[i] - o[i]) * inv_d[i];
    double tb = (hi[i] - o[i]) * inv_d[i];
    if (ta > tb) std::swap(ta, tb);
    t0 = std::max(t0, ta);
    t1 = std::min(t1, tb);
    if (t0 > t1) return false;
  }
  return true;
}

// ---------------------------------------------------------------------------- Shape names

const char* shape_name(Shape s) {
  switch (s) {
    case Shape::box:
      return "box";
    case Shape::cylinder:
      return "cylinder";
    case Shape::sphere:
      return "sphere";
    case Shape::ellipsoid:
      return "ellipsoid";
    case Shape::mesh:
      return "mesh";
  }
  return "box";
}

bool shape_from_name(const std::string& name, Shape& out) {
  for (Shape s : {Shape::box, Shape::cylinder, Shape::sphere, Shape::ellipsoid, Shape::mesh}) {
    if (name == shape_name(s)) {
      out = s;
      return true;
    }
  }
  return false;
}

// ---------------------------------------------------------------------------- Part

Part Part::box(std::string name, const V3& half_extents, const Rigid& pose) {
  Part p;
  p.name = std::move(name);
  p.shape = Shape::box;
  p.size = half_extents;
  p.world_T_shape = pose;
  return p;
}

Part Part::cylinder(std::string name, double radius, double half_height, const Rigid& pose) {
  Part p;
  p.name = std::move(name);
  p.shape = Shape::cylinder;
  p.size = V3(radius, radius, half_height);
  p.world_T_shape = pose;
  return p;
}

Part Part::sphere(std::string name, double radius, const V3& centre) {
  Part p;
  p.name = std::move(name);
  p.shape = Shape::sphere;
  p.size = V3::Constant(radius);
  p.world_T_shape = Rigid::translation(centre);
  return p;
}

Part Part::ellipsoid(std::string name, const V3& semi_axes, const Rigid& pose) {
  Part p;
  p.name = std::move(name);
  p.shape = Shape::ellipsoid;
  p.size = semi_axes;
  p.world_T_shape = pose;
  return p;
}

Part Part::mesh(std::string name, std::shared_ptr<const TriangleMesh> mesh, const Rigid& pose) {
  if (!mesh) throw std::invalid_argument("Part::mesh: no mesh for part " + name);
  Part p;
  p.name = std::move(name);
  p.shape = Shape::mesh;
  p.size = 0.5 * mesh->bounds().size();
  p.world_T_shape = pose;
  p.triangle_mesh = std::move(mesh);
  return p;
}

double Part::width_along(const V3& u) const {
  const V3 l = world_T_shape.R.transpose() * u;
  switch (shape) {
    case Shape::box:
      return 2.0 * (size.x() * std::abs(l.x()) + size.y() * std::abs(l.y()) + size.z() * std::abs(l.z()));
    case Shape::cylinder: {
      const double n2 = l.squaredNorm();
      const double axial = std::abs(l.z());
      const double radial = std::sqrt(std::max(0.0, n2 - l.z() * l.z()));
      return 2.0 * (radius() * radial + half_height() * axial);
    }
    case Shape::sphere:
      return 2.0 * radius() * l.norm();
    case Shape::ellipsoid:
      return 2.0 * l.cwiseProduct(size).norm();
    case Shape::mesh:
      return triangle_mesh ? triangle_mesh->extent_along(l) : 0.0;
  }
  return 0.0;
}

void Part::project(const V3& u, double& lo, double& hi) const {
  const double c = u.dot(world_T_shape.t);
  if (shape == Shape::mesh) {
    // Not symmetric about the shape origin: project the vertices.
    if (!triangle_mesh) {
      lo = hi = c;
      return;
    }
    triangle_mesh->project(world_T_shape.R.transpose() * u, lo, hi);
    lo += c;
    hi += c;
    return;
  }
  const double half = 0.5 * width_along(u);
  lo = c - half;
  hi = c + half;
}

Aabb Part::aabb() const {
  Aabb b;
  for (int i = 0; i < 3; ++i) project(V3::Unit(i), b.lo[i], b.hi[i]);
  return b;
}

double Part::sdf(const V3& pw) const {
  const V3 p = world_T_shape.inverse_apply(pw);
  switch (shape) {
    case Shape::box: {
      const V3 q = p.cwiseAbs() - size;
      const double outside = q.cwiseMax(0.0).norm();
      const double inside = std::min(q.maxCoeff(), 0.0);
      return outside + inside;
    }
    case Shape::cylinder: {
      const double qx = std::hypot(p.x(), p.y()) - radius();
      const double qz = std::abs(p.z()) - half_height();
      const double outside = std::hypot(std::max(qx, 0.0), std::max(qz, 0.0));
      const double inside = std::min(std::max(qx, qz), 0.0);
      return outside + inside;
    }
    case Shape::sphere:
      return p.norm() - radius();
    case Shape::ellipsoid: {
      // |p/s| - 1 grows at most 1/min(s) per metre, so (|p/s| - 1) min(s) is 1-Lipschitz,
      // has the exact sign and never exceeds the true distance in magnitude.
      const double k0 = p.cwiseQuotient(size).norm();
      return (k0 - 1.0) * size.minCoeff();
    }
    case Shape::mesh:
      return triangle_mesh ? triangle_mesh->signed_distance(p) : kInf;
  }
  return kInf;
}

double Part::distance(const V3& pw) const {
  if (shape != Shape::ellipsoid) return std::max(0.0, sdf(pw));
  // The nearest point of the ellipsoid to an outside point y is x_i = e_i^2 y_i / (t + e_i^2)
  // for the root t >= 0 of sum (e_i y_i / (t + e_i^2))^2 = 1, which decreases in t
  // (Eberly, "Distance from a point to an ellipse, an ellipsoid, or a hyperellipsoid").
  const V3 y = world_T_shape.inverse_apply(pw).cwiseAbs();
  const V3& e = size;
  if (y.cwiseQuotient(e).squaredNorm() <= 1.0) return 0.0;
  const auto excess = [&](double t) {
    double sum = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double r = e[i] * y[i] / (t + e[i] * e[i]);
      sum += r * r;
    }
    return sum - 1.0;
  };
  double lo = 0.0, hi = e.maxCoeff() * y.norm();  // excess(hi) <= 0
  for (int it = 0; it < 200 && hi - lo > 1e-15 * (1.0 + hi); ++it) {
    const double mid = 0.5 * (lo + hi);
    (excess(mid) > 0.0 ? lo : hi) = mid;
  }
  const double t = 0.5 * (lo + hi);
  V3 x;
  for (int i = 0; i < 3; ++i) x[i] = e[i] * e[i] * y[i] / (t + e[i] * e[i]);
  return (y - x).norm();
}

bool Part::intersect(const V3& ow, const V3& dw, double tmin, double tmax, double& t, V3& normal,
                     bool* inside_out) const {
  const M3& R = world_T_shape.R;
  const V3 o = R.transpose() * (ow - world_T_shape.t);
  const V3 d = R.transpose() * dw;
  double ta = -kInf, tb = kInf;
  V3 n_local = V3::Zero();
  bool inside = false;

  switch (shape) {
    case Shape::box: {
      int axis = -1;
      for (int i = 0; i < 3; ++i) {
        bool moved = false;
        if (!clip_slab(o[i], d[i], size[i], ta, tb, moved)) return false;
        if (moved) axis = i;
      }
      if (!finish(ta, tb, tmin, tmax, t, inside)) return false;
      if (axis >= 0) n_local[axis] = d[axis] > 0.0 ? -1.0 : 1.0;
      break;
    }
    case Shape::cylinder: {
      const double a = d.x() * d.x() + d.y() * d.y();
      const double b = 2.0 * (o.x() * d.x() + o.y() * d.y());
      const double c = o.x() * o.x() + o.y() * o.y() - radius() * radius();
      bool side_entry = false;
      if (a < 1e-18 * std::max(1.0, d.squaredNorm())) {
        if (c > 0.0) return false;
      } else {
        double t1, t2;
        if (!solve_quadratic(a, b, c, t1, t2)) return false;
        ta = t1;
        tb = t2;
        side_entry = true;
      }
      bool moved = false;
      if (!clip_slab(o.z(), d.z(), half_height(), ta, tb, moved)) return false;
      if (moved) side_entry = false;
      if (!finish(ta, tb, tmin, tmax, t, inside)) return false;
      const V3 p = o + ta * d;
      if (side_entry) {
        n_local = V3(p.x(), p.y(), 0.0);
        const double nn = n_local.norm();
        if (nn > 0.0) n_local /= nn;
      } else {
        n_local = V3(0, 0, d.z() > 0.0 ? -1.0 : 1.0);
      }
      break;
    }
    case Shape::sphere:
    case Shape::ellipsoid: {
      const V3 os = o.cwiseQuotient(size);
      const V3 ds = d.cwiseQuotient(size);
      const double a = ds.squaredNorm();
      if (a == 0.0) return false;
      double t1, t2;
      if (!solve_quadratic(a, 2.0 * os.dot(ds), os.squaredNorm() - 1.0, t1, t2)) return false;
      ta = t1;
      tb = t2;
      if (!finish(ta, tb, tmin, tmax, t, inside)) return false;
      const V3 p = o + ta * d;
      n_local = p.cwiseQuotient(size.cwiseProduct(size));
      const double nn = n_local.norm();
      if (nn > 0.0) n_local /= nn;
      break;
    }
    case Shape::mesh: {
      if (!triangle_mesh || tmin > tmax) return false;
      // Inside-ness costs a distance query: only asked where it can be true.
      const V3 start = o + tmin * d;
      const Aabb& box = triangle_mesh->bounds();
      if ((start.array() >= box.lo.array()).all() && (start.array() <= box.hi.array()).all() &&
          triangle_mesh->inside(start)) {
        t = tmin;
        inside = true;
      } else if (!triangle_mesh->intersect(o, d, tmin, tmax, t, n_local)) {
        return false;
      }
      break;
    }
  }
  normal = R * n_local;
  if (inside_out) *inside_out = inside;
  return true;
}

// ---------------------------------------------------------------------------- Object

Aabb Object::aabb() const {
  Aabb b;
  for (const Part& p : parts) b.extend(p.aabb());
  return b;
}

double Object::distance(const V3& p) const {
  double d = kInf;
  for (const Part& part : parts) d = std::min(d, part.distance(p));
  return d;
}

double Object::sdf(const V3& p) const {
  double d = kInf;
  for (const Part& part : parts) d = std::min(d, part.sdf(p));
  return d;
}

V3 Object::sdf_gradient(const V3& p, double h) const {
  V3 g;
  for (int i = 0; i < 3; ++i) {
    const V3 e = V3::Unit(i) * h;
    g[i] = (sdf(p + e) - sdf(p - e)) / (2.0 * h);
  }
  return g;
}

V3 Object::normal(const V3& p, double h) const {
  const V3 g = sdf_gradient(p, h);
  const double n = g.norm();
  return n > 0.0 ? V3(g / n) : V3(V3::Zero());
}

bool Object::intersect(const V3& o, const V3& d, double tmin, double tmax, double& t, V3& normal, int* part) const {
  bool found = false;
  double best = tmax;
  for (size_t i = 0; i < parts.size(); ++i) {
    double ti;
    V3 ni;
    if (parts[i].intersect(o, d, tmin, best, ti, ni) && (!found || ti < best)) {
      found = true;
      best = ti;
      t = ti;
      normal = ni;
      if (part) *part = static_cast<int>(i);
    }
  }
  return found;
}

double Object::width_along(const V3& u) const {
  double hi = -kInf, lo = kInf;
  for (const Part& p : parts) {
    double part_lo, part_hi;
    p.project(u, part_lo, part_hi);
    hi = std::max(hi, part_hi);
    lo = std::min(lo, part_lo);
  }
  return parts.empty() ? 0.0 : hi - lo;
}

// ---------------------------------------------------------------------------- Table, World

Part Table::as_part() const {
  const V3 half(0.5 * (x_max - x_min), 0.5 * (y_max - y_min), 0.5 * thickness);
  const V3 centre(0.5 * (x_max + x_min), 0.5 * (y_max + y_min), height - 0.5 * thickness);
  return Part::box("table", half, Rigid::translation(centre));
}

double World::sdf_objects(const V3& p) const {
  double d = kInf;
  for (const Object& o : objects) d = std::min(d, o.sdf(p));
  return d;
}

// ---------------------------------------------------------------------------- Raycaster

Raycaster::Raycaster(const World& world) : world_(world), table_part_(world.table.as_part()) {
  table_box_ = table_part_.aabb();
  object_boxes_.reserve(world.objects.size());
  part_boxes_.reserve(world.objects.size());
  for (const Object& o : world.objects) {
    std::vector<Aabb> pb;
    pb.reserve(o.parts.size());
    Aabb ob;
    for (const Part& p : o.parts) {
      pb.push_back(p.aabb());
      ob.extend(pb.back());
    }
    object_boxes_.push_back(ob);
    part_boxes_.push_back(std::move(pb));
  }
}

bool Raycaster::cast(const V3& o, const V3& d, double tmin, double tmax, RayHit& hit, int only_object) const {
  const V3 inv_d(1.0 / d.x(), 1.0 / d.y(), 1.0 / d.z());
  bool found = false;
  double best = tmax;
  auto try_part = [&](const Part& part, const Aabb& box, int obj, int part_index) {
    double t0 = tmin, t1 = best;
    if (!box.ray_overlap(o, inv_d, t0, t1)) return;
    double t;
    V3 n;
    bool inside = false;
    if (part.intersect(o, d, tmin, best, t, n, &inside) && (!found || t < best)) {
      found = true;
      best = t;
      hit.t = t;
      hit.normal = n;
      hit.object = obj;
      hit.part = part_index;
      hit.inside = inside;
    }
  };
  if (only_object < 0 && world_.has_table) try_part(table_part_, table_box_, kHitTable, 0);
  for (size_t i = 0; i < world_.objects.size(); ++i) {
    if (only_object >= 0 && static_cast<size_t>(only_object) != i) continue;
    double t0 = tmin, t1 = best;
    if (!object_boxes_[i].ray_overlap(o, inv_d, t0, t1)) continue;
    const Object& obj = world_.objects[i];
    for (size_t j = 0; j < obj.parts.size(); ++j)
      try_part(obj.parts[j], part_boxes_[i][j], static_cast<int>(i), static_cast<int>(j));
  }
  if (!found) {
    hit = RayHit{};
    hit.object = kHitNothing;
  }
  return found;
}

// ---------------------------------------------------------------------------- look_at

Rigid look_at(const V3& eye, const V3& target, const V3& up) {
  V3 z = target - eye;
  const double zn = z.norm();
  z = zn > 0.0 ? V3(z / zn) : V3(0, 0, -1);
  V3 x = z.cross(up);
  if (x.norm() < 1e-9) x = z.cross(V3(1, 0, 0));
  if (x.norm() < 1e-9) x = z.cross(V3(0, 1, 0));
  x.normalize();
  const V3 y = z.cross(x);
  Rigid r;
  r.R.col(0) = x;
  r.R.col(1) = y;
  r.R.col(2) = z;
  r.t = eye;
  return r;
}

}  // namespace fg::sim
