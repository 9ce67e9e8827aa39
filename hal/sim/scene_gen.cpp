#include "sim/scene_gen.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <mutex>
#include <stdexcept>

#include <Eigen/Geometry>

#include "sim/grasp_judge.hpp"
#include "sim/obj_mesh.hpp"
#include "sim/sim_rng.hpp"

namespace fg::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
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
      ObjectKind::box,        ObjectKind::can,          ObjectKind::bottle,
      ObjectKind::spray_bottle, ObjectKind::sphere,     ObjectKind::big_sphere,
      ObjectKind::ellipsoid,  ObjectKind::lying_cylinder, ObjectKind::bat_standing,
      ObjectKind::bat_lying,  ObjectKind::wide_box};
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
    case ObjectKind::box: return "box";
    case ObjectKind::can: return "can";
    case ObjectKind::bottle: return "bottle";
    case ObjectKind::spray_bottle: return "spray_bottle";
    case ObjectKind::sphere: return "sphere";
    case ObjectKind::big_sphere: return "big_sphere";
    case ObjectKind::ellipsoid: return "ellipsoid";
    case ObjectKind::lying_cylinder: return "lying_cylinder";
    case ObjectKind::bat_standing: return "bat_standing";
    case ObjectKind::bat_lying: return "bat_lying";
    case ObjectKind::wide_box: return "wide_box";
    case ObjectKind::ycb_mustard_bottle:
    case ObjectKind::ycb_master_chef_can:
    case ObjectKind::ycb_tomato_soup_can:
    case ObjectKind::ycb_cracker_box:
    case ObjectKind::ycb_banana:
    case ObjectKind::ycb_power_drill:
    case ObjectKind::ycb_scissors:
    case ObjectKind::ycb_chips_can: return find_mesh_kind(k)->name;
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

