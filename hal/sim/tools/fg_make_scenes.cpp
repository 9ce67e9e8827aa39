// fg_make_scenes OUTDIR [--count N] [--seed S] [--kinds k1,k2,...] [--second-object-rate R]
//                       [--encoding binary|ascii|binary_compressed] [--no-noise]
//                       [--distribution classic|cell]
// Writes OUTDIR/<kind>-<seed>/ scene folders (scene.json, head.pcd, hand.pcd, truth.json):
// scene i has kind kinds[i % kinds] (a balanced mix) and seed S + i. The distribution is
// classic unless given (scene_gen.hpp); --second-object-rate is classic's.
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "sim/scene_export.hpp"
#include "sim/scene_gen.hpp"

namespace {

void usage(const char* argv0) {
  std::fprintf(stderr,
               "usage: %s OUTDIR [--count N] [--seed S] [--kinds k1,k2,...] [--second-object-rate R]\n"
               "       [--encoding binary|ascii|binary_compressed] [--no-noise] [--distribution classic|cell]\n"
               "kinds:",
               argv0);
  for (fg::sim::ObjectKind k : fg::sim::all_kinds()) std::fprintf(stderr, " %s", fg::sim::kind_name(k));
  std::fprintf(stderr, "\n");
}

bool parse_u64(const std::string& s, unsigned long long& out) {
  if (s.empty() || s[0] == '-') return false;
  char* end = nullptr;
  out = std::strtoull(s.c_str(), &end, 10);
  return end && *end == '\0';
}

[[nodiscard]] bool parse_double(const std::string& s, double& out) {
  char* end = nullptr;
  out = std::strtod(s.c_str(), &end);
  return !s.empty() && end && *end == '\0';
}

}  // namespace

int main(int argc, char** argv) {
  using namespace fg::sim;
  std::string outdir;
  unsigned long long count = 0, seed = 1;
  bool count_given = false;
  std::vector<ObjectKind> kinds = all_kinds();
  SceneOptions opt;
  ExportOptions eopt;
  // The distribution first: the other options change its ranges, whatever their order.
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::string(argv[i]) != "--distribution") continue;
    Distribution d;
    if (!distribution_from_name(argv[i + 1], d)) return usage(argv[0]), 2;
    opt = SceneOptions::of(d);
  }
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&](std::string& v) {
      if (i + 1 >= argc) return false;
      v = argv[++i];
      return true;
    };
    std::string v;
    if (a == "-h" || a == "--help") {
      usage(argv[0]);
      return 0;
    } else if (a == "--count") {
      if (!value(v) || !parse_u64(v, count)) return usage(argv[0]), 2;
      count_given = true;
    } else if (a == "--seed") {
      if (!value(v) || !parse_u64(v, seed)) return usage(argv[0]), 2;
    } else if (a == "--second-object-rate") {
      if (!value(v) || !parse_double(v, opt.second_object_rate) || opt.second_object_rate < 0 ||
          opt.second_object_rate > 1)
        return usage(argv[0]), 2;
    } else if (a == "--kinds") {
      if (!value(v)) return usage(argv[0]), 2;
      kinds.clear();
      size_t start = 0;
      while (start <= v.size()) {
        const size_t comma = v.find(',', start);
        const std::string name = v.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
        if (!name.empty()) {
          ObjectKind k;
          if (!kind_from_name(name, k)) {
            std::fprintf(stderr, "unknown kind '%s'\n", name.c_str());
            usage(argv[0]);
            return 2;
          }
          kinds.push_back(k);
        }
        if (comma == std::string::npos) break;
        start = comma + 1;
      }
      if (kinds.empty()) return usage(argv[0]), 2;
    } else if (a == "--encoding") {
      if (!value(v)) return usage(argv[0]), 2;
      if (v == "binary")
        eopt.encoding = fg::host::PcdEncoding::binary;
      else if (v == "ascii")
        eopt.encoding = fg::host::PcdEncoding::ascii;
      else if (v == "binary_compressed")
        eopt.encoding = fg::host::PcdEncoding::binary_compressed;
      else
        return usage(argv[0]), 2;
    } else if (a == "--distribution") {
      if (!value(v)) return usage(argv[0]), 2;  // read above
    } else if (a == "--no-noise") {
      opt.noise = NoiseModel::none();
    } else if (!a.empty() && a[0] == '-') {
      std::fprintf(stderr, "unknown option '%s'\n", a.c_str());
      usage(argv[0]);
      return 2;
    } else if (outdir.empty()) {
      outdir = a;
    } else {
      usage(argv[0]);
      return 2;
    }
  }
  if (outdir.empty()) return usage(argv[0]), 2;
  if (!count_given) count = 2 * kinds.size();

  int fits = 0, second = 0;
  for (unsigned long long i = 0; i < count; ++i) {
    const ObjectKind kind = kinds[i % kinds.size()];
    const unsigned long long s = seed + i;
    const GeneratedScene scene = make_scene(kind, s, opt);
    const std::string dir = outdir + "/" + kind_name(kind) + "-" + std::to_string(s);
    const fg::host::ReadResult r = export_scene(scene, dir, eopt);
    if (!r.ok) {
      std::fprintf(stderr, "error: %s\n", r.error.c_str());
      return 1;
    }
    fits += scene.truth.target_fits ? 1 : 0;
    second += scene.world.objects.size() > 1 ? 1 : 0;
    std::printf("%s fits=%d min_width=%.3f objects=%zu\n", dir.c_str(), scene.truth.target_fits ? 1 : 0,
                scene.truth.target_min_width, scene.world.objects.size());
  }
  std::fprintf(stderr, "%llu scenes in %s (%d targets fit the gripper, %d with a second object)\n", count,
               outdir.c_str(), fits, second);
  return 0;
}
