// The SVG pictures of `forcegrasp plan --pictures`: a small synthetic scene (a box on a
// table) is planned, the pictures are written into a temporary folder and checked for
// well-formed XML and the expected elements; unwritable folders give false and a message.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cctype>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

// The picture code lives in the forcegrasp executable's folder: compile it here.
#include "../../platform/host/cli/svg_pictures.cpp"

namespace {

namespace fs = std::filesystem;
using fg::Planner;
using fg::PlannerConfig;
using fg::PlanResult;
using fg::Status;

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream os;
  os << in.rdbuf();
  return os.str();
}

size_t count_of(const std::string& s, const std::string& what) {
  size_t n = 0;
  for (size_t pos = s.find(what); pos != std::string::npos; pos = s.find(what, pos + 1)) ++n;
  return n;
}

// A small XML well-formedness check: balanced and properly nested tags, quoted
// attributes, known entities, one root element named `root`.
::testing::AssertionResult well_formed(const std::string& x, const std::string& root) {
  std::vector<std::string> stack;
  size_t i = 0, roots = 0;
  while (i < x.size()) {
    if (x[i] == '&') {
      const size_t semi = x.find(';', i);
      if (semi == std::string::npos) return ::testing::AssertionFailure() << "unterminated entity at " << i;
      const std::string ent = x.substr(i, semi - i + 1);
      if (ent != "&amp;" && ent != "&lt;" && ent != "&gt;" && ent != "&quot;" && ent != "&apos;")
        return ::testing::AssertionFailure() << "unknown entity " << ent;
      i = semi + 1;
      continue;
    }
    if (x[i] != '<') {
      if (x[i] == '>') return ::testing::AssertionFailure() << "stray '>' at " << i;
      ++i;
      continue;
    }
    if (x.compare(i, 2, "<?") == 0) {
      const size_t e = x.find("?>", i);
      if (e == std::string::npos) return ::testing::AssertionFailure() << "unterminated <? at " << i;
      i = e + 2;
      continue;
    }
    if (x.compare(i, 4, "<!--") == 0) {
      const size_t e = x.find("-->", i);
      if (e == std::string::npos) return ::testing::AssertionFailure() << "unterminated comment at " << i;
      i = e + 3;
      continue;
    }
    const bool closing = x.compare(i, 2, "</") == 0;
    size_t j = i + (closing ? 2 : 1);
    const size_t name_start = j;
    while (j < x.size() &&
           (std::isalnum(static_cast<unsigned char>(x[j])) || x[j] == '-' || x[j] == ':' || x[j] == '_'))
      ++j;
    const std::string name = x.substr(name_start, j - name_start);
    if (name.empty()) return ::testing::AssertionFailure() << "tag without a name at " << i;
    // Attributes up to '>' (quotes respected).
    char quote = 0;
    while (j < x.size() && (quote != 0 || x[j] != '>')) {
      if (quote == 0 && (x[j] == '"' || x[j] == '\''))
        quote = x[j];
      else if (quote != 0 && x[j] == quote)
        quote = 0;
      else if (quote == 0 && x[j] == '<')
        return ::testing::AssertionFailure() << "'<' inside tag " << name;
      ++j;
    }
    if (j >= x.size()) return ::testing::AssertionFailure() << "unterminated tag " << name;
    const bool self_closing = x[j - 1] == '/';
    if (closing) {
      if (stack.empty() || stack.back() != name)
        return ::testing::AssertionFailure() << "</" << name << "> does not close <"
                                             << (stack.empty() ? std::string("(nothing)") : stack.back()) << ">";
      stack.pop_back();
    } else {
      if (stack.empty()) {
        ++roots;
        if (name != root) return ::testing::AssertionFailure() << "root element is <" << name << ">";
      }
      if (!self_closing) stack.push_back(name);
    }
    i = j + 1;
  }
  if (!stack.empty()) return ::testing::AssertionFailure() << "<" << stack.back() << "> is never closed";
  if (roots != 1) return ::testing::AssertionFailure() << roots << " root elements";
  return ::testing::AssertionSuccess();
}

// A 0.05 x 0.08 x 0.12 m box standing at (0.5, 0) on a 0.6 x 0.6 m table at z = 0,
// sampled on a 4 mm grid: the table around the box, the top and the faces towards
// the sensor side (-x) and both y sides.
std::vector<float> box_on_table() {
  std::vector<float> xyz;
  auto add = [&](double x, double y, double z) {
    xyz.push_back(static_cast<float>(x));
    xyz.push_back(static_cast<float>(y));
    xyz.push_back(static_cast<float>(z));
  };
  const double s = 0.004;
  const double bx0 = 0.475, bx1 = 0.525, by0 = -0.04, by1 = 0.04, bz1 = 0.12;
  for (double x = 0.2; x <= 0.8 + 1e-9; x += s)
    for (double y = -0.3; y <= 0.3 + 1e-9; y += s)
      if (x < bx0 || x > bx1 || y < by0 || y > by1) add(x, y, 0.0);
  for (double x = bx0; x <= bx1 + 1e-9; x += s)
    for (double y = by0; y <= by1 + 1e-9; y += s) add(x, y, bz1);
  for (double z = s; z <= bz1 + 1e-9; z += s) {
    for (double y = by0; y <= by1 + 1e-9; y += s) add(bx0, y, z);
    for (double x = bx0; x <= bx1 + 1e-9; x += s) {
      add(x, by0, z);
      add(x, by1, z);
    }
  }
  return xyz;
}

