// Google Benchmark cases for every stage of the planner and for the whole plan on a
// two-sensor scene (two 640x480 clouds by default: examples/two-sensor-box).
//   build/host-release/tests/bench/fg_bench [--scene PATH] [benchmark flags]
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "fg/core/cluster.hpp"
#include "fg/core/force_balance.hpp"
#include "fg/core/hull.hpp"
#include "fg/core/plane.hpp"
#include "fg/core/planner.hpp"
#include "io/lzf.hpp"
#if FG_HAVE_LIBLZF
#include <liblzf/lzf.h>
#endif
#include "io/pcd.hpp"
#include "io/pcd_stream.hpp"
#include "io/ply.hpp"
#include "io/scene.hpp"

namespace {

struct Loaded {
  std::vector<fg::host::PointCloud> clouds;
  std::vector<fg::Pose> poses;
  std::vector<fg::SensorRole> roles;
  std::vector<std::string> paths;
  fg::PlannerConfig cfg;
  uint32_t raw_points = 0;
};

std::string g_scene = FG_DEFAULT_BENCH_SCENE;
Loaded* g_data = nullptr;
std::unique_ptr<fg::Planner> g_planner;

bool load(const std::string& path, Loaded& out) {
  fg::host::Scene scene;
  if (auto r = fg::host::read_scene(path, scene); !r.ok) {
    std::fprintf(stderr, "%s\n", r.error.c_str());
    return false;
  }
  out.cfg.gripper.max_opening_m = static_cast<float>(scene.gripper.max_opening);
  out.cfg.gripper.finger_width_m = static_cast<float>(scene.gripper.finger_width);
  out.cfg.gripper.finger_depth_m = static_cast<float>(scene.gripper.finger_depth);
  for (const auto& s : scene.sensors) {
    if (!s.pose) {
      std::fprintf(stderr, "bench scenes need sensor poses\n");
      return false;
    }
    fg::host::PointCloud c;
    if (auto r = fg::host::read_cloud(s.cloud_path, c); !r.ok) {
      std::fprintf(stderr, "%s\n", r.error.c_str());
      return false;
    }
    const fg::Pose p = fg::host::to_pose(*s.pose);
    out.raw_points += static_cast<uint32_t>(c.size());
    out.clouds.push_back(std::move(c));
    out.poses.push_back(p);
    out.roles.push_back(s.name == "head" ? fg::SensorRole::head : fg::SensorRole::hand);
    out.paths.push_back(s.cloud_path);
  }
  return true;
}

void ingest(fg::Planner& p) {
  p.reset();
  for (size_t i = 0; i < g_data->clouds.size(); ++i) {
    const auto& c = g_data->clouds[i];
    (void)p.add_points(g_data->roles[i], c.xyz.data(), static_cast<uint32_t>(c.size()), 12, g_data->poses[i]);
  }
}

// A finished plan whose intermediate data the stage benchmarks start from.
fg::Planner& planned() {
  static bool done = false;
  if (!done) {
    ingest(*g_planner);
    fg::PlanResult r;
    (void)g_planner->plan(r);
    done = true;
  }
  return *g_planner;
}

void BM_Ingest(benchmark::State& st) {
  for (auto _ : st) ingest(*g_planner);
  st.counters["raw_points"] = g_data->raw_points;
}

// The same clouds as x, y and z arrays, as `forcegrasp plan` hands over the blocks of
// binary_compressed PCD files: converted once, on first use.
const std::vector<std::vector<float>>& planar_clouds() {
  static std::vector<std::vector<float>> planar;
  if (planar.empty()) {
    for (const auto& c : g_data->clouds) {
      const size_t n = c.size();
      std::vector<float> a(3 * n);
      for (size_t k = 0; k < n; ++k)
        for (size_t j = 0; j < 3; ++j) a[j * n + k] = c.xyz[3 * k + j];
      planar.push_back(std::move(a));
    }
  }
  return planar;
}

void ingest_planar(fg::Planner& p) {
  const auto& planar = planar_clouds();
  p.reset();
  for (size_t i = 0; i < planar.size(); ++i) {
    const uint32_t n = static_cast<uint32_t>(planar[i].size() / 3);
    const float* a = planar[i].data();
    (void)p.add_points_planar(g_data->roles[i], a, a + n, a + 2 * n, n, g_data->poses[i]);
  }
}

void BM_IngestPlanar(benchmark::State& st) {
  (void)planar_clouds();  // the conversion stays out of the timed loop
  for (auto _ : st) ingest_planar(*g_planner);
  st.counters["raw_points"] = g_data->raw_points;
  st.counters["lanes"] = g_planner->ingest_lanes();
}

// The same in the four lanes of every target (BM_IngestPlanar takes the widest the CPU
// runs: eight with AVX2).
void BM_IngestPlanar4(benchmark::State& st) {
  g_planner->set_ingest_lanes(4);
  BM_IngestPlanar(st);
  g_planner->set_ingest_lanes(0);
}

// The same scene as the depth images a firmware's sensors deliver (uint16 mm, pinhole
// intrinsics): each organized cloud's z in millimetres, its intrinsics fitted to its
// pixels by least squares (u = cx + fx x / z, v = cy + fy y / z). Made once, on first use.
struct DepthImage {
  std::vector<uint16_t> mm;
  uint16_t width = 0, height = 0;
  fg::PinholeIntrinsics k;
};

const std::vector<DepthImage>& depth_images() {
  static std::vector<DepthImage> images;
  if (!images.empty()) return images;
  for (const auto& c : g_data->clouds) {
    DepthImage img;
    if (!c.organized() || c.planar() || c.width > 65535u || c.height > 65535u) {
      images.clear();
      return images;
    }
    img.width = static_cast<uint16_t>(c.width);
    img.height = static_cast<uint16_t>(c.height);
    img.mm.assign(static_cast<size_t>(c.width) * c.height, 0);
    double fit[2][5] = {};  // per axis: n, sum a, sum a^2, sum p, sum a p (a = x/z or y/z, p = pixel)
    for (uint32_t v = 0; v < c.height; ++v)
      for (uint32_t u = 0; u < c.width; ++u) {
        const size_t i = static_cast<size_t>(v) * c.width + u;
        const float x = c.xyz[3 * i], y = c.xyz[3 * i + 1], z = c.xyz[3 * i + 2];
        if (!(std::isfinite(x) && std::isfinite(y) && z > 0.f && z < 65.f)) continue;
        img.mm[i] = static_cast<uint16_t>(std::lround(z * 1000.f));
        const double a[2] = {x / z, y / z}, px[2] = {static_cast<double>(u), static_cast<double>(v)};
        for (int j = 0; j < 2; ++j) {
          fit[j][0] += 1;
          fit[j][1] += a[j];
          fit[j][2] += a[j] * a[j];
          fit[j][3] += px[j];
          fit[j][4] += a[j] * px[j];
        }
      }
    double f[2], ctr[2];
    for (int j = 0; j < 2; ++j) {
      const double n = fit[j][0];
      f[j] = (n * fit[j][4] - fit[j][1] * fit[j][3]) / (n * fit[j][2] - fit[j][1] * fit[j][1]);
      ctr[j] = (fit[j][3] - f[j] * fit[j][1]) / n;
    }
    img.k.fx = static_cast<float>(f[0]);
    img.k.fy = static_cast<float>(f[1]);
    img.k.cx = static_cast<float>(ctr[0]);
    img.k.cy = static_cast<float>(ctr[1]);
    images.push_back(std::move(img));
  }
  return images;
}

void BM_IngestDepth(benchmark::State& st) {
  const auto& images = depth_images();
  if (images.size() != g_data->clouds.size()) {
    st.SkipWithError("the scene's clouds are not organized (no depth images)");
    return;
  }
  for (auto _ : st) {
    g_planner->reset();
    for (size_t i = 0; i < images.size(); ++i)
      (void)g_planner->add_depth_image(g_data->roles[i], images[i].mm.data(), images[i].width, images[i].height,
                                       images[i].k, g_data->poses[i]);
  }
  st.counters["raw_points"] = g_data->raw_points;
  st.counters["voxels"] = g_planner->voxels().size();
}

// Ingest both clouds with `ingest_clouds`, then plan; each stage's time as a counter.
void whole_plan(benchmark::State& st, void (*ingest_clouds)(fg::Planner&)) {
  fg::PlanResult r;
  for (auto _ : st) {
    ingest_clouds(*g_planner);
    benchmark::DoNotOptimize(g_planner->plan(r));
  }
  st.counters["object_points"] = r.points.object;
  st.counters["viewpoints"] = r.viewpoints;
  for (int s = 0; s < static_cast<int>(fg::Stage::count); ++s)
    st.counters[std::string("us_") + fg::to_string(static_cast<fg::Stage>(s))] = r.stage_us[s];
  st.counters["us_registration"] = r.registration.us;
}

void BM_WholePlan(benchmark::State& st) { whole_plan(st, ingest); }

// The same with the hand fused as calibrated: the registration's cost (A.4b: the hand's
// first pass and the alignment) is BM_WholePlan's time minus this one's.
void BM_WholePlanNoRegistration(benchmark::State& st) {
  g_planner->set_registration(fg::RegistrationMode::off);
  whole_plan(st, ingest);
  g_planner->set_registration(fg::RegistrationMode::on);
}

// The whole plan as `forcegrasp plan` runs it: each binary_compressed cloud decodes to
// x, y and z arrays (the format stores the fields one after the other), handed over as
// they are (add_points_planar); BM_WholePlan takes interleaved xyz triples.
void BM_WholePlanPlanar(benchmark::State& st) {
  (void)planar_clouds();  // the conversion stays out of the timed loop
  whole_plan(st, ingest_planar);
}

void BM_RansacPlane(benchmark::State& st) {
  fg::Planner& p = planned();
  std::vector<fg::Vec3> pts(p.voxels().size());
  for (uint32_t i = 0; i < pts.size(); ++i) pts[i] = p.voxels().centroid(i);
  fg::PlaneParams pp;
  for (auto _ : st) {
    fg::Plane pl;
    uint32_t inl = 0;
    benchmark::DoNotOptimize(fg::ransac_plane(pts.data(), static_cast<uint32_t>(pts.size()), pp, pl, inl));
  }
  st.counters["points"] = static_cast<double>(pts.size());
}

void BM_Cluster(benchmark::State& st) {
  fg::Planner& p = planned();
  const uint32_t n = p.voxels().size();
  std::vector<uint8_t> base(n), state(n);
  for (uint32_t i = 0; i < n; ++i) base[i] = p.voxel_state(i) == fg::kVoxelRemoved ? fg::kVoxelRemoved : fg::kVoxelFree;
  std::vector<uint32_t> queue(n), target(fg::kMaxObjectPoints);
  // The cells' bitmap as plan() builds it (in its per-view memory, 344 KiB on the host:
  // 256 KiB here holds the example's).
  std::vector<uint64_t> words(1u << 15);
  fg::ClusterParams cp;
  fg::ClusterResult result;
  bool dense = false;
  for (auto _ : st) {
    std::memcpy(state.data(), base.data(), n);
    fg::CellBitmap cells;
    dense = fg::build_cell_bitmap(p.voxels(), state.data(), fg::kVoxelFree, queue.data(), words.data(),
                                  static_cast<uint32_t>(words.size()), cells);
    fg::cluster_and_pick(p.voxels(), state.data(), queue.data(), cp, target.data(), fg::kMaxObjectPoints, result,
                         dense ? &cells : nullptr);
    benchmark::DoNotOptimize(result);
  }
  st.counters["bitmap"] = dense ? 1 : 0;  // 0: the cells span more than the bitmap holds
}

// The silhouette of the chosen (or first) viewpoint: the per-viewpoint XOY stages.
struct Silhouette {
  std::vector<fg::Vec2> pts;
};
Silhouette silhouette() {
  fg::Planner& p = planned();
  Silhouette s;
  auto d = std::make_unique<fg::ViewDetail>();
  const uint32_t v = p.chosen_view() >= 0 ? static_cast<uint32_t>(p.chosen_view()) : 0u;
  if (p.view_count() > 0 && p.analyze_view(v, *d) == fg::Status::ok) s.pts.assign(d->points, d->points + d->n_points);
  return s;
}

void BM_ConcaveHull(benchmark::State& st) {
  const Silhouette s = silhouette();
  auto scratch = std::make_unique<fg::ConcaveHullScratch>();
  std::vector<fg::Vec2> out(fg::kMaxContourVertices);
  fg::ConcaveHullParams hp;
  for (auto _ : st) {
    uint32_t n = 0;
    float cell = 0;
    bool inside = false;
    benchmark::DoNotOptimize(fg::concave_hull_2d(s.pts.data(), static_cast<uint32_t>(s.pts.size()), hp, *scratch,
                                                 out.data(), fg::kMaxContourVertices, n, cell, inside));
  }
  st.counters["points"] = static_cast<double>(s.pts.size());
}

void BM_ConvexHull(benchmark::State& st) {
  const Silhouette s = silhouette();
  std::vector<fg::Vec2> scratch(s.pts.size()), out(s.pts.size() + 1);
  for (auto _ : st) {
    uint32_t n = 0;
    benchmark::DoNotOptimize(fg::convex_hull_2d(s.pts.data(), static_cast<uint32_t>(s.pts.size()), scratch.data(),
                                                out.data(), static_cast<uint32_t>(out.size()), n));
  }
}

void BM_ScanLinesAndWindows(benchmark::State& st) {
  fg::Planner& p = planned();
  auto d = std::make_unique<fg::ViewDetail>();
  const uint32_t v = p.chosen_view() >= 0 ? static_cast<uint32_t>(p.chosen_view()) : 0u;
  if (p.view_count() == 0 || p.analyze_view(v, *d) != fg::Status::ok) {
    st.SkipWithError("no viewpoint");
    return;
  }
  float ymin = d->contour[0].y, ymax = ymin;
  for (uint32_t i = 0; i < d->n_contour; ++i) {
    ymin = std::min(ymin, d->contour[i].y);
    ymax = std::max(ymax, d->contour[i].y);
  }
  std::vector<fg::ScanLine> lines(fg::kMaxScanLines);
  fg::SideFit best[3];
  for (auto _ : st) {
    float delta = 0;
    const uint32_t n =
        fg::build_scan_lines(d->contour, d->n_contour, ymin, ymax, 0.002f, lines.data(), fg::kMaxScanLines, delta);
    fg::mark_graspable(lines.data(), n, 0.f, 0.081f);
    benchmark::DoNotOptimize(fg::best_windows(lines.data(), n, 0.004f, 11, 0.f, 0.5f, best, 3));
  }
}

// What `forcegrasp plan` does before the planner sees a point: every cloud of the scene
// read from the file (the page cache, after the first round), parsed and, for
// binary_compressed, LZF-decoded into x, y and z arrays. One thread; the program reads
// the clouds on threads of their own.
void BM_ReadClouds(benchmark::State& st) {
  fg::host::ReadLimits limits;
  limits.planar = true;
  for (auto _ : st) {
    for (const std::string& path : g_data->paths) {
      fg::host::PointCloud c;
      const fg::host::ReadResult r = fg::host::read_cloud(path, c, limits);
      if (!r.ok) st.SkipWithError(r.error.c_str());
      benchmark::DoNotOptimize(c.size());
    }
  }
}

// The scene's clouds written once in each PCD encoding (a temporary folder, removed at
// exit): the reading cases below time each kind on the same points.
const std::vector<std::string>& clouds_as(fg::host::PcdEncoding e) {
  static std::vector<std::string> paths[3];
  static struct Folder {
    std::filesystem::path dir =
        std::filesystem::temp_directory_path() / ("fg_bench_clouds_" + std::to_string(::getpid()));
    ~Folder() {
      std::error_code ec;
      std::filesystem::remove_all(dir, ec);
    }
  } folder;
  std::vector<std::string>& out = paths[static_cast<int>(e)];
  if (!out.empty()) return out;
  std::filesystem::create_directories(folder.dir);
  for (size_t i = 0; i < g_data->clouds.size(); ++i) {
    fg::host::PointCloud c = g_data->clouds[i];
    if (c.planar()) continue;  // read_cloud above fills xyz (no planar limit)
    out.push_back((folder.dir / (std::to_string(static_cast<int>(e)) + "_" + std::to_string(i) + ".pcd")).string());
    if (!fg::host::write_pcd(out.back(), c, e).ok) std::fprintf(stderr, "cannot write %s\n", out.back().c_str());
  }
  return out;
}

// Every cloud of the scene read whole by read_cloud (as the program reads any file it
// does not stream), in one PCD encoding.
void read_whole(benchmark::State& st, fg::host::PcdEncoding e) {
  const std::vector<std::string>& paths = clouds_as(e);
  fg::host::ReadLimits limits;
  limits.planar = true;
  for (auto _ : st) {
    for (const std::string& path : paths) {
      fg::host::PointCloud c;
      const fg::host::ReadResult r = fg::host::read_cloud(path, c, limits);
      if (!r.ok) st.SkipWithError(r.error.c_str());
      benchmark::DoNotOptimize(c.size());
    }
  }
}
void BM_ReadAscii(benchmark::State& st) { read_whole(st, fg::host::PcdEncoding::ascii); }
void BM_ReadBinaryWhole(benchmark::State& st) { read_whole(st, fg::host::PcdEncoding::binary); }
void BM_ReadBinaryCompressed(benchmark::State& st) { read_whole(st, fg::host::PcdEncoding::binary_compressed); }

// The DATA binary clouds read in chunks by PcdStream, every piece touched, no ingest:
// what streaming adds to the ingest.
void BM_StreamBinary(benchmark::State& st) {
  const std::vector<std::string>& paths = clouds_as(fg::host::PcdEncoding::binary);
  for (auto _ : st) {
    for (const std::string& path : paths) {
      fg::host::PcdStream s;
      if (!s.open(path)) st.SkipWithError("cannot stream");
      fg::PointPiece piece;
      float sum = 0.f;
      while (s.next(piece) && piece.count > 0) {
        float z;
        std::memcpy(&z, piece.z + static_cast<size_t>(piece.count - 1) * piece.stride, 4);
        sum += z;
      }
      benchmark::DoNotOptimize(sum);
    }
  }
}

// The DATA binary clouds streamed into the planner, as `forcegrasp plan` ingests them:
// BM_IngestPlanar plus the reading.
void BM_StreamBinaryIngest(benchmark::State& st) {
  const std::vector<std::string>& paths = clouds_as(fg::host::PcdEncoding::binary);
  for (auto _ : st) {
    g_planner->reset();
    for (size_t i = 0; i < paths.size(); ++i) {
      fg::host::PcdStream s;
      if (!s.open(paths[i]) || g_planner->add_point_source(g_data->roles[i], s, g_data->poses[i]) != fg::Status::ok)
        st.SkipWithError("cannot stream");
    }
  }
}

// The LZF streams of every binary_compressed cloud of the scene.
struct LzfStream {
  std::vector<uint8_t> in;
  uint32_t out_size;
};
std::vector<LzfStream> lzf_streams() {
  std::vector<LzfStream> streams;
  for (const std::string& path : g_data->paths) {
    std::FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) continue;
    std::vector<uint8_t> bytes;
    uint8_t buf[65536];
    for (size_t got; (got = std::fread(buf, 1, sizeof buf, f)) > 0;) bytes.insert(bytes.end(), buf, buf + got);
    std::fclose(f);
    static const char kTag[] = "DATA binary_compressed\n";
    const auto at = std::search(bytes.begin(), bytes.end(), kTag, kTag + sizeof kTag - 1);
    if (at == bytes.end()) continue;
    const size_t head = static_cast<size_t>(at - bytes.begin()) + sizeof kTag - 1;
    if (bytes.size() < head + 8) continue;
    uint32_t packed = 0, unpacked = 0;
    std::memcpy(&packed, &bytes[head], 4);
    std::memcpy(&unpacked, &bytes[head + 4], 4);
    if (bytes.size() < head + 8 + packed) continue;
    streams.push_back(LzfStream{std::vector<uint8_t>(bytes.begin() + static_cast<long>(head) + 8,
                                                     bytes.begin() + static_cast<long>(head + 8 + packed)),
                                unpacked});
  }
  return streams;
}

