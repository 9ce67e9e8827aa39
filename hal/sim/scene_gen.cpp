#include "sim/scene_gen.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>

#include "fg/core/constants.hpp"
#include "sim/grasp_judge.hpp"
#include "sim/obj_mesh.hpp"
#include "sim/sim_rng.hpp"

namespace fg::sim {

namespace {

constexpr double kDeg = kPi / 180.0;

Rigid at(double x, double y, double z) { return Rigid::translation(V3(x, y, z)); }

// Moves the object so its bounding box is centred on x = y = 0 with its bottom on z = 0.
void recentre(Object& obj) {
  const Aabb b = obj.aabb();
  const V3 shift(-0.5 * (b.lo.x() + b.hi.x()), -0.5 * (b.lo.y() + b.hi.y()), -b.lo.z());
  for (Part& p : obj.parts) p.world_T_shape = Rigid::translation(shift) * p.world_T_shape;
}

void transform(Object& obj, const Rigid& T) {
  for (Part& p : obj.parts) p.world_T_shape = T * p.world_T_shape;
}

Object make_small_object(Rng& rng, std::string& kind) {
  Object o;
  switch (rng.index(3)) {
    case 0: {
      kind = "can";
      const double r = rng.uniform(0.02, 0.03), h = rng.uniform(0.05, 0.10);
      o.parts.push_back(Part::cylinder("body", r, 0.5 * h, at(0, 0, 0.5 * h)));
      break;
    }
    case 1: {
      kind = "sphere";
      const double r = rng.uniform(0.02, 0.03);
      o.parts.push_back(Part::sphere("body", r, V3(0, 0, r)));
      break;
    }
    default: {
      kind = "box";
      // Drawn z, y, x (sim_rng.hpp: one draw per full expression).
      const double hz = rng.uniform(0.02, 0.045), hy = rng.uniform(0.015, 0.03), hx = rng.uniform(0.015, 0.025);
      const V3 h(hx, hy, hz);
      o.parts.push_back(Part::box("body", h, at(0, 0, h.z())));
      break;
    }
  }
  o.kind = kind;
  recentre(o);
  return o;
}

// Gap between two boxes in the horizontal plane (negative when they overlap).
double xy_gap(const Aabb& a, const Aabb& b) {
  const double gx = std::max(a.lo.x() - b.hi.x(), b.lo.x() - a.hi.x());
  const double gy = std::max(a.lo.y() - b.hi.y(), b.lo.y() - a.hi.y());
  if (gx < 0.0 && gy < 0.0) return std::max(gx, gy);
  return std::hypot(std::max(gx, 0.0), std::max(gy, 0.0));
}

uint64_t kind_salt(ObjectKind k) { return 0xA24BAED4963EE407ull * (static_cast<uint64_t>(k) + 1); }

// How a mesh kind rests on the table: on the stable face of its convex hull nearest the
// file's bottom (-z; the upright objects), or on its largest stable face (flat objects).
enum class Rest { upright, largest_face };

struct MeshKind {
  ObjectKind kind;
  const char* name;
  const char* file;
  Rest rest;
};

const MeshKind kMeshKinds[] = {
    {ObjectKind::ycb_mustard_bottle, "ycb_mustard_bottle", "YcbMustardBottle.obj", Rest::upright},
    {ObjectKind::ycb_master_chef_can, "ycb_master_chef_can", "YcbMasterChefCan.obj", Rest::upright},
    {ObjectKind::ycb_tomato_soup_can, "ycb_tomato_soup_can", "YcbTomatoSoupCan.obj", Rest::upright},
    {ObjectKind::ycb_cracker_box, "ycb_cracker_box", "YcbCrackerBox.obj", Rest::upright},
    {ObjectKind::ycb_banana, "ycb_banana", "YcbBanana.obj", Rest::largest_face},
    {ObjectKind::ycb_power_drill, "ycb_power_drill", "YcbPowerDrill.obj", Rest::upright},
    {ObjectKind::ycb_scissors, "ycb_scissors", "YcbScissors.obj", Rest::largest_face},
    {ObjectKind::ycb_chips_can, "ycb_chips_can", "YcbChipsCan_collision_vhacd.obj", Rest::upright},
};

const MeshKind* find_mesh_kind(ObjectKind k) {
  for (const MeshKind& m : kMeshKinds)
    if (m.kind == k) return &m;
  return nullptr;
}

// Rotation that puts the mesh on its resting face (face normal to -z); identity when the
// hull is flat. Cached per file: the hull is the costly part.
M3 resting_rotation(const TriangleMesh& mesh, Rest rest) {
  static std::mutex mutex;
  static std::map<std::string, M3> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  const auto it = cache.find(mesh.source());
  if (it != cache.end()) return it->second;
  const std::vector<RestingFace> faces = resting_faces(mesh);
  M3 R = M3::Identity();
  if (!faces.empty()) {
    const auto better = [rest](const RestingFace& a, const RestingFace& b) {
      return rest == Rest::upright ? a.down.z() < b.down.z() : a.area > b.area;
    };
    const RestingFace& best = *std::min_element(faces.begin(), faces.end(), better);
    R = Eigen::Quaterniond::FromTwoVectors(best.down, -V3::UnitZ()).toRotationMatrix();
  }
  cache.emplace(mesh.source(), R);
  return R;
}

Part mesh_part(const MeshKind& kind, const std::string& mesh_dir) {
  const std::string path = (std::filesystem::path(mesh_dir) / kind.file).lexically_normal().string();
  std::string error;
  std::shared_ptr<const TriangleMesh> mesh = load_obj_cached(path, error);
  if (!mesh)
    throw std::runtime_error(std::string(kind.name) + ": " + error +
                             " (the mesh folder is SceneOptions::mesh_dir or $FG_MESH_DIR)");
  Rigid pose;
  pose.R = resting_rotation(*mesh, kind.rest);
  return Part::mesh("body", mesh, pose);
}

}  // namespace

const std::vector<ObjectKind>& all_kinds() {
  static const std::vector<ObjectKind> kinds = {
      ObjectKind::box,          ObjectKind::can,        ObjectKind::bottle,    ObjectKind::spray_bottle,
      ObjectKind::sphere,       ObjectKind::big_sphere, ObjectKind::ellipsoid, ObjectKind::lying_cylinder,
      ObjectKind::bat_standing, ObjectKind::bat_lying,  ObjectKind::wide_box};
  return kinds;
}

const std::vector<ObjectKind>& mesh_kinds() {
  static const std::vector<ObjectKind> kinds = [] {
    std::vector<ObjectKind> k;
    for (const MeshKind& m : kMeshKinds) k.push_back(m.kind);
    return k;
  }();
  return kinds;
}

const char* mesh_file(ObjectKind k) {
  const MeshKind* m = find_mesh_kind(k);
  return m ? m->file : nullptr;
}

std::string default_mesh_dir() {
  const char* env = std::getenv("FG_MESH_DIR");
  if (env && *env) return env;
  return FG_DEFAULT_MESH_DIR;
}

const char* kind_name(ObjectKind k) {
  switch (k) {
    case ObjectKind::box:
      return "box";
    case ObjectKind::can:
      return "can";
    case ObjectKind::bottle:
      return "bottle";
    case ObjectKind::spray_bottle:
      return "spray_bottle";
    case ObjectKind::sphere:
      return "sphere";
    case ObjectKind::big_sphere:
      return "big_sphere";
    case ObjectKind::ellipsoid:
      return "ellipsoid";
    case ObjectKind::lying_cylinder:
      return "lying_cylinder";
    case ObjectKind::bat_standing:
      return "bat_standing";
    case ObjectKind::bat_lying:
      return "bat_lying";
    case ObjectKind::wide_box:
      return "wide_box";
    case ObjectKind::ycb_mustard_bottle:
    case ObjectKind::ycb_master_chef_can:
    case ObjectKind::ycb_tomato_soup_can:
    case ObjectKind::ycb_cracker_box:
    case ObjectKind::ycb_banana:
    case ObjectKind::ycb_power_drill:
    case ObjectKind::ycb_scissors:
    case ObjectKind::ycb_chips_can:
      return find_mesh_kind(k)->name;
  }
  return "box";
}

bool kind_from_name(const std::string& name, ObjectKind& out) {
  for (const std::vector<ObjectKind>* kinds : {&all_kinds(), &mesh_kinds()}) {
    for (ObjectKind k : *kinds) {
      if (name == kind_name(k)) {
        out = k;
        return true;
      }
    }
  }
  return false;
}

namespace {

// The kind's parts in its own frame, not yet recentred. Every size comes from size(lo, hi),
// which is rng.uniform(lo, hi) at stretch 1 (the classic draws, in their order).
Object build_object(ObjectKind kind, Rng& rng, double stretch, const std::string& mesh_dir) {
  const auto size = [&rng, stretch](double lo, double hi) {
    return stretch == 1.0 ? rng.uniform(lo, hi) : rng.uniform(lo / stretch, hi * stretch);
  };
  Object o;
  o.name = "target";
  o.kind = kind_name(kind);
  switch (kind) {
    case ObjectKind::box: {
      const double n = size(0.04, 0.07), w = size(0.10, 0.16), h = size(0.10, 0.22);
      o.parts.push_back(Part::box("body", V3(0.5 * n, 0.5 * w, 0.5 * h), at(0, 0, 0.5 * h)));
      break;
    }
    case ObjectKind::can: {
      const double r = size(0.025, 0.04), h = size(0.08, 0.15);
      o.parts.push_back(Part::cylinder("body", r, 0.5 * h, at(0, 0, 0.5 * h)));
      break;
    }
    case ObjectKind::bottle: {
      const double rb = size(0.028, 0.04), hb = size(0.10, 0.17);
      const double sh = size(0.02, 0.04);
      const double rn = size(0.011, 0.015), ln = size(0.025, 0.045);
      const double cap_h = size(0.012, 0.016);
      o.parts.push_back(Part::cylinder("body", rb, 0.5 * hb, at(0, 0, 0.5 * hb)));
      o.parts.push_back(Part::ellipsoid("shoulder", V3(rb, rb, sh), at(0, 0, hb)));
      const double n0 = hb + 0.7 * sh, n1 = hb + sh + ln;
      o.parts.push_back(Part::cylinder("neck", rn, 0.5 * (n1 - n0), at(0, 0, 0.5 * (n0 + n1))));
      const double c0 = n1 - 0.002, c1 = n1 + cap_h;
      o.parts.push_back(Part::cylinder("cap", rn + 0.0015, 0.5 * (c1 - c0), at(0, 0, 0.5 * (c0 + c1))));
      break;
    }
    case ObjectKind::spray_bottle: {
      const double n = size(0.04, 0.06), w = size(0.08, 0.11), h = size(0.13, 0.19);
      o.parts.push_back(Part::box("body", V3(0.5 * n, 0.5 * w, 0.5 * h), at(0, 0, 0.5 * h)));
      const double rn = size(0.013, 0.016), hn = size(0.015, 0.02);
      o.parts.push_back(Part::cylinder("neck", rn, 0.5 * hn + 0.001, at(0, 0, h + 0.5 * hn - 0.001)));
      const double head_hz = size(0.02, 0.025), head_hy = size(0.03, 0.04),
                   head_hx = size(0.013, 0.016);  // drawn z, y, x (sim_rng.hpp)
      const V3 head(head_hx, head_hy, head_hz);
      const double head_y = rng.uniform(0.01, 0.02);
      const double head_z = h + hn + head.z() - 0.001;
      o.parts.push_back(Part::box("head", head, at(0, head_y, head_z)));
      const double rz = size(0.004, 0.006), hl = size(0.006, 0.01);
      Part nozzle = Part::cylinder(
          "nozzle", rz, hl, at(0, head_y + head.y() + hl - 0.002, head_z + head.z() - 0.01) * Rigid::rot_x(0.5 * kPi));
      nozzle.graspable = false;
      o.parts.push_back(nozzle);
      break;
    }
    case ObjectKind::sphere: {
      const double r = size(0.025, 0.037);
      o.parts.push_back(Part::sphere("body", r, V3(0, 0, r)));
      break;
    }
    case ObjectKind::big_sphere: {
      const double r = size(0.05, 0.07);
      o.parts.push_back(Part::sphere("body", r, V3(0, 0, r)));
      break;
    }
    case ObjectKind::ellipsoid: {
      // Drawn z, y, x (sim_rng.hpp: one draw per full expression).
      const double sz = size(0.035, 0.08), sy = size(0.04, 0.07), sx = size(0.025, 0.038);
      const V3 s(sx, sy, sz);
      o.parts.push_back(Part::ellipsoid("body", s, at(0, 0, s.z())));
      break;
    }
    case ObjectKind::lying_cylinder: {
      const double r = size(0.02, 0.035), len = size(0.12, 0.2);
      o.parts.push_back(Part::cylinder("body", r, 0.5 * len, at(0, 0, r) * Rigid::rot_y(0.5 * kPi)));
      break;
    }
    case ObjectKind::bat_lying: {
      const double r = size(0.073, 0.077), hh = size(0.005, 0.007);
      const double L = size(0.085, 0.10), w = size(0.024, 0.03), t = size(0.02, 0.026);
      o.parts.push_back(Part::cylinder("blade", r, hh, at(0, 0, hh)));
      o.parts.push_back(Part::box("handle", V3(0.5 * L, 0.5 * w, 0.5 * t), at(r - 0.008 + 0.5 * L, 0, 0.5 * t)));
      break;
    }
    case ObjectKind::bat_standing: {
      const double r = size(0.073, 0.077), hh = size(0.005, 0.007);
      const double L = size(0.085, 0.10), w = size(0.024, 0.03), t = size(0.02, 0.026);
      const double phi = rng.uniform(-50.0, 50.0) * kDeg;  // handle tilt from vertical
      const double stand_h = 0.012;
      Part stand = Part::box("stand", V3(0.03, 0.02, 0.5 * stand_h), at(0, 0, 0.5 * stand_h));
      stand.graspable = false;
      o.parts.push_back(stand);
      const V3 c(0, 0, stand_h + r - 0.004);
      o.parts.push_back(Part::cylinder("blade", r, hh, Rigid::translation(c) * Rigid::rot_x(0.5 * kPi)));
      const V3 dir(std::sin(phi), 0, std::cos(phi));
      o.parts.push_back(Part::box("handle", V3(0.5 * L, 0.5 * t, 0.5 * w),
                                  Rigid::translation(c + (r - 0.008 + 0.5 * L) * dir) * Rigid::rot_y(phi - 0.5 * kPi)));
      break;
    }
    case ObjectKind::wide_box: {
      const double a = size(0.10, 0.15), b = size(0.10, 0.15), h = size(0.05, 0.15);
      o.parts.push_back(Part::box("body", V3(0.5 * a, 0.5 * b, 0.5 * h), at(0, 0, 0.5 * h)));
      break;
    }
    case ObjectKind::ycb_mustard_bottle:
    case ObjectKind::ycb_master_chef_can:
    case ObjectKind::ycb_tomato_soup_can:
    case ObjectKind::ycb_cracker_box:
    case ObjectKind::ycb_banana:
    case ObjectKind::ycb_power_drill:
    case ObjectKind::ycb_scissors:
    case ObjectKind::ycb_chips_can:
      o.parts.push_back(mesh_part(*find_mesh_kind(kind), mesh_dir));
      break;
  }
  return o;
}

}  // namespace

Object make_object(ObjectKind kind, uint64_t rng_seed, const std::string& mesh_dir) {
  Rng rng(rng_seed);
  Object o = build_object(kind, rng, 1.0, mesh_dir);
  recentre(o);
  return o;
}

GroundTruth compute_truth(const World& world, int target, const fg::GripperGeometry& gripper, double fit_margin) {
  GroundTruth t;
  t.fit_margin = fit_margin;
  if (target < 0 || static_cast<size_t>(target) >= world.objects.size()) return t;
  const Object& obj = world.objects[static_cast<size_t>(target)];
  const FitReport fit = target_fit(obj, gripper, fit_margin);
  t.target_fits = fit.fits;
  t.target_min_width = fit.min_width;
  t.target_box = obj.aabb();
  t.target_centre = t.target_box.centre();
  return t;
}

namespace {

// ------------------------------------------------------------------ the cell distribution

constexpr uint64_t kCellSalt = 0x5CE11D157B1B5A17ull;  // cell seeds draw apart from classic ones
constexpr int kClassRedraws = 20;                      // size draws per target before its class gives way
constexpr int kPlacementAttempts = 32;                 // draws of an other object's place or of a sensor pose
constexpr double kGapSampleSpacing = 0.004;            // surface_gap's sample spacing (m)

// The stable faces of a mesh's convex hull, once per file.
const std::vector<RestingFace>& cached_resting_faces(const TriangleMesh& mesh) {
  static std::mutex mutex;
  static std::map<std::string, std::vector<RestingFace>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  auto it = cache.find(mesh.source());
  if (it == cache.end()) it = cache.emplace(mesh.source(), resting_faces(mesh)).first;
  return it->second;  // map nodes stay put
}

bool may_lie(ObjectKind k) {
  switch (k) {
    case ObjectKind::box:
    case ObjectKind::wide_box:
    case ObjectKind::ellipsoid:
    case ObjectKind::can:
    case ObjectKind::bottle:
      return true;
    default: {
      const MeshKind* m = find_mesh_kind(k);
      return m && m->rest == Rest::upright;
    }
  }
}

// Lays an object of a kind that may lie (may_lie) in its own frame, before recentring: a box
// or an ellipsoid turns a horizontal axis up, a can or a bottle lies on its side, an upright
// mesh takes another stable face of its hull (a larger face is likelier, as it is when an
// object is put down at random).
void lie_down(Object& o, ObjectKind kind, Rng& rng) {
  switch (kind) {
    case ObjectKind::box:
    case ObjectKind::wide_box:
    case ObjectKind::ellipsoid: {
      const bool x_up = rng.chance(0.5);
      transform(o, x_up ? Rigid::rot_y(0.5 * kPi) : Rigid::rot_x(0.5 * kPi));
      break;
    }
    case ObjectKind::can:
    case ObjectKind::bottle:
      transform(o, Rigid::rot_x(0.5 * kPi));
      break;
    default: {
      if (o.parts.size() != 1 || !o.parts[0].triangle_mesh) break;
      Part& part = o.parts[0];
      const std::vector<RestingFace>& faces = cached_resting_faces(*part.triangle_mesh);
      if (faces.empty()) break;
      const RestingFace& upright =
          *std::min_element(faces.begin(), faces.end(),
                            [](const RestingFace& a, const RestingFace& b) { return a.down.z() < b.down.z(); });
      // Faces within 20 deg of the upright one are the same way up.
      std::vector<const RestingFace*> sides;
      double total = 0.0;
      for (const RestingFace& f : faces) {
        if (f.down.dot(upright.down) > std::cos(20.0 * kDeg)) continue;
        sides.push_back(&f);
        total += f.area;
      }
      if (sides.empty()) break;
      double pick = rng.uniform(0.0, total);
      const RestingFace* chosen = sides.back();
      for (const RestingFace* f : sides) {
        if (pick < f->area) {
          chosen = f;
          break;
        }
        pick -= f->area;
      }
      part.world_T_shape.R = Eigen::Quaterniond::FromTwoVectors(chosen->down, -V3::UnitZ()).toRotationMatrix();
      break;
    }
  }
}

// An object of the kind as cell draws it, in its own frame (recentred): sizes widened,
// standing or lying. A target is redrawn until it keeps its kind's class (kind_fits: its
// smallest width within max_opening - fit_margin, or beyond max_opening); after
// kClassRedraws draws the last one stays and the truth says what it is.
// target_fit's smallest width of a recentred object. A mesh's comes from a few resting
// faces only and costs thousands of vertices per direction: kept per file and rotation.
double smallest_width(const Object& o, const fg::GripperGeometry& gripper) {
  if (o.parts.size() != 1 || !o.parts[0].triangle_mesh) return target_fit(o, gripper, 0.0).min_width;
  static std::mutex mutex;
  static std::map<std::pair<std::string, std::array<double, 9>>, double> cache;
  const M3& R = o.parts[0].world_T_shape.R;
  std::array<double, 9> rotation;
  std::copy(R.data(), R.data() + 9, rotation.begin());
  const auto key = std::make_pair(o.parts[0].triangle_mesh->source(), rotation);
  const std::lock_guard<std::mutex> lock(mutex);
  const auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  return cache.emplace(key, target_fit(o, gripper, 0.0).min_width).first->second;
}

Object draw_cell_object(ObjectKind kind, Rng& rng, const SceneOptions& opt, bool keep_class) {
  Object o;
  for (int draw = 0; draw < kClassRedraws; ++draw) {
    o = build_object(kind, rng, opt.cell.size_stretch, opt.mesh_dir);
    if (may_lie(kind) && rng.chance(opt.cell.lying_rate)) lie_down(o, kind, rng);
    recentre(o);
    if (!keep_class) break;
    const double width = smallest_width(o, opt.gripper);
    const double opening = opt.gripper.max_opening_m;
    if (kind_fits(kind) ? width <= opening - opt.fit_margin : width > opening) break;
  }
  return o;
}

double draw_albedo(Rng& rng, double dark_rate) {
  const bool dark = rng.chance(dark_rate);
  return dark ? rng.uniform(0.05, 0.25) : rng.uniform(0.4, 1.0);
}

// Points on a part's surface about `spacing` apart, its edges and corners included, in world.
// Points a union's other parts cover lie inside it, which never lowers a gap below the truth.
void add_surface_samples(const Part& p, double spacing, std::vector<V3>& out) {
  const Rigid& T = p.world_T_shape;
  const auto steps = [spacing](double length) { return std::max(1, static_cast<int>(std::ceil(length / spacing))); };
  switch (p.shape) {
    case Shape::box: {
      const V3& e = p.size;
      for (int a = 0; a < 3; ++a) {
        const int b = (a + 1) % 3, c = (a + 2) % 3;
        const int nb = steps(2.0 * e[b]), nc = steps(2.0 * e[c]);
        for (int side = -1; side <= 1; side += 2)
          for (int i = 0; i <= nb; ++i)
            for (int j = 0; j <= nc; ++j) {
              V3 q;
              q[a] = side * e[a];
              q[b] = -e[b] + 2.0 * e[b] * i / nb;
              q[c] = -e[c] + 2.0 * e[c] * j / nc;
              out.push_back(T.apply(q));
            }
      }
      break;
    }
    case Shape::cylinder: {
      const double r = p.radius(), hh = p.half_height();
      const int around = std::max(8, steps(2.0 * kPi * r)), along = steps(2.0 * hh), rings = steps(r);
      for (int k = 0; k < around; ++k) {
        const double th = 2.0 * kPi * k / around;
        for (int i = 0; i <= along; ++i)
          out.push_back(T.apply(V3(r * std::cos(th), r * std::sin(th), -hh + 2.0 * hh * i / along)));
      }
      for (int ring = 0; ring < rings; ++ring) {  // the caps inside their rims
        const double rr = r * ring / rings;
        const int n = ring == 0 ? 1 : std::max(6, steps(2.0 * kPi * rr));
        for (int k = 0; k < n; ++k) {
          const double th = 2.0 * kPi * k / n;
          for (int side = -1; side <= 1; side += 2)
            out.push_back(T.apply(V3(rr * std::cos(th), rr * std::sin(th), side * hh)));
        }
      }
      break;
    }
    case Shape::sphere:
    case Shape::ellipsoid: {
      const V3& e = p.size;
      const double mean = e.mean();
      const int n = std::max(32, static_cast<int>(std::ceil(4.0 * kPi * mean * mean / (spacing * spacing))));
      const double golden = kPi * (3.0 - std::sqrt(5.0));
      for (int i = 0; i < n; ++i) {
        const double z = 1.0 - (2.0 * i + 1.0) / n, rxy = std::sqrt(std::max(0.0, 1.0 - z * z));
        const double phi = golden * i;
        out.push_back(T.apply(e.cwiseProduct(V3(rxy * std::cos(phi), rxy * std::sin(phi), z))));
      }
      break;
    }
    case Shape::mesh:
      if (p.triangle_mesh)
        for (const V3& v : p.triangle_mesh->vertices()) out.push_back(T.apply(v));
      break;
  }
}

std::vector<V3> surface_samples(const Object& o) {
  std::vector<V3> pts;
  for (const Part& p : o.parts) add_surface_samples(p, kGapSampleSpacing, pts);
  return pts;
}

double box_distance(const Aabb& b, const V3& p) { return (b.lo - p).cwiseMax(p - b.hi).cwiseMax(0.0).norm(); }

// The smallest exact distance from the points to the object's parts. Unless with_meshes,
// mesh parts are left to the other direction, from their vertices (a few mm apart on the
// YCB meshes): a mesh's exact distance costs a tree search per point. Bounding boxes skip
// the points and parts that cannot beat the best so far, starting from the point nearest
// the whole box.
double distance_from(const std::vector<V3>& pts, const Object& o, const V3& shift = V3::Zero(),
                     bool with_meshes = false) {
  std::vector<const Part*> parts;
  std::vector<Aabb> boxes;
  Aabb whole;
  for (const Part& p : o.parts) {
    if (p.shape == Shape::mesh && !with_meshes) continue;
    parts.push_back(&p);
    boxes.push_back(p.aabb());
    whole.extend(boxes.back());
  }
  double best = std::numeric_limits<double>::infinity();
  if (pts.empty() || parts.empty()) return best;
  size_t nearest = 0;
  double nearest_bound = best;
  for (size_t i = 0; i < pts.size(); ++i) {
    const double b = box_distance(whole, pts[i] + shift);
    if (b < nearest_bound) nearest_bound = b, nearest = i;
  }
  for (const Part* p : parts) best = std::min(best, p->distance(pts[nearest] + shift));
  for (const V3& q : pts) {
    const V3 p = q + shift;
    if (box_distance(whole, p) >= best) continue;
    for (size_t k = 0; k < boxes.size(); ++k)
      if (box_distance(boxes[k], p) < best) best = std::min(best, parts[k]->distance(p));
  }
  return best;
}

// surface_gap for b moved by shift, with the samples of a and of b (unmoved) given.
double gap_shifted(const Object& a, const std::vector<V3>& a_pts, const Object& b, const std::vector<V3>& b_pts,
                   const V3& shift) {
  Object moved = b;
  transform(moved, Rigid::translation(shift));
  return std::min(distance_from(b_pts, a, shift), distance_from(a_pts, moved));
}

// Places an other object (recentred, yawed) so that its surface is `gap` from the target's
// along the horizontal direction `dir` from the target's centre: it starts where the two
// footprints' bounding circles are `gap` apart (the surfaces are then at least that far)
// and moves in by the excess, which the distance's 1-Lipschitz bound never lets overshoot.
// Returns the translation that places it; `achieved` is the gap there.
V3 place_beside(const Object& target, const std::vector<V3>& target_pts, const Object& other,
                const std::vector<V3>& other_pts, const V3& dir, double gap, double z0, double& achieved) {
  const Aabb tb = target.aabb();
  const V3 tc = tb.centre();
  const auto radius_xy = [](const Aabb& b) { return 0.5 * std::hypot(b.size().x(), b.size().y()); };
  double dist = radius_xy(tb) + radius_xy(other.aabb()) + gap;
  V3 shift(tc.x() + dist * dir.x(), tc.y() + dist * dir.y(), z0);
  achieved = gap_shifted(target, target_pts, other, other_pts, shift);
  for (int step = 0; step < 12 && achieved - gap > 5e-4; ++step) {
    dist -= achieved - gap;
    shift = V3(tc.x() + dist * dir.x(), tc.y() + dist * dir.y(), z0);
    achieved = gap_shifted(target, target_pts, other, other_pts, shift);
  }
  return shift;
}

// The distance from a point to the nearest object surface (0 inside one).
double clearance_from_objects(const World& w, const V3& p) {
  double d = std::numeric_limits<double>::infinity();
  for (const Object& o : w.objects) d = std::min(d, o.distance(p));
  return d;
}

GeneratedScene make_cell_scene(ObjectKind kind, uint64_t seed, const SceneOptions& opt,
                               const WristPoseTest& wrist_reachable) {
  const CellOptions& cell = opt.cell;
  GeneratedScene s;
  s.kind = kind_name(kind);
  s.seed = seed;
  s.distribution = Distribution::cell;
  s.gripper = opt.gripper;
  s.noise = opt.noise;
  s.world.table = opt.table;
  const uint64_t base = splitmix64(seed ^ kind_salt(kind) ^ kCellSalt);
  Rng rng(base);
  const double z0 = opt.table.height;

  // The target, anywhere in the area, any yaw (sim_rng.hpp: one draw per full expression).
  Object target = draw_cell_object(kind, rng, opt, true);
  target.name = "target";
  const double tx = rng.uniform(opt.target_x_min, opt.target_x_max);
  const double ty = rng.uniform(-opt.target_y_half, opt.target_y_half);
  const double yaw = rng.uniform(0.0, 2.0 * kPi);
  transform(target, Rigid::rot_z(yaw));
  recentre(target);
  transform(target, Rigid::translation(V3(tx, ty, z0)));
  target.albedo = draw_albedo(rng, cell.dark_rate);
  s.world.table.albedo = rng.uniform(0.4, 1.0);
  s.world.objects.push_back(target);
  s.target = 0;
  const V3 tc = target.aabb().centre();

  // Other objects, each others_gap_min..max from the target, 1 cm or more from each other,
  // on the table 2 cm or more inside its edges, farther from the workspace centre than the
  // target. One that finds no place is left out.
  const std::vector<V3> target_pts = surface_samples(target);
  const double target_to_ws = std::hypot(tc.x() - opt.workspace_centre.x(), tc.y() - opt.workspace_centre.y());
  const int fewest = std::max(0, std::min(cell.others_min, cell.others_max));
  const int others =
      fewest + static_cast<int>(rng.index(static_cast<uint64_t>(std::max(0, cell.others_max) - fewest) + 1));
  for (int k = 0; k < others; ++k) {
    const ObjectKind other_kind = all_kinds()[rng.index(all_kinds().size())];
    Object other = draw_cell_object(other_kind, rng, opt, false);
    other.name = "object" + std::to_string(k + 1);
    other.albedo = draw_albedo(rng, cell.dark_rate);
    for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
      const double gap = rng.uniform(cell.others_gap_min, cell.others_gap_max);
      const double ang = rng.uniform(0.0, 2.0 * kPi);
      const double yaw2 = rng.uniform(0.0, 2.0 * kPi);
      Object turned = other;
      transform(turned, Rigid::rot_z(yaw2));
      recentre(turned);
      const std::vector<V3> pts = surface_samples(turned);
      double achieved = 0.0;
      const V3 shift =
          place_beside(target, target_pts, turned, pts, V3(std::cos(ang), std::sin(ang), 0.0), gap, z0, achieved);
      if (achieved < cell.others_gap_min || achieved > cell.others_gap_max) continue;
      if (std::hypot(shift.x() - opt.workspace_centre.x(), shift.y() - opt.workspace_centre.y()) <
          target_to_ws + cell.others_farther)
        continue;
      Object cand = turned;
      transform(cand, Rigid::translation(shift));
      const Aabb cb = cand.aabb();
      const Table& tb = opt.table;
      if (cb.lo.x() < tb.x_min + 0.02 || cb.hi.x() > tb.x_max - 0.02 || cb.lo.y() < tb.y_min + 0.02 ||
          cb.hi.y() > tb.y_max - 0.02)
        continue;
      bool apart = true;
      for (size_t j = 1; j < s.world.objects.size() && apart; ++j)
        apart = surface_gap(s.world.objects[j], cand) >= 0.01;
      if (!apart) continue;
      s.world.objects.push_back(std::move(cand));
      break;
    }
  }