class SvgPictures : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("fg_svg_test_" + std::to_string(::getpid()) + "_" +
                                        ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    planner_ = std::make_unique<Planner>();
    PlannerConfig cfg;
    cfg.range_min_m = 0.0f;  // the points are given in world (identity pose): no range cut
    cfg.range_max_m = 5.0f;
    cfg.gripper.max_opening_m = 0.14f;
    ASSERT_EQ(planner_->configure(cfg), Status::ok);
  }
  void TearDown() override {
    // FG_KEEP_PICTURES=1 keeps the folder for a look at the pictures.
    if (const char* keep = std::getenv("FG_KEEP_PICTURES"); keep != nullptr && keep[0] == '1') {
      std::printf("pictures kept in %s\n", dir_.string().c_str());
      return;
    }
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  void plan_box() {
    const std::vector<float> pts = box_on_table();
    ASSERT_EQ(planner_->add_points(fg::SensorRole::head, pts.data(), static_cast<uint32_t>(pts.size() / 3),
                                   3 * sizeof(float), fg::Pose{}),
              Status::ok)
        << planner_->last_message();
    EXPECT_EQ(planner_->plan(result_), result_.status);
    ASSERT_TRUE(result_.status == Status::ok || result_.status == Status::no_grasp) << result_.message;
  }

  fs::path dir_;
  std::unique_ptr<Planner> planner_;
  PlanResult result_;
};

const char* const kPictures[] = {"object_top.svg", "object_side.svg", "silhouette.svg", "balance.svg"};

TEST_F(SvgPictures, WritesFourWellFormedPicturesAndAnIndex) {
  plan_box();
  ASSERT_GT(planner_->object_points().size(), 30u);
  ASSERT_TRUE(planner_->plane_found());
  ASSERT_GT(planner_->view_count(), 0u);

  std::string error;
  ASSERT_TRUE(fg::host::write_pictures(*planner_, result_, dir_.string(), error)) << error;
  for (const char* name : kPictures) {
    const fs::path p = dir_ / name;
    ASSERT_TRUE(fs::is_regular_file(p)) << p;
    const std::string svg = read_text(p);
    ASSERT_FALSE(svg.empty()) << p;
    EXPECT_TRUE(svg.rfind("<?xml", 0) == 0 || svg.rfind("<svg", 0) == 0) << p;
    EXPECT_TRUE(well_formed(svg, "svg")) << p;
    EXPECT_EQ(count_of(svg, "<svg"), 1u) << p;
    EXPECT_EQ(count_of(svg, "</svg>"), 1u) << p;
    EXPECT_NE(svg.find("viewBox=\""), std::string::npos) << p;
    EXPECT_NE(svg.find("<title>"), std::string::npos) << p;
    EXPECT_NE(svg.find("Legend"), std::string::npos) << p;
    EXPECT_NE(svg.find("(mm)"), std::string::npos) << p << ": axis labels with units";
    EXPECT_EQ(svg.find("nan"), std::string::npos) << p << ": a non-finite coordinate";
    EXPECT_EQ(svg.find("inf\""), std::string::npos) << p << ": a non-finite coordinate";
  }
  const std::string index = read_text(dir_ / "index.html");
  for (const char* name : kPictures) EXPECT_NE(index.find(std::string("<img src=\"") + name), std::string::npos);
  EXPECT_TRUE(well_formed(index.substr(index.find("<html")), "html"));

  // Top and side: one circle per object point (plus markers); the scale bar.
  const std::string top = read_text(dir_ / "object_top.svg");
  EXPECT_GE(count_of(top, "<circle"), planner_->object_points().size());
  EXPECT_NE(top.find("Scale"), std::string::npos);
  const std::string side = read_text(dir_ / "object_side.svg");
  EXPECT_NE(side.find("support plane"), std::string::npos);
  if (result_.status == Status::ok) {
    // Palm, 2 open + 2 closed fingers, 2 open + 2 closed pads: outlines (a pad seen edge-on
    // is a polyline), and both arrows.
    for (const std::string* s : {&top, &side}) {
      EXPECT_GE(count_of(*s, "<polygon") + count_of(*s, "<polyline"), 9u);
      EXPECT_NE(s->find("palm"), std::string::npos);
      EXPECT_NE(s->find("closing direction"), std::string::npos);
    }
  }

  // Silhouette: the contour polygon and one line per scan line at least.
  auto detail = std::make_unique<fg::ViewDetail>();
  const int32_t vi = fg::host::picture_view(*planner_);
  ASSERT_GE(vi, 0);
  ASSERT_EQ(planner_->analyze_view(static_cast<uint32_t>(vi), *detail), Status::ok);
  const std::string sil = read_text(dir_ / "silhouette.svg");
  EXPECT_GE(count_of(sil, "<polygon"), 1u);
  EXPECT_GE(count_of(sil, "<line"), detail->n_lines);
  EXPECT_GT(detail->n_lines, 10u);
  if (detail->has_best) {
    EXPECT_NE(sil.find("beta = "), std::string::npos);
  }

  // Balance: one marker per plotted viewpoint, the beta_max line.
  const std::string bal = read_text(dir_ / "balance.svg");
  EXPECT_NE(bal.find("beta_max"), std::string::npos);
  EXPECT_NE(bal.find("dz (mm)"), std::string::npos);
  EXPECT_NE(bal.find("stroke-dasharray"), std::string::npos);
}