// Every binary_compressed stream of the scene decoded by `decode` in each iteration.
using LzfDecoder = bool (*)(const LzfStream& s, uint8_t* out, std::string& err);
void lzf_decode(benchmark::State& st, LzfDecoder decode) {
  const std::vector<LzfStream> streams = lzf_streams();
  if (streams.empty()) {
    st.SkipWithError("no binary_compressed cloud in the scene");
    return;
  }
  std::vector<uint8_t> out;
  uint64_t bytes_out = 0;
  for (const LzfStream& s : streams) bytes_out += s.out_size;
  std::string err;
  for (auto _ : st) {
    for (const LzfStream& s : streams) {
      out.resize(s.out_size);
      if (!decode(s, out.data(), err)) st.SkipWithError(err.c_str());
      benchmark::DoNotOptimize(out.data());
    }
  }
  st.SetBytesProcessed(static_cast<int64_t>(st.iterations() * bytes_out));
}

// The project's LZF decoder alone (platform/host/io/lzf.cpp).
void BM_LzfDecode(benchmark::State& st) {
  lzf_decode(st, [](const LzfStream& s, uint8_t* out, std::string& err) {
    return fg::host::lzf::decompress(s.in.data(), s.in.size(), out, s.out_size, err);
  });
}

#if FG_HAVE_LIBLZF
// The same streams through liblzf (Debian's liblzf-dev, the code PCL's LZF decoder was
// copied from): the reference speed of the format's decoder.
void BM_LzfDecodeLiblzf(benchmark::State& st) {
  lzf_decode(st, [](const LzfStream& s, uint8_t* out, std::string& err) {
    if (lzf_decompress(s.in.data(), static_cast<unsigned>(s.in.size()), out, s.out_size) == s.out_size) return true;
    err = "liblzf refused the stream";
    return false;
  });
}
BENCHMARK(BM_LzfDecodeLiblzf)->Unit(benchmark::kMicrosecond);
#endif

