// fg_judge SCENE_DIR PLAN_JSON [--mu MU] [-v]
// Judges the answer of `forcegrasp plan SCENE.json --json` (PLAN_JSON: a file, or - for
// stdin) on the true geometry in SCENE_DIR/truth.json. Prints one line
//   <scene> <right|wrong> <reason>
// and exits 0 when right, 1 when wrong, 2 on a usage error, an unreadable truth.json or an
// internal error (an exception, reported on stderr).
// A no_grasp answer is right iff the target fits the gripper in no direction; an ok answer
// is right iff the grasp passes the judge.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

#include "sim/grasp_judge.hpp"
#include "sim/scene_export.hpp"

namespace {

void usage(const char* argv0) {
  std::fprintf(stderr, "usage: %s SCENE_DIR PLAN_JSON [--mu MU] [-v]   (PLAN_JSON may be - for stdin)\n", argv0);
}

std::string scene_name(std::string dir) {
  while (dir.size() > 1 && dir.back() == '/') dir.pop_back();
  const size_t slash = dir.find_last_of('/');
  return slash == std::string::npos ? dir : dir.substr(slash + 1);
}

[[nodiscard]] bool read_vec3(const nlohmann::json& j, fg::Vec3& v) {
  if (!j.is_array() || j.size() != 3) return false;
  for (size_t i = 0; i < 3; ++i) {
    if (!j[i].is_number()) return false;
    v[static_cast<int>(i)] = j[i].get<float>();
  }
  return true;
}

//! The whole program; may throw.
int judge_main(int argc, char** argv) {
  using namespace fg::sim;
  std::string scene_dir, plan_path;
  double mu = 0.5;
  bool verbose = false;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--mu" && i + 1 < argc) {
      char* end = nullptr;
      mu = std::strtod(argv[++i], &end);
      if (!end || *end != '\0' || !(mu >= 0.0)) return usage(argv[0]), 2;
    } else if (a == "-v" || a == "--verbose") {
      verbose = true;
    } else if (a == "-h" || a == "--help") {
      usage(argv[0]);
      return 0;
    } else if (scene_dir.empty()) {
      scene_dir = a;
    } else if (plan_path.empty()) {
      plan_path = a;
    } else {
      return usage(argv[0]), 2;
    }
  }
  if (scene_dir.empty() || plan_path.empty()) return usage(argv[0]), 2;
  // A path to the manifest works too.
  if (scene_dir.size() > 5 && scene_dir.compare(scene_dir.size() - 5, 5, ".json") == 0) {
    const size_t slash = scene_dir.find_last_of('/');
    scene_dir = slash == std::string::npos ? std::string(".") : scene_dir.substr(0, slash);
  }
  const std::string name = scene_name(scene_dir);

  GeneratedScene truth;
  const fg::host::ReadResult tr = read_truth(scene_dir + "/truth.json", truth);
  if (!tr.ok) {
    std::fprintf(stderr, "error: %s\n", tr.error.c_str());
    return 2;
  }

  std::string text;
  if (plan_path == "-") {
    std::ostringstream ss;
    ss << std::cin.rdbuf();
    text = ss.str();
  } else {
    std::ifstream f(plan_path, std::ios::binary);
    if (f) {
      std::ostringstream ss;
      ss << f.rdbuf();
      text = ss.str();
    }
  }
  nlohmann::json plan = nlohmann::json::parse(text, nullptr, false);
  auto verdict = [&](bool right, const std::string& reason) {
    std::printf("%s %s %s\n", name.c_str(), right ? "right" : "wrong", reason.c_str());
    return right ? 0 : 1;
  };
  if (plan.is_discarded() || !plan.is_object() || !plan.contains("status") || !plan["status"].is_string())
    return verdict(false, "plan_unreadable");
  const std::string status = plan["status"].get<std::string>();
  char buf[160];
  if (status == "no_grasp") {
    std::snprintf(buf, sizeof buf, "min_width %.3f", truth.truth.target_min_width);
    return truth.truth.target_fits ? verdict(false, std::string("no_grasp_but_fits ") + buf)
                                   : verdict(true, std::string("no_grasp_correct ") + buf);
  }
  if (status != "ok") return verdict(false, "plan_status " + status);

  Grasp g;
  const nlohmann::json& jg = plan.contains("grasp") ? plan["grasp"] : nlohmann::json();
  if (!jg.is_object() || !read_vec3(jg.value("position", nlohmann::json()), g.position) ||
      !read_vec3(jg.value("approach", nlohmann::json()), g.approach) ||
      !read_vec3(jg.value("closing", nlohmann::json()), g.closing) || !jg.contains("width") || !jg["width"].is_number())
    return verdict(false, "plan_malformed_grasp");
  g.width = jg["width"].get<float>();

  const JudgeResult r = judge_grasp(truth.world, truth.target, g, truth.gripper, mu);
  if (verbose) {
    std::fprintf(stderr,
                 "%s: true_width %.4f reported %.4f angles %.1f/%.1f deg contacts (%.3f %.3f %.3f) "
                 "(%.3f %.3f %.3f) target fits %d min_width %.3f\n",
                 name.c_str(), r.true_width, g.width, r.angle_left * 57.29578f, r.angle_right * 57.29578f,
                 r.contact_left.x(), r.contact_left.y(), r.contact_left.z(), r.contact_right.x(), r.contact_right.y(),
                 r.contact_right.z(), truth.truth.target_fits ? 1 : 0, truth.truth.target_min_width);
  }
  return verdict(r.success, r.reason);
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return judge_main(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: internal: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "error: internal: unknown exception\n");
  }
  return 2;
}