// The ranked alternates (--top) are drawn in both object pictures, each numbered in
// rank order with its closing line, and listed in the legend; without them nothing of
// theirs is drawn.
TEST_F(SvgPictures, RankedAlternatesAreDrawnNumberedInRankOrder) {
  plan_box();
  ASSERT_EQ(result_.status, Status::ok);
  std::vector<fg::Grasp> alternates(2, result_.grasp);
  alternates[1].position += fg::Vec3(0.f, 0.f, 0.02f);
  std::string error;
  ASSERT_TRUE(fg::host::write_pictures(*planner_, result_, dir_.string(), error, alternates)) << error;
  for (const char* name : {"object_top.svg", "object_side.svg"}) {
    const std::string svg = read_text(dir_ / name);
    EXPECT_TRUE(well_formed(svg, "svg")) << name;
    EXPECT_NE(svg.find("ranked alternates 1..2"), std::string::npos) << name;
    EXPECT_NE(svg.find(">1</text>"), std::string::npos) << name;
    EXPECT_NE(svg.find(">2</text>"), std::string::npos) << name;
  }
  ASSERT_TRUE(fg::host::write_pictures(*planner_, result_, dir_.string(), error)) << error;
  EXPECT_EQ(read_text(dir_ / "object_top.svg").find("ranked alternates"), std::string::npos);
}

TEST_F(SvgPictures, RewritesAnExistingFolder) {
  plan_box();
  std::string error;
  ASSERT_TRUE(fg::host::write_pictures(*planner_, result_, dir_.string(), error)) << error;
  ASSERT_TRUE(fg::host::write_pictures(*planner_, result_, dir_.string(), error)) << error;
  EXPECT_TRUE(well_formed(read_text(dir_ / "silhouette.svg"), "svg"));
}

TEST_F(SvgPictures, NestedFolderIsCreated) {
  plan_box();
  std::string error;
  const fs::path nested = dir_ / "a" / "b";
  ASSERT_TRUE(fg::host::write_pictures(*planner_, result_, nested.string(), error)) << error;
  EXPECT_TRUE(fs::is_regular_file(nested / "balance.svg"));
}

TEST_F(SvgPictures, UnwritableFolderGivesFalseAndAMessage) {
  plan_box();
  std::string error;
  EXPECT_FALSE(fg::host::write_pictures(*planner_, result_, "/proc/forbidden", error));
  EXPECT_NE(error.find("/proc/forbidden"), std::string::npos) << error;

  // A file where the folder should be.
  fs::create_directories(dir_);
  const fs::path file = dir_ / "not_a_folder";
  std::ofstream(file) << "x";
  error.clear();
  EXPECT_FALSE(fg::host::write_pictures(*planner_, result_, file.string(), error));
  EXPECT_NE(error.find(file.string()), std::string::npos) << error;

  error.clear();
  EXPECT_FALSE(fg::host::write_pictures(*planner_, result_, "", error));
  EXPECT_FALSE(error.empty());
}

TEST_F(SvgPictures, NothingPlannedStillGivesPictures) {
  // plan() without data: no object, no viewpoint; the pictures say so instead of failing.
  PlanResult r;
  EXPECT_EQ(planner_->plan(r), r.status);
  EXPECT_EQ(r.status, Status::no_input);
  std::string error;
  ASSERT_TRUE(fg::host::write_pictures(*planner_, r, dir_.string(), error)) << error;
  for (const char* name : kPictures) {
    const std::string svg = read_text(dir_ / name);
    EXPECT_TRUE(well_formed(svg, "svg")) << name;
  }
  EXPECT_NE(read_text(dir_ / "silhouette.svg").find("no viewpoint"), std::string::npos);
}

TEST(SvgPicturesText, EscapesAndNumbers) {
  EXPECT_EQ(fg::host::esc("a<b & \"c\">"), "a&lt;b &amp; &quot;c&quot;&gt;");
  EXPECT_EQ(fg::host::fmt(1.50, 2), "1.5");
  EXPECT_EQ(fg::host::fmt(-0.001, 2), "0");
  EXPECT_EQ(fg::host::fmt(std::nan(""), 2), "0");
  EXPECT_EQ(fg::host::nice_floor(37.0), 20.0);
  EXPECT_EQ(fg::host::nice_floor(0.6), 0.5);
}

}  // namespace
