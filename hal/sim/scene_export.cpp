#include "sim/scene_export.hpp"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "io/scene.hpp"
#include "sim/obj_mesh.hpp"

namespace fg::sim {

namespace {

using fg::host::ReadResult;
using nlohmann::json;

json vec_json(const V3& v) { return json::array({v.x(), v.y(), v.z()}); }

json pose_json(const Rigid& p) {
  json rows = json::array();
  for (int i = 0; i < 3; ++i) rows.push_back(json::array({p.R(i, 0), p.R(i, 1), p.R(i, 2)}));
  return json{{"position", vec_json(p.t)}, {"rotation", rows}};
}

V3 read_vec(const json& j) {
  if (!j.is_array() || j.size() != 3) throw std::runtime_error("expected an array of 3 numbers");
  return V3(j[0].get<double>(), j[1].get<double>(), j[2].get<double>());
}

Rigid read_pose(const json& j) {
  Rigid p;
  p.t = read_vec(j.at("position"));
  const json& rows = j.at("rotation");
  if (!rows.is_array() || rows.size() != 3) throw std::runtime_error("rotation must have 3 rows");
  for (int i = 0; i < 3; ++i) p.R.row(i) = read_vec(rows[static_cast<size_t>(i)]).transpose();
  return p;
}

// Float parameters written with 6 decimals (0.085f -> 0.085, not 0.0850000008940697).
double tidy(float v) { return std::round(static_cast<double>(v) * 1e6) / 1e6; }

json intrinsics_json(const Intrinsics& K) {
  return json{{"width", K.width}, {"height", K.height}, {"fx", K.fx}, {"fy", K.fy}, {"cx", K.cx}, {"cy", K.cy}};
}

Intrinsics read_intrinsics(const json& j) {
  Intrinsics K;
  K.width = j.at("width").get<int>();
  K.height = j.at("height").get<int>();
  K.fx = j.at("fx").get<double>();
  K.fy = j.at("fy").get<double>();
  K.cx = j.at("cx").get<double>();
  K.cy = j.at("cy").get<double>();
  return K;
}

json part_json(const Part& p) {
  json j{{"name", p.name},
         {"shape", shape_name(p.shape)},
         {"graspable", p.graspable},
         {"pose", pose_json(p.world_T_shape)}};
  switch (p.shape) {
    case Shape::box:
      j["half_extents"] = vec_json(p.size);
      break;
    case Shape::cylinder:
      j["radius"] = p.radius();
      j["half_height"] = p.half_height();
      break;
    case Shape::sphere:
      j["radius"] = p.radius();
      break;
    case Shape::ellipsoid:
      j["semi_axes"] = vec_json(p.size);
      break;
    case Shape::mesh:
      j["mesh"] = p.triangle_mesh ? p.triangle_mesh->source() : std::string();
      break;
  }
  return j;
}

Part read_part(const json& j) {
  Part p;
  p.name = j.value("name", std::string());
  if (!shape_from_name(j.at("shape").get<std::string>(), p.shape))
    throw std::runtime_error("unknown shape " + j.at("shape").get<std::string>());
  p.graspable = j.value("graspable", true);
  p.world_T_shape = read_pose(j.at("pose"));
  switch (p.shape) {
    case Shape::box:
      p.size = read_vec(j.at("half_extents"));
      break;
    case Shape::cylinder: {
      const double r = j.at("radius").get<double>();
      p.size = V3(r, r, j.at("half_height").get<double>());
      break;
    }
    case Shape::sphere:
      p.size = V3::Constant(j.at("radius").get<double>());
      break;
    case Shape::ellipsoid:
      p.size = read_vec(j.at("semi_axes"));
      break;
    case Shape::mesh: {
      // The OBJ file is read again (once per process); a flat mesh may have a zero size.
      std::string error;
      std::shared_ptr<const TriangleMesh> mesh = load_obj_cached(j.at("mesh").get<std::string>(), error);
      if (!mesh) throw std::runtime_error("part " + p.name + ": " + error);
      Part m = Part::mesh(p.name, std::move(mesh), p.world_T_shape);
      m.graspable = p.graspable;
      return m;
    }
  }
  if (!(p.size.array() > 0.0).all() || !p.size.allFinite())
    throw std::runtime_error("part " + p.name + " has a non-positive size");
  return p;
}

json camera_json(const Camera& c, uint64_t noise_seed) {
  return json{{"pose", pose_json(c.world_T_sensor)}, {"intrinsics", intrinsics_json(c.K)}, {"noise_seed", noise_seed}};
}

fg::host::PoseD to_posed(const Rigid& r) {
  fg::host::PoseD p;
  for (int i = 0; i < 3; ++i) {
    p.position[static_cast<size_t>(i)] = r.t[i];
    for (int k = 0; k < 3; ++k) p.rotation[static_cast<size_t>(i)][static_cast<size_t>(k)] = r.R(i, k);
  }
  return p;
}

}  // namespace

std::string truth_to_json(const GeneratedScene& s) {
  json objects = json::array();
  for (const Object& o : s.world.objects) {
    json parts = json::array();
    for (const Part& p : o.parts) parts.push_back(part_json(p));
    json jo{{"name", o.name}, {"kind", o.kind}, {"parts", parts}};
    if (o.albedo != 1.0) jo["albedo"] = o.albedo;  // written only when set: classic files stay as they were
    objects.push_back(jo);
  }
  const Table& t = s.world.table;
  const NoiseModel& n = s.noise;
  const fg::GripperGeometry& g = s.gripper;
  json root{
      {"format", "forcegrasp-sim-truth"},
      {"version", 1},
      {"kind", s.kind},
      {"seed", s.seed},
      {"table",
       {{"present", s.world.has_table},
        {"height", t.height},
        {"x", {t.x_min, t.x_max}},
        {"y", {t.y_min, t.y_max}},
        {"thickness", t.thickness}}},
      {"objects", objects},
      {"target", s.target},
      {"target_fits", s.truth.target_fits},
      {"target_min_width", s.truth.target_min_width},
      {"fit_margin", s.truth.fit_margin},
      {"target_centre", vec_json(s.truth.target_centre)},
      {"target_box", {{"min", vec_json(s.truth.target_box.lo)}, {"max", vec_json(s.truth.target_box.hi)}}},
      {"gripper",
       {{"max_opening", tidy(g.max_opening_m)},
        {"min_opening", tidy(g.min_opening_m)},
        {"finger_width", tidy(g.finger_width_m)},
        {"finger_depth", tidy(g.finger_depth_m)},
        {"finger_thickness", tidy(g.finger_thickness_m)},
        {"palm_depth", tidy(g.palm_depth_m)},
        {"palm_width", tidy(g.palm_width_m)}}},
      {"cameras", {{"head", camera_json(s.head, s.head_noise_seed)}, {"hand", camera_json(s.hand, s.hand_noise_seed)}}},
      {"noise",
       {{"gaussian", n.gaussian},
        {"sigma_a", n.sigma_a},
        {"sigma_b", n.sigma_b},
        {"sigma_z0", n.sigma_z0},
        {"quantize", n.quantize},
        {"quant_k", n.quant_k},
        {"max_incidence_deg", n.max_incidence_deg},
        {"z_min", n.z_min},
        {"z_max", n.z_max},
        {"edge_dropout", n.edge_dropout},
        {"edge_jump", n.edge_jump}}},
  };
  // What classic scenes never set is written only when set, so their files stay as they were.
  if (s.distribution != Distribution::classic) root["distribution"] = distribution_name(s.distribution);
  if (t.albedo != 1.0) root["table"]["albedo"] = t.albedo;
  json& jn = root["noise"];
  if (n.edge_band_px != 1) jn["edge_band_px"] = n.edge_band_px;
  if (n.projector_shadow) {
    jn["projector_shadow"] = true;
    jn["projector_baseline"] = n.projector_baseline;
  }
  if (n.dark_dropout) {
    jn["dark_dropout"] = true;
    jn["return_none"] = n.return_none;
    jn["return_full"] = n.return_full;
  }
  if (n.steep_dropout) {
    jn["steep_dropout"] = true;
    jn["steep_from_deg"] = n.steep_from_deg;
  }
  return root.dump(1) + "\n";
}

ReadResult parse_truth(const std::string& text, const std::string& name, GeneratedScene& out) {
  try {
    const json root = json::parse(text);
    if (root.value("format", std::string()) != "forcegrasp-sim-truth")
      return ReadResult::failure(name + ": not a forcegrasp-sim-truth file");
    GeneratedScene s;
    s.kind = root.value("kind", std::string());
    s.seed = root.value("seed", uint64_t{0});
    const json& t = root.at("table");
    s.world.has_table = t.value("present", true);
    s.world.table.height = t.at("height").get<double>();
    s.world.table.x_min = t.at("x").at(0).get<double>();
    s.world.table.x_max = t.at("x").at(1).get<double>();
    s.world.table.y_min = t.at("y").at(0).get<double>();
    s.world.table.y_max = t.at("y").at(1).get<double>();
    s.world.table.thickness = t.value("thickness", 0.03);
    s.world.table.albedo = t.value("albedo", 1.0);
    if (root.contains("distribution") &&
        !distribution_from_name(root["distribution"].get<std::string>(), s.distribution))
      return ReadResult::failure(name + ": unknown distribution " + root["distribution"].get<std::string>());
    for (const json& jo : root.at("objects")) {
      Object o;
      o.name = jo.value("name", std::string());
      o.kind = jo.value("kind", std::string());
      o.albedo = jo.value("albedo", 1.0);
      for (const json& jp : jo.at("parts")) o.parts.push_back(read_part(jp));
      s.world.objects.push_back(std::move(o));
    }
    s.target = root.at("target").get<int>();
    if (s.target < 0 || static_cast<size_t>(s.target) >= s.world.objects.size())
      return ReadResult::failure(name + ": target index out of range");
    if (root.contains("gripper")) {
      const json& g = root["gripper"];
      s.gripper.max_opening_m = g.value("max_opening", s.gripper.max_opening_m);
      s.gripper.min_opening_m = g.value("min_opening", s.gripper.min_opening_m);
      s.gripper.finger_width_m = g.value("finger_width", s.gripper.finger_width_m);
      s.gripper.finger_depth_m = g.value("finger_depth", s.gripper.finger_depth_m);
      s.gripper.finger_thickness_m = g.value("finger_thickness", s.gripper.finger_thickness_m);
      s.gripper.palm_depth_m = g.value("palm_depth", s.gripper.palm_depth_m);
      s.gripper.palm_width_m = g.value("palm_width", s.gripper.palm_width_m);
    }
    if (root.contains("cameras")) {
      const json& c = root["cameras"];
      if (c.contains("head")) {
        s.head.world_T_sensor = read_pose(c["head"].at("pose"));
        s.head.K = read_intrinsics(c["head"].at("intrinsics"));
        s.head_noise_seed = c["head"].value("noise_seed", uint64_t{0});
      }
      if (c.contains("hand")) {
        s.hand.world_T_sensor = read_pose(c["hand"].at("pose"));
        s.hand.K = read_intrinsics(c["hand"].at("intrinsics"));
        s.hand_noise_seed = c["hand"].value("noise_seed", uint64_t{0});
      }
    }
    if (root.contains("noise")) {
      const json& n = root["noise"];
      NoiseModel& m = s.noise;
      m.gaussian = n.value("gaussian", m.gaussian);
      m.sigma_a = n.value("sigma_a", m.sigma_a);
      m.sigma_b = n.value("sigma_b", m.sigma_b);
      m.sigma_z0 = n.value("sigma_z0", m.sigma_z0);
      m.quantize = n.value("quantize", m.quantize);
      m.quant_k = n.value("quant_k", m.quant_k);
      m.max_incidence_deg = n.value("max_incidence_deg", m.max_incidence_deg);
      m.z_min = n.value("z_min", m.z_min);
      m.z_max = n.value("z_max", m.z_max);
      m.edge_dropout = n.value("edge_dropout", m.edge_dropout);
      m.edge_jump = n.value("edge_jump", m.edge_jump);
      m.edge_band_px = n.value("edge_band_px", m.edge_band_px);
      m.projector_shadow = n.value("projector_shadow", m.projector_shadow);
      m.projector_baseline = n.value("projector_baseline", m.projector_baseline);
      m.dark_dropout = n.value("dark_dropout", m.dark_dropout);
      m.return_none = n.value("return_none", m.return_none);
      m.return_full = n.value("return_full", m.return_full);
      m.steep_dropout = n.value("steep_dropout", m.steep_dropout);
      m.steep_from_deg = n.value("steep_from_deg", m.steep_from_deg);
    }
    // The facts are recomputed from the geometry (the stored ones are for people and scripts).
    s.truth = compute_truth(s.world, s.target, s.gripper, root.value("fit_margin", 0.005));
    if (root.contains("target_fits") && root["target_fits"].get<bool>() != s.truth.target_fits)
      return ReadResult::failure(name + ": target_fits disagrees with the geometry");
    out = std::move(s);
    return {};
  } catch (const std::exception& e) {
    return ReadResult::failure(name + ": " + e.what());
  }
}

ReadResult write_truth(const std::string& path, const GeneratedScene& scene) {
  std::ofstream f(path);
  if (!f) return ReadResult::failure(path + ": cannot write");
  f << truth_to_json(scene);
  if (!f) return ReadResult::failure(path + ": write failed");
  return {};
}

ReadResult read_truth(const std::string& path, GeneratedScene& out) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return ReadResult::failure(path + ": cannot open");
  std::ostringstream ss;
  ss << f.rdbuf();
  return parse_truth(ss.str(), path, out);
}