  // Sensors, sensor_clearance or more from every object; after kPlacementAttempts draws
  // the last one stays.
  s.head.K = opt.intrinsics;
  s.hand.K = opt.intrinsics;
  const double to_base = std::atan2(-tc.y(), -tc.x());
  V3 head_eye = tc;
  for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
    const double dist = rng.uniform(cell.head_distance_min, cell.head_distance_max);
    const double down = rng.uniform(cell.head_down_min_deg, cell.head_down_max_deg) * kDeg;
    const double az = to_base + rng.uniform(-cell.head_azimuth_half_deg, cell.head_azimuth_half_deg) * kDeg;
    head_eye = tc + dist * V3(std::cos(down) * std::cos(az), std::cos(down) * std::sin(az), std::sin(down));
    if (clearance_from_objects(s.world, head_eye) >= cell.sensor_clearance) break;
  }
  s.head.world_T_sensor = look_at(head_eye, tc);
  V3 hand_eye = tc;
  const double sin_el_min = std::sin(cell.wrist_elevation_min_deg * kDeg);
  const double sin_el_max = std::sin(cell.wrist_elevation_max_deg * kDeg);
  for (int attempt = 0; attempt < kPlacementAttempts; ++attempt) {
    const double dist = rng.uniform(cell.wrist_distance_min, cell.wrist_distance_max);
    const double el = std::asin(rng.uniform(sin_el_min, sin_el_max));  // uniform over the sphere's area
    const double az = rng.uniform(0.0, 2.0 * kPi);
    hand_eye = tc + dist * V3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
    s.hand.world_T_sensor = look_at(hand_eye, tc);
    if (clearance_from_objects(s.world, hand_eye) >= cell.sensor_clearance &&
        hand_eye.z() >= z0 + cell.sensor_clearance && (!wrist_reachable || wrist_reachable(s.hand.world_T_sensor)))
      break;
  }
  s.head_noise_seed = splitmix64(base + 1);
  s.hand_noise_seed = splitmix64(base + 2);