void BM_AnalyzeViewpoint(benchmark::State& st) {
  fg::Planner& p = planned();
  auto d = std::make_unique<fg::ViewDetail>();
  for (auto _ : st) benchmark::DoNotOptimize(p.analyze_view(0, *d));
}

}  // namespace

BENCHMARK(BM_Ingest)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WholePlanNoRegistration)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IngestPlanar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IngestPlanar4)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_IngestDepth)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_RansacPlane)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Cluster)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ConcaveHull)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ConvexHull)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ScanLinesAndWindows)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AnalyzeViewpoint)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WholePlan)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_WholePlanPlanar)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadClouds)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadAscii)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadBinaryWhole)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_ReadBinaryCompressed)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StreamBinary)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_StreamBinaryIngest)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LzfDecode)->Unit(benchmark::kMicrosecond);

int main(int argc, char** argv) {
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--scene") == 0 && i + 1 < argc) {
      g_scene = argv[i + 1];
      for (int j = i; j + 2 <= argc; ++j) argv[j] = argv[j + 2];
      argc -= 2;
      break;
    }
  }
  static Loaded data;
  if (!load(g_scene, data)) return 2;
  std::printf("scene %s: %u raw points; planner workspace sizeof(fg::Planner) = %zu bytes\n", g_scene.c_str(),
              data.raw_points, sizeof(fg::Planner));
  g_data = &data;
  g_planner = std::make_unique<fg::Planner>();
  if (g_planner->configure(data.cfg) != fg::Status::ok) return 2;
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
