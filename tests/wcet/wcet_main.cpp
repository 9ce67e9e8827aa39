// fg_wcet: worst-case timing harness (issue 4, item 4; docs/worst-case-timing.md).
// Runs each case of wcet_cases.cpp through the public Planner API (reset, add_points /
// add_depth_image, plan) and reports, per stage of PlanResult::stage_us, the median and
// the largest time over the runs, the whole public calls, and the planner's status.
//
//   fg_wcet [--runs N] [--case a,b] [--json FILE] [--markdown FILE] [--points N]
//   fg_wcet --case NAME --once [--ir PREFIX | --profile]   (one run, for valgrind)
//   fg_wcet --smoke        (the cheap cases once each; exit 1 on an undefined outcome)
//   fg_wcet --list
//
// Under valgrind --tool=callgrind --collect-atstart=no, --ir PREFIX counts instructions
// instead of microseconds (wcet_clock.hpp); --profile only switches collection on around
// the measured calls (for callgrind_annotate). scripts/wcet.sh drives both.
#include <pthread.h>
#include <sys/mman.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "fg/core/limits.hpp"
#include "fg/core/planner.hpp"
#include "fg/robot/ur5_grasp_check.hpp"
#include "wcet_cases.hpp"
#include "wcet_clock.hpp"

#ifndef FG_WCET_LIMITS
#define FG_WCET_LIMITS "unknown"
#endif