  s.truth = compute_truth(s.world, s.target, s.gripper, opt.fit_margin);
  return s;
}

}  // namespace

const char* distribution_name(Distribution d) { return d == Distribution::cell ? "cell" : "classic"; }

bool distribution_from_name(const std::string& name, Distribution& out) {
  if (name == "classic")
    out = Distribution::classic;
  else if (name == "cell")
    out = Distribution::cell;
  else
    return false;
  return true;
}

SceneOptions SceneOptions::of(Distribution d) {
  SceneOptions o;
  o.distribution = d;
  if (d == Distribution::cell) {
    // The scene contract's whole area (shared/spec/scene-and-cli.md).
    o.target_x_min = 0.3;
    o.target_x_max = 0.7;
    o.target_y_half = 0.35;
    o.fit_margin = 2.0 * 0.003;  // targets that fit may leave 3 mm per finger
    o.noise = NoiseModel::structured_light();
  }
  return o;
}

bool kind_fits(ObjectKind k) {
  return k != ObjectKind::big_sphere && k != ObjectKind::wide_box && k != ObjectKind::ycb_master_chef_can &&
         k != ObjectKind::ycb_scissors;
}

double surface_gap(const Object& a, const Object& b) {
  const std::vector<V3> pa = surface_samples(a), pb = surface_samples(b);
  const double gap = std::min(distance_from(pb, a), distance_from(pa, b));
  return std::isfinite(gap) ? gap : distance_from(pb, a, V3::Zero(), true);  // meshes only
}