Object make_object(ObjectKind kind, uint64_t rng_seed, const std::string& mesh_dir) {
  Rng rng(rng_seed);
  Object o;
  o.name = "target";
  o.kind = kind_name(kind);
  switch (kind) {
    case ObjectKind::box: {
      const double n = rng.uniform(0.04, 0.07), w = rng.uniform(0.10, 0.16), h = rng.uniform(0.10, 0.22);
      o.parts.push_back(Part::box("body", V3(0.5 * n, 0.5 * w, 0.5 * h), at(0, 0, 0.5 * h)));
      break;
    }
    case ObjectKind::can: {
      const double r = rng.uniform(0.025, 0.04), h = rng.uniform(0.08, 0.15);
      o.parts.push_back(Part::cylinder("body", r, 0.5 * h, at(0, 0, 0.5 * h)));
      break;
    }
    case ObjectKind::bottle: {
      const double rb = rng.uniform(0.028, 0.04), hb = rng.uniform(0.10, 0.17);
      const double sh = rng.uniform(0.02, 0.04);
      const double rn = rng.uniform(0.011, 0.015), ln = rng.uniform(0.025, 0.045);
      const double cap_h = rng.uniform(0.012, 0.016);
      o.parts.push_back(Part::cylinder("body", rb, 0.5 * hb, at(0, 0, 0.5 * hb)));
      o.parts.push_back(Part::ellipsoid("shoulder", V3(rb, rb, sh), at(0, 0, hb)));
      const double n0 = hb + 0.7 * sh, n1 = hb + sh + ln;
      o.parts.push_back(Part::cylinder("neck", rn, 0.5 * (n1 - n0), at(0, 0, 0.5 * (n0 + n1))));
      const double c0 = n1 - 0.002, c1 = n1 + cap_h;
      o.parts.push_back(Part::cylinder("cap", rn + 0.0015, 0.5 * (c1 - c0), at(0, 0, 0.5 * (c0 + c1))));
      break;
    }
    case ObjectKind::spray_bottle: {
      const double n = rng.uniform(0.04, 0.06), w = rng.uniform(0.08, 0.11), h = rng.uniform(0.13, 0.19);
      o.parts.push_back(Part::box("body", V3(0.5 * n, 0.5 * w, 0.5 * h), at(0, 0, 0.5 * h)));
      const double rn = rng.uniform(0.013, 0.016), hn = rng.uniform(0.015, 0.02);
      o.parts.push_back(Part::cylinder("neck", rn, 0.5 * hn + 0.001, at(0, 0, h + 0.5 * hn - 0.001)));
      const double head_hz = rng.uniform(0.02, 0.025), head_hy = rng.uniform(0.03, 0.04),
                   head_hx = rng.uniform(0.013, 0.016);  // drawn z, y, x (sim_rng.hpp)
      const V3 head(head_hx, head_hy, head_hz);
      const double head_y = rng.uniform(0.01, 0.02);
      const double head_z = h + hn + head.z() - 0.001;
      o.parts.push_back(Part::box("head", head, at(0, head_y, head_z)));
      const double rz = rng.uniform(0.004, 0.006), hl = rng.uniform(0.006, 0.01);
      Part nozzle = Part::cylinder("nozzle", rz, hl,
                                   at(0, head_y + head.y() + hl - 0.002, head_z + head.z() - 0.01) *
                                       Rigid::rot_x(0.5 * kPi));
      nozzle.graspable = false;
      o.parts.push_back(nozzle);
      break;
    }
    case ObjectKind::sphere: {
      const double r = rng.uniform(0.025, 0.037);
      o.parts.push_back(Part::sphere("body", r, V3(0, 0, r)));
      break;
    }
    case ObjectKind::big_sphere: {
      const double r = rng.uniform(0.05, 0.07);
      o.parts.push_back(Part::sphere("body", r, V3(0, 0, r)));
      break;
    }
    case ObjectKind::ellipsoid: {
      // Drawn z, y, x (sim_rng.hpp: one draw per full expression).
      const double sz = rng.uniform(0.035, 0.08), sy = rng.uniform(0.04, 0.07), sx = rng.uniform(0.025, 0.038);
      const V3 s(sx, sy, sz);
      o.parts.push_back(Part::ellipsoid("body", s, at(0, 0, s.z())));
      break;
    }
    case ObjectKind::lying_cylinder: {
      const double r = rng.uniform(0.02, 0.035), len = rng.uniform(0.12, 0.2);
      o.parts.push_back(Part::cylinder("body", r, 0.5 * len, at(0, 0, r) * Rigid::rot_y(0.5 * kPi)));
      break;
    }
    case ObjectKind::bat_lying: {
      const double r = rng.uniform(0.073, 0.077), hh = rng.uniform(0.005, 0.007);
      const double L = rng.uniform(0.085, 0.10), w = rng.uniform(0.024, 0.03), t = rng.uniform(0.02, 0.026);
      o.parts.push_back(Part::cylinder("blade", r, hh, at(0, 0, hh)));
      o.parts.push_back(Part::box("handle", V3(0.5 * L, 0.5 * w, 0.5 * t), at(r - 0.008 + 0.5 * L, 0, 0.5 * t)));
      break;
    }
    case ObjectKind::bat_standing: {
      const double r = rng.uniform(0.073, 0.077), hh = rng.uniform(0.005, 0.007);
      const double L = rng.uniform(0.085, 0.10), w = rng.uniform(0.024, 0.03), t = rng.uniform(0.02, 0.026);
      const double phi = rng.uniform(-50.0, 50.0) * kDeg;  // handle tilt from vertical
      const double stand_h = 0.012;
      Part stand = Part::box("stand", V3(0.03, 0.02, 0.5 * stand_h), at(0, 0, 0.5 * stand_h));
      stand.graspable = false;
      o.parts.push_back(stand);
      const V3 c(0, 0, stand_h + r - 0.004);
      o.parts.push_back(Part::cylinder("blade", r, hh, Rigid::translation(c) * Rigid::rot_x(0.5 * kPi)));
      const V3 dir(std::sin(phi), 0, std::cos(phi));
      o.parts.push_back(Part::box("handle", V3(0.5 * L, 0.5 * t, 0.5 * w),
                                  Rigid::translation(c + (r - 0.008 + 0.5 * L) * dir) *
                                      Rigid::rot_y(phi - 0.5 * kPi)));
      break;
    }
    case ObjectKind::wide_box: {
      const double a = rng.uniform(0.10, 0.15), b = rng.uniform(0.10, 0.15), h = rng.uniform(0.05, 0.15);
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
  recentre(o);
  return o;
}

GroundTruth compute_truth(const World& world, int target, const fg::GripperGeometry& gripper,
                          double fit_margin) {
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

GeneratedScene make_scene(ObjectKind kind, uint64_t seed, const SceneOptions& opt) {
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
  const double tx = rng.uniform(opt.target_x_min, opt.target_x_max), ty = rng.uniform(-opt.target_y_half, opt.target_y_half);
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
      if (std::hypot(px - opt.workspace_centre.x(), py - opt.workspace_centre.y()) < target_to_ws + 0.05)
        continue;
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