namespace {

using fg::wcet::CaseInfo;
using fg::wcet::CaseInput;

constexpr int kStages = static_cast<int>(fg::Stage::count);
// Report columns: the planner's stages, then the whole public calls.
enum Extra { kReset = kStages, kAdd, kPlan, kColumns };
const char* column_name(int c) {
  if (c < kStages) return fg::to_string(static_cast<fg::Stage>(c));
  switch (c) {
    case kReset:
      return "reset";
    case kAdd:
      return "add";
    case kPlan:
      return "plan";
    default:
      return "?";
  }
}

struct RunValues {
  double v[kColumns] = {};
};

struct CaseReport {
  const CaseInfo* info = nullptr;
  CaseInput input;
  std::string build_error;
  fg::Status add_status = fg::Status::ok;
  std::string add_message;
  fg::PlanResult result;
  std::vector<RunValues> runs;
  uint32_t max_contour = 0, max_lines = 0;  // over all viewpoints (timed mode only)
  bool analysed_views = false;
  int64_t stack_bytes = -1;     // measured high-water of reset + add + plan (timed mode)
  uint32_t hash_max_probe = 0;  // voxel hash: longest displacement from the home slot
  double hash_mean_probe = 0;
  std::vector<std::string> saturated;  // capacities reached, and what the planner did
  std::vector<std::string> problems;   // undefined outcomes (smoke failures)
};

double now_us() {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

double median(std::vector<double> v) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  const size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

[[nodiscard]] fg::Status add_sensor(fg::Planner& p, const fg::wcet::SensorInput& s) {
  if (s.is_image()) return p.add_depth_image(s.role, s.depth.data(), s.width, s.height, s.k, s.pose);
  return p.add_points(s.role, s.xyz.data(), s.points(), 12, s.pose);
}

// One measured run: [reset], add every sensor, plan. In instruction mode the values are
// instructions, else microseconds. `reset_after` measures the reset that forgets this
// run's data after the plan (the --once order) instead of the one before it.
RunValues run_once(fg::Planner& p, CaseReport& rep, bool reset_after, bool ir) {
  RunValues rv;
  auto clock = [ir]() { return ir ? static_cast<double>(fg::wcet::counter_now()) : now_us(); };
  fg::wcet::collect_begin();
  double t = 0;
  if (!reset_after) {
    t = clock();
    p.reset();
    rv.v[kReset] = clock() - t;
  }
  rep.add_status = fg::Status::ok;
  t = clock();
  for (const auto& s : rep.input.sensors) {
    const fg::Status st = add_sensor(p, s);
    if (st != fg::Status::ok && rep.add_status == fg::Status::ok) {
      rep.add_status = st;
      rep.add_message = p.last_message();
    }
  }
  rv.v[kAdd] = clock() - t;
  t = clock();
  (void)p.plan(rep.result);
  rv.v[kPlan] = clock() - t;
  fg::wcet::collect_end();
  if (reset_after) {
    fg::wcet::collect_begin();
    t = clock();
    p.reset();
    rv.v[kReset] = clock() - t;
    fg::wcet::collect_end();
  }
  const double unit = ir ? static_cast<double>(fg::wcet::kIrUnit) : 1.0;
  for (int s = 0; s < kStages; ++s) rv.v[s] = unit * rep.result.stage_us[s];
  return rv;
}

// What a capacity-saturating case did, and anything that is not a defined outcome.
void judge(CaseReport& rep) {
  const fg::PlanResult& r = rep.result;
  const fg::Status st = r.status;
  if (st == fg::Status::internal_error || st == fg::Status::numeric_failure)
    rep.problems.push_back(std::string("plan returned ") + fg::to_string(st));
  if (rep.add_status != fg::Status::ok && rep.add_status != fg::Status::capacity_exceeded)
    rep.problems.push_back(std::string("add returned ") + fg::to_string(rep.add_status));
  if (st != fg::Status::ok && (r.message == nullptr || r.message[0] == '\0'))
    rep.problems.push_back("no message with a non-ok status");
  if (rep.add_status == fg::Status::capacity_exceeded) {
    rep.saturated.push_back("voxels: add_* returned capacity_exceeded, plan() " + std::string(fg::to_string(st)));
    if (st != fg::Status::capacity_exceeded)
      rep.problems.push_back("plan after a full grid did not return capacity_exceeded");
  } else if (r.points.voxels == fg::kMaxVoxels) {
    rep.saturated.push_back("voxels: exactly kMaxVoxels, accepted");
  }
  if (st == fg::Status::capacity_exceeded && rep.add_status == fg::Status::ok)
    rep.saturated.push_back(std::string("plan() capacity_exceeded: ") + r.message);
  if (r.viewpoints == fg::kMaxViewpoints) rep.saturated.push_back("viewpoints: kMaxViewpoints, the rest not searched");
  if (r.candidates == fg::kMaxCandidates) rep.saturated.push_back("candidates: kMaxCandidates, later windows dropped");
  if (rep.analysed_views && rep.max_lines == fg::kMaxScanLines)
    rep.saturated.push_back("scan lines: kMaxScanLines, spacing widened to fit");
  if (rep.analysed_views && rep.max_contour >= fg::kMaxContourVertices)
    rep.saturated.push_back("contour: kMaxContourVertices, view skipped");
  if (rep.input.name == "voxel_overflow" && rep.add_status != fg::Status::capacity_exceeded)
    rep.problems.push_back("voxel_overflow did not report capacity_exceeded");
}

void analyse_views(fg::Planner& p, CaseReport& rep) {
  auto d = std::make_unique<fg::ViewDetail>();
  for (uint32_t v = 0; v < p.view_count(); ++v) {
    if (p.analyze_view(v, *d) != fg::Status::ok) continue;
    rep.max_contour = std::max(rep.max_contour, d->n_contour);
    rep.max_lines = std::max(rep.max_lines, d->n_lines);
  }
  rep.analysed_views = true;
}

// Measured stack use: runs `fn` on a thread whose 1 MiB stack is painted with a pattern
// and returns how far below the thread's first frame the pattern was overwritten
// (everything fn called: the planner, libm, libc), minus the same for an empty call.
int64_t stack_high_water(const std::function<void()>& fn) {
  struct Job {
    const std::function<void()>* fn;
    uintptr_t top;
  };
  auto measure = [](const std::function<void()>* f) -> int64_t {
    constexpr size_t kSize = 1u << 20;
    void* mem = mmap(nullptr, kSize, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
    if (mem == MAP_FAILED) return -1;
    std::memset(mem, 0xA5, kSize);
    pthread_attr_t attr;
    pthread_attr_init(&attr);
    pthread_attr_setstack(&attr, mem, kSize);
    Job job{f, 0};
    pthread_t th;
    const int rc = pthread_create(
        &th, &attr,
        [](void* p) -> void* {
          Job* j = static_cast<Job*>(p);
          volatile char mark = 0;
          j->top = reinterpret_cast<uintptr_t>(&mark);
          if (*j->fn) (*j->fn)();
          return nullptr;
        },
        &job);
    pthread_attr_destroy(&attr);
    if (rc != 0) {
      munmap(mem, kSize);
      return -1;
    }
    pthread_join(th, nullptr);
    const unsigned char* b = static_cast<const unsigned char*>(mem);
    size_t i = 0;
    while (i < kSize && b[i] == 0xA5) ++i;
    const int64_t used = static_cast<int64_t>(job.top) - static_cast<int64_t>(reinterpret_cast<uintptr_t>(mem) + i);
    munmap(mem, kSize);
    return used;
  };
  const std::function<void()> empty;
  const int64_t base = measure(&empty), used = measure(&fn);
  return used < 0 || base < 0 ? -1 : used - base;
}

// The voxel hash's probe lengths for this case's voxels: the grid's keys inserted in
// the grid's order into a mirror of voxel_grid.hpp's table (same multiplicative hash,
// same linear probing). Diagnostic only (timed mode).
void hash_probes(const fg::Planner& p, CaseReport& rep) {
  const fg::VoxelGrid& g = p.voxels();
  uint32_t bits = 0;
  while ((1u << bits) < fg::kVoxelHashSlots) ++bits;
  std::vector<uint8_t> used(fg::kVoxelHashSlots, 0);
  uint64_t sum = 0;
  for (uint32_t i = 0; i < g.size(); ++i) {
    uint32_t s = (g.voxel(i).key * 0x9E3779B1u) >> (32 - bits), d = 0;
    while (used[s]) s = (s + 1) & (fg::kVoxelHashSlots - 1), ++d;
    used[s] = 1;
    sum += d;
    rep.hash_max_probe = std::max(rep.hash_max_probe, d);
  }
  rep.hash_mean_probe = g.size() ? static_cast<double>(sum) / g.size() : 0.0;
}

std::string status_text(const CaseReport& r) {
  std::string s = fg::to_string(r.result.status);
  if (r.result.status == fg::Status::no_grasp) s += std::string("/") + fg::to_string(r.result.reason);
  return s;
}

struct Options {
  int runs = 20;
  bool once = false, smoke = false, profile = false, warmup = true, quiet = false;
  std::string ir_prefix, json_path, md_path;
  std::vector<std::string> cases;
  uint32_t points = 0;
  uint32_t hash_cells = 0;
};

nlohmann::json to_json(const std::vector<CaseReport>& reps, const Options& o) {
  nlohmann::json j;
  j["limits"] = FG_WCET_LIMITS;
  j["sizeof_planner"] = sizeof(fg::Planner);
  j["unit"] = o.ir_prefix.empty() ? "us" : "Ir";
  j["runs"] = o.once ? 1 : o.runs;
  j["points_per_sensor"] = o.points;
  j["reference_typical"] = fg::wcet::reference_typical_case();
  j["capacities"] = {{"kMaxVoxels", fg::kMaxVoxels},
                     {"kVoxelHashSlots", fg::kVoxelHashSlots},
                     {"kMaxObjectPoints", fg::kMaxObjectPoints},
                     {"kHullGridDim", fg::kHullGridDim},
                     {"kMaxContourVertices", fg::kMaxContourVertices},
                     {"kMaxScanLines", fg::kMaxScanLines},
                     {"kMaxViewpoints", fg::kMaxViewpoints},
                     {"kMaxCandidates", fg::kMaxCandidates},
                     {"kRansacMaxIters", fg::kRansacMaxIters},
                     {"kMaxSensors", fg::kMaxSensors},
                     {"kSightBins", fg::kSightBins},
                     {"kVoxelCacheBits", fg::kVoxelCacheBits}};
  nlohmann::json cs = nlohmann::json::array();
  for (const CaseReport& r : reps) {
    nlohmann::json c;
    c["name"] = r.input.name;
    c["targets"] = r.info->targets;
    c["what"] = r.info->what;
    c["typical"] = r.info->typical;
    if (!r.build_error.empty()) {
      c["error"] = r.build_error;
      cs.push_back(c);
      continue;
    }
    c["note"] = r.input.note;
    c["overrides"] = r.input.overrides;
    uint64_t offered = 0;
    for (const auto& s : r.input.sensors) offered += s.points();
    c["input_points"] = offered;
    c["distinct_cells"] = r.input.distinct_cells;
    c["add_status"] = fg::to_string(r.add_status);
    c["status"] = fg::to_string(r.result.status);
    c["reason"] = fg::to_string(r.result.reason);
    c["message"] = r.result.message;
    c["voxels"] = r.result.points.voxels;
    c["plane_voxels"] = r.result.points.plane;
    c["object_points"] = r.result.points.object;
    c["viewpoints"] = r.result.viewpoints;
    c["candidates"] = r.result.candidates;
    c["rejected"] = {{"table", r.result.rejected.table},
                     {"collision", r.result.rejected.collision},
                     {"friction", r.result.rejected.friction},
                     {"occluded", r.result.rejected.occluded}};
    if (r.analysed_views) {
      c["max_contour_vertices"] = r.max_contour;
      c["max_scan_lines"] = r.max_lines;
    }
    if (r.analysed_views) {
      c["hash_max_displacement"] = r.hash_max_probe;
      c["hash_mean_displacement"] = r.hash_mean_probe;
    }
    if (r.stack_bytes >= 0) c["stack_high_water_bytes"] = r.stack_bytes;
    c["saturated"] = r.saturated;
    c["problems"] = r.problems;
    nlohmann::json st;
    for (int k = 0; k < kColumns; ++k) {
      std::vector<double> v;
      for (const RunValues& rv : r.runs) v.push_back(rv.v[k]);
      st[column_name(k)] = {{"median", median(v)}, {"max", v.empty() ? 0.0 : *std::max_element(v.begin(), v.end())}};
    }
    c["stats"] = st;
    cs.push_back(c);
  }
  j["cases"] = cs;
  return j;
}

std::string number(double v, bool ir) {
  char b[64];
  if (ir || v >= 100)  // instructions, and times from 100 us on, in whole units
    std::snprintf(b, sizeof b, "%.0f", v);
  else
    std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

std::string table(const std::vector<CaseReport>& reps, const Options& o, bool markdown) {
  const bool ir = !o.ir_prefix.empty();
  std::ostringstream out;
  const int cols[] = {0, 1, 2, 3, 4, 5, 6, 7, kReset, kAdd, kPlan};
  if (markdown) {
    out << "| case | status | voxels | object | views | cands |";
    for (int c : cols) out << ' ' << column_name(c) << " |";
    out << "\n|---|---|---|---|---|---|";
    for (size_t i = 0; i < std::size(cols); ++i) out << "---|";
    out << "\n";
  } else {
    char b[256];
    std::snprintf(b, sizeof b, "%-16s %-26s %7s %6s %5s %5s", "case", "status", "voxels", "object", "views", "cands");
    out << b;
    for (int c : cols) {
      std::snprintf(b, sizeof b, " %17s", column_name(c));
      out << b;
    }
    out << "\n";
  }
  for (const CaseReport& r : reps) {
    if (!r.build_error.empty()) {
      out << (markdown ? "| " : "") << r.input.name << (markdown ? " | not built: " : "  not built: ") << r.build_error
          << (markdown ? " |\n" : "\n");
      continue;
    }
    std::string status;  // "add <status>, " first when an add_* call failed
    if (r.add_status != fg::Status::ok) {
      status = "add ";
      status += fg::to_string(r.add_status);
      status += ", ";
    }
    status += status_text(r);
    char b[256];
    if (markdown)
      std::snprintf(b, sizeof b, "| %s | %s | %u | %u | %u | %u |", r.input.name.c_str(), status.c_str(),
                    r.result.points.voxels, r.result.points.object, r.result.viewpoints, r.result.candidates);
    else
      std::snprintf(b, sizeof b, "%-16s %-26s %7u %6u %5u %5u", r.input.name.c_str(), status.c_str(),
                    r.result.points.voxels, r.result.points.object, r.result.viewpoints, r.result.candidates);
    out << b;
    for (int c : cols) {
      std::vector<double> v;
      for (const RunValues& rv : r.runs) v.push_back(rv.v[c]);
      const double med = median(v), mx = v.empty() ? 0 : *std::max_element(v.begin(), v.end());
      const std::string cell = (o.once || v.size() == 1) ? number(med, ir) : number(med, ir) + " / " + number(mx, ir);
      if (markdown)
        out << ' ' << cell << " |";
      else {
        std::snprintf(b, sizeof b, " %17s", cell.c_str());
        out << b;
      }
    }
    out << "\n";
  }
  return out.str();
}

std::vector<std::string> split(const std::string& s) {
  std::vector<std::string> v;
  std::stringstream ss(s);
  std::string x;
  while (std::getline(ss, x, ','))
    if (!x.empty()) v.push_back(x);
  return v;
}

[[nodiscard]] int usage() {
  std::fprintf(stderr,
               "usage: fg_wcet [--runs N] [--case a,b] [--json FILE] [--markdown FILE] [--points N] [--no-warmup]\n"
               "              [--hash-cells N] [--quiet]\n"
               "       fg_wcet --case NAME --once [--ir PREFIX | --profile] [--json FILE]\n"
               "       fg_wcet --smoke | --list\n");
  return 2;
}

void print_case_list() {
  for (const CaseInfo& c : fg::wcet::case_list())
    std::printf("%-16s %-22s %s%s\n", c.name, c.targets, c.what, c.typical ? " [typical]" : "");
}

// The value after option argv[i] (i moves onto it); a missing value ends the program.
std::string option_value(int argc, char** argv, int& i) {
  if (i + 1 >= argc) {
    std::fprintf(stderr, "%s needs a value\n", argv[i]);
    std::exit(2);
  }
  return argv[++i];
}

// Every option in its order. Returns the exit code when the program ends here (--list,
// an unknown option), else nothing.
[[nodiscard]] std::optional<int> parse_options(int argc, char** argv, Options& o) {
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto next = [&]() { return option_value(argc, argv, i); };
    if (a == "--runs")
      o.runs = std::max(1, std::atoi(next().c_str()));
    else if (a == "--case")
      o.cases = split(next());
    else if (a == "--once")
      o.once = true;
    else if (a == "--ir")
      o.ir_prefix = next(), o.once = true;
    else if (a == "--profile")
      o.profile = true, o.once = true;
    else if (a == "--json")
      o.json_path = next();
    else if (a == "--markdown")
      o.md_path = next();
    else if (a == "--points")
      o.points = static_cast<uint32_t>(std::strtoul(next().c_str(), nullptr, 10));
    else if (a == "--hash-cells")
      o.hash_cells = static_cast<uint32_t>(std::strtoul(next().c_str(), nullptr, 10));
    else if (a == "--smoke")
      o.smoke = true;
    else if (a == "--no-warmup")
      o.warmup = false;
    else if (a == "--quiet")
      o.quiet = true;
    else if (a == "--list") {
      print_case_list();
      return 0;
    } else {
      return usage();
    }
  }
  return std::nullopt;
}

// The options' consequences: the default point count, the instruction clock (false when
// it cannot be used), --smoke's single run without warm-up.
[[nodiscard]] bool apply_options(Options& o) {
  if (o.points == 0) o.points = fg::wcet::default_points_per_sensor();
  if (!o.ir_prefix.empty()) {
    std::string err;
    if (!fg::wcet::use_instruction_clock(o.ir_prefix, err)) {
      std::fprintf(stderr, "fg_wcet: %s\n", err.c_str());
      return false;
    }
  }
  if (o.profile && !fg::wcet::under_valgrind())
    std::fprintf(stderr, "fg_wcet: --profile outside valgrind only runs once\n");
  if (o.smoke) {
    o.runs = 1;
    o.warmup = false;
  }
  return true;
}

// The cases to run, in case_list's order: those named by --case, else all (--smoke: the
// cheap ones). False on an unknown name, or when --once does not get exactly one case.
[[nodiscard]] bool select_cases(const Options& o, std::vector<const CaseInfo*>& todo) {
  for (const CaseInfo& c : fg::wcet::case_list()) {
    const bool wanted =
        o.cases.empty() ? (!o.smoke || c.smoke) : std::find(o.cases.begin(), o.cases.end(), c.name) != o.cases.end();
    if (wanted) todo.push_back(&c);
  }
  for (const std::string& n : o.cases) {
    bool known = false;
    for (const CaseInfo& c : fg::wcet::case_list()) known = known || n == c.name;
    if (!known) {
      std::fprintf(stderr, "fg_wcet: unknown case %s (--list)\n", n.c_str());
      return false;
    }
  }
  if (o.once && todo.size() != 1) {
    std::fprintf(stderr, "fg_wcet: --once needs exactly one --case\n");
    return false;
  }
  return true;
}

void print_header(const Options& o) {
  const bool ir = !o.ir_prefix.empty();
  std::printf("fg_wcet: limits %s, sizeof(fg::Planner) = %zu bytes, %u points per sensor, %s\n", FG_WCET_LIMITS,
              sizeof(fg::Planner), o.points,
              ir ? "instructions (callgrind)" : (o.once ? "one run (us)" : "microseconds, median / max"));
}

// The case's input; false (recorded in rep.build_error) when it cannot be built.
[[nodiscard]] bool build_case(const Options& o, CaseReport& rep) {
  std::string err;
  if (fg::wcet::make_case(rep.info->name, o.points, rep.input, err, o.hash_cells)) return true;
  rep.input.name = rep.info->name;
  rep.build_error = err;
  if (!o.quiet) std::fprintf(stderr, "fg_wcet: %s: %s\n", rep.info->name, err.c_str());
  return false;
}

// The arm starts from one fixed capture pose over the table (the synthetic cases put the
// object about the default workspace centre, 0.5 m in front of the base).
constexpr double kCaptureJoints[6] = {0.0, -1.9, 1.9, -1.57, -1.57, 0.0};

// The planner with the case's configuration (false, recorded in rep.build_error, when it
// is refused) and the robot's check as the grasp task installs it
// (firmware_api/src/grasp_task.cpp): inverse kinematics from the arm's joints at the
// capture, the joint path with its per-plan budget, and (where the firmware image has
// libccd: the host configuration) the whole tool against the plane and the target.
[[nodiscard]] bool configure_case(fg::Planner& planner, fg::robot::Ur5GraspCheck& check, CaseReport& rep) {
  const char* field = nullptr;
  if (planner.configure(rep.input.cfg, &field) != fg::Status::ok) {
    rep.build_error = std::string("invalid configuration: ") + (field ? field : "?");
    return false;
  }
  fg::robot::GraspCheckConfig check_cfg;
  check_cfg.tool.gripper = rep.input.cfg.gripper;
  check_cfg.check_tool = std::strcmp(FG_WCET_LIMITS, "host") == 0;
  check.configure(check_cfg);
  check.set_current_joints(kCaptureJoints);
  planner.set_grasp_check(&check);
  return true;
}

// Timed mode: [a warm-up run,] the measured runs, then the diagnostics of the last run's
// state (views, voxel hash) and the stack used by one more run.
void measure_runs(fg::Planner& planner, const Options& o, CaseReport& rep) {
  if (o.warmup) (void)run_once(planner, rep, false, false);
  for (int r = 0; r < o.runs; ++r) rep.runs.push_back(run_once(planner, rep, false, false));
  analyse_views(planner, rep);
  hash_probes(planner, rep);
  if (rep.input.name != "hash_collide")  // O(n^2) probing: minutes at full size
    rep.stack_bytes = stack_high_water([&]() {
      planner.reset();
      for (const auto& s : rep.input.sensors) (void)add_sensor(planner, s);
      fg::PlanResult r;
      (void)planner.plan(r);
    });
}

// "  <case> <status>[ (add: <status>)]; <saturated>...; PROBLEM: <problem>..."
void print_case_line(const CaseReport& rep) {
  std::string add;
  if (rep.add_status != fg::Status::ok) {
    add = " (add: ";
    add += fg::to_string(rep.add_status);
    add += ")";
  }
  std::printf("  %-16s %s%s", rep.info->name, status_text(rep).c_str(), add.c_str());
  for (const std::string& s : rep.saturated) std::printf("; %s", s.c_str());
  for (const std::string& s : rep.problems) std::printf("; PROBLEM: %s", s.c_str());
  std::printf("\n");
  std::fflush(stdout);
}

// One case built, configured, measured, judged and (unless --quiet) reported on one line.
// False when the case fails: a refused configuration or an undefined outcome. A case that
// cannot be built (e.g. a typical case without its example files) is not fatal.
[[nodiscard]] bool run_case(fg::Planner& planner, fg::robot::Ur5GraspCheck& check, const Options& o, CaseReport& rep) {
  if (!build_case(o, rep)) return true;
  if (!configure_case(planner, check, rep)) return false;
  if (o.once)
    rep.runs.push_back(run_once(planner, rep, true, !o.ir_prefix.empty()));
  else
    measure_runs(planner, o, rep);
  judge(rep);
  if (!o.quiet) print_case_line(rep);
  return rep.problems.empty();
}

// The table on stdout (unless --quiet), and the --json and --markdown files.
void write_reports(const std::vector<CaseReport>& reps, const Options& o) {
  if (!o.quiet) std::printf("\n%s", table(reps, o, false).c_str());
  if (!o.json_path.empty()) {
    std::ofstream f(o.json_path);
    f << to_json(reps, o).dump(1) << "\n";
  }
  if (!o.md_path.empty()) {
    std::ofstream f(o.md_path);
    f << table(reps, o, true);
  }
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  if (const std::optional<int> exit_code = parse_options(argc, argv, o)) return *exit_code;
  if (!apply_options(o)) return 2;
  std::vector<const CaseInfo*> todo;
  if (!select_cases(o, todo)) return 2;
  if (!o.quiet) print_header(o);
  static fg::Planner planner;             // large: static storage
  static fg::robot::Ur5GraspCheck check;  // 68 KiB of scratch
  std::vector<CaseReport> reps;
  bool failed = false;
  for (const CaseInfo* info : todo) {
    CaseReport rep;
    rep.info = info;
    if (!run_case(planner, check, o, rep)) failed = true;
    reps.push_back(std::move(rep));
  }
  write_reports(reps, o);
  if (o.smoke) std::printf("fg_wcet smoke: %s\n", failed ? "FAILED" : "every case returned a defined status");
  return failed ? 1 : 0;
}