GeneratedScene make_scene(ObjectKind kind, uint64_t seed, const SceneOptions& opt,
                          const WristPoseTest& wrist_reachable) {
  if (opt.distribution == Distribution::cell) return make_cell_scene(kind, seed, opt, wrist_reachable);
  return make_scene(kind, seed, opt);
}

GeneratedScene make_scene(ObjectKind kind, uint64_t seed, const SceneOptions& opt) {
  if (opt.distribution == Distribution::cell) return make_cell_scene(kind, seed, opt, nullptr);
  GeneratedScene s;
  s.kind = kind_name(kind);
  s.seed = seed;
  s.gripper = opt.gripper;
  s.noise = opt.noise;
  s.world.table = opt.table;
  const uint64_t base = splitmix64(seed ^ kind_salt(kind));
  Rng rng(base);
  const double z0 = opt.table.height;

  // Target.
  Object target = make_object(kind, rng.bits(), opt.mesh_dir);
  const double tx = rng.uniform(opt.target_x_min, opt.target_x_max),
               ty = rng.uniform(-opt.target_y_half, opt.target_y_half);
  const double yaw = rng.uniform(0.0, 2.0 * kPi);
  transform(target, Rigid::translation(V3(tx, ty, z0)) * Rigid::rot_z(yaw));
  {
    // Yawed, an asymmetric object's bounding box moves: centre it on (tx, ty) again.
    const V3 c = target.aabb().centre();
    transform(target, Rigid::translation(V3(tx - c.x(), ty - c.y(), 0.0)));
  }
  s.world.objects.push_back(target);
  s.target = 0;
  const Aabb tbox = target.aabb();
  const V3 tc = tbox.centre();

  // Optional second object, 0.15-0.25 m from the target, never touching it, farther from
  // the workspace centre than the target, on the table.
  if (rng.chance(opt.second_object_rate)) {
    std::string k2;
    Object second = make_small_object(rng, k2);
    second.name = "object1";
    const double yaw2 = rng.uniform(0.0, 2.0 * kPi);
    const double target_to_ws = std::hypot(tc.x() - opt.workspace_centre.x(), tc.y() - opt.workspace_centre.y());
    for (int attempt = 0; attempt < 64; ++attempt) {
      const double dist = rng.uniform(0.15, 0.25), ang = rng.uniform(0.0, 2.0 * kPi);
      const double px = tc.x() + dist * std::cos(ang), py = tc.y() + dist * std::sin(ang);
      Object cand = second;
      transform(cand, Rigid::translation(V3(px, py, z0)) * Rigid::rot_z(yaw2));
      const Aabb cb = cand.aabb();
      const Table& tb = opt.table;
      if (cb.lo.x() < tb.x_min + 0.05 || cb.hi.x() > tb.x_max - 0.05 || cb.lo.y() < tb.y_min + 0.05 ||
          cb.hi.y() > tb.y_max - 0.05)
        continue;
      if (xy_gap(cb, tbox) < 0.03) continue;
      if (std::hypot(px - opt.workspace_centre.x(), py - opt.workspace_centre.y()) < target_to_ws + 0.05) continue;
      s.world.objects.push_back(cand);
      break;
    }
  }

  // Cameras.
  s.head.K = opt.intrinsics;
  s.hand.K = opt.intrinsics;
  // Drawn z, y, x (sim_rng.hpp: one draw per full expression).
  const double head_z = z0 + rng.uniform(opt.head_height_min, opt.head_height_max), head_y = rng.uniform(-0.1, 0.1),
               head_x = rng.uniform(-0.05, 0.05);
  const V3 head_eye(head_x, head_y, head_z);
  s.head.world_T_sensor =
      look_at(head_eye, opt.head_at_workspace ? V3(opt.workspace_centre.x(), opt.workspace_centre.y(), z0) : tc);
  const double az_head = std::atan2(head_eye.y() - tc.y(), head_eye.x() - tc.x());
  const double delta_size = rng.uniform(40.0, 120.0) * kDeg;
  const double delta = delta_size * (rng.chance(0.5) ? 1.0 : -1.0);
  const double az = az_head + delta;
  const double el = rng.uniform(opt.hand_elevation_min_deg, opt.hand_elevation_max_deg) * kDeg;
  const double dist = rng.uniform(opt.hand_distance_min, opt.hand_distance_max);
  const V3 hand_eye = tc + dist * V3(std::cos(el) * std::cos(az), std::cos(el) * std::sin(az), std::sin(el));
  s.hand.world_T_sensor = look_at(hand_eye, tc);
  s.head_noise_seed = splitmix64(base + 1);
  s.hand_noise_seed = splitmix64(base + 2);

  s.truth = compute_truth(s.world, s.target, s.gripper, opt.fit_margin);
  return s;
}

SceneImages render_scene(const GeneratedScene& scene) {
  SceneImages im;
  im.head = render_depth(scene.world, scene.head, scene.noise, scene.head_noise_seed);
  im.hand = render_depth(scene.world, scene.hand, scene.noise, scene.hand_noise_seed);
  return im;
}

}  // namespace fg::sim