ReadResult export_scene(const GeneratedScene& scene, const std::string& dir, const ExportOptions& options) {
  return export_scene(scene, render_scene(scene), dir, options);
}

ReadResult export_scene(const GeneratedScene& scene, const SceneImages& images, const std::string& dir,
                        const ExportOptions& options) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) return ReadResult::failure(dir + ": cannot create the folder: " + ec.message());
  const std::string base = dir.empty() || dir.back() == '/' ? dir : dir + "/";

  ReadResult r = fg::host::write_pcd(base + "head.pcd", depth_to_cloud(images.head, scene.head.K), options.encoding);
  if (!r.ok) return r;
  r = fg::host::write_pcd(base + "hand.pcd", depth_to_cloud(images.hand, scene.hand.K), options.encoding);
  if (!r.ok) return r;

  fg::host::Scene manifest;
  fg::host::SceneSensor head;
  head.name = "head";
  head.cloud_path = "head.pcd";
  head.pose = to_posed(scene.head.world_T_sensor);
  fg::host::SceneSensor hand;
  hand.name = "hand";
  hand.cloud_path = "hand.pcd";
  hand.pose = to_posed(scene.hand.world_T_sensor);
  manifest.sensors = {head, hand};
  manifest.gripper.max_opening = tidy(scene.gripper.max_opening_m);
  manifest.gripper.finger_width = tidy(scene.gripper.finger_width_m);
  manifest.gripper.finger_depth = tidy(scene.gripper.finger_depth_m);
  r = fg::host::write_scene(base + "scene.json", manifest);
  if (!r.ok) return r;
  return write_truth(base + "truth.json", scene);
}

}  // namespace fg::sim
