// SVG pictures of the planner's stages (host only): the object cloud with the grasp
// and the gripper seen from above and from the side, the chosen viewpoint's
// silhouette with its scan lines and fitted sides, and the force-balance figures of
// every viewpoint. Plain SVG 1.1, one self-contained file each, plus an index.html.
#include "svg_pictures.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <system_error>
#include <utility>
#include <vector>

#include "fg/core/constants.hpp"

namespace fg::host {
namespace {

using V3 = Eigen::Vector3d;
// The side view looks along the closing direction when it is within 20 deg of horizontal.
constexpr double kNearHorizontal = 0.342;

// ---------------------------------------------------------------------------------
// Text and numbers

std::string fmt(double v, int decimals) {
  if (!std::isfinite(v)) return "0";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s(buf);
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}
std::string px(double v) { return fmt(v, 2); }

std::string esc(const std::string& s) {
  std::string o;
  o.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&':
        o += "&amp;";
        break;
      case '<':
        o += "&lt;";
        break;
      case '>':
        o += "&gt;";
        break;
      case '"':
        o += "&quot;";
        break;
      case '\'':
        o += "&apos;";
        break;
      default:
        o += c;
    }
  }
  return o;
}

//! An angle in rad with enough digits for the paper's range (1e-5 .. 0.4 rad).
std::string rad_text(double v) {
  if (v != 0 && std::fabs(v) < 1e-3) {
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2e", v);
    return buf;
  }
  return fmt(v, 4);
}

std::string vec_text(const V3& v, int decimals = 3) {
  return "(" + fmt(v.x(), decimals) + ", " + fmt(v.y(), decimals) + ", " + fmt(v.z(), decimals) + ")";
}

// Largest of 1, 2, 5 x 10^k not above v (v > 0).
double nice_floor(double v) {
  const double mag = std::pow(10.0, std::floor(std::log10(v)));
  const double n = v / mag;
  return (n >= 5 ? 5 : n >= 2 ? 2 : 1) * mag;
}
// A 1-2-5 tick step giving about `count` ticks over `range`.
double nice_step(double range, double count) {
  const double raw = range / count;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / mag;
  return (n < 1.5 ? 1 : n < 3 ? 2 : n < 7 ? 5 : 10) * mag;
}
int step_decimals(double step) {
  const int d = static_cast<int>(-std::floor(std::log10(step) + 1e-9));
  return d > 0 ? d : 0;
}

// ---------------------------------------------------------------------------------
// The SVG document

struct P2 {
  double x = 0, y = 0;
};

std::string attrs(const std::string& stroke, double width, const std::string& fill, const std::string& extra = "") {
  std::string s = "stroke=\"" + stroke + "\" stroke-width=\"" + fmt(width, 2) + "\" fill=\"" + fill + "\"";
  if (!extra.empty()) s += " " + extra;
  return s;
}

class Svg {
 public:
  Svg(double w, double h) : w_(w), h_(h) {}
  double width() const { return w_; }
  double height() const { return h_; }

  void raw(const std::string& s) { os_ << s << "\n"; }
  void def(const std::string& s) { defs_ << s << "\n"; }
  void line(P2 a, P2 b, const std::string& style) {
    os_ << "<line x1=\"" << px(a.x) << "\" y1=\"" << px(a.y) << "\" x2=\"" << px(b.x) << "\" y2=\"" << px(b.y) << "\" "
        << style << "/>\n";
  }
  void circle(P2 c, double r, const std::string& style) {
    os_ << "<circle cx=\"" << px(c.x) << "\" cy=\"" << px(c.y) << "\" r=\"" << px(r) << "\" " << style << "/>\n";
  }
  void rect(double x, double y, double w, double h, const std::string& style) {
    os_ << "<rect x=\"" << px(x) << "\" y=\"" << px(y) << "\" width=\"" << px(std::max(w, 0.0)) << "\" height=\""
        << px(std::max(h, 0.0)) << "\" " << style << "/>\n";
  }
  void poly(const char* tag, const std::vector<P2>& pts, const std::string& style) {
    if (pts.empty()) return;
    os_ << "<" << tag << " points=\"";
    for (size_t i = 0; i < pts.size(); ++i) os_ << (i ? " " : "") << px(pts[i].x) << "," << px(pts[i].y);
    os_ << "\" " << style << "/>\n";
  }
  void polygon(const std::vector<P2>& pts, const std::string& style) { poly("polygon", pts, style); }
  void polyline(const std::vector<P2>& pts, const std::string& style) { poly("polyline", pts, style); }
  //! Text at `at`; `extra` holds further attributes (anchor, size, colour, transform).
  void text(P2 at, const std::string& s, const std::string& extra = "") {
    os_ << "<text x=\"" << px(at.x) << "\" y=\"" << px(at.y) << "\"" << (extra.empty() ? "" : " ") << extra << ">"
        << esc(s) << "</text>\n";
  }
  void open(const std::string& tag_and_attrs) { os_ << "<" << tag_and_attrs << ">\n"; }
  void close(const char* tag) { os_ << "</" << tag << ">\n"; }

  //! Arrow from a to b with a filled head of `head` px.
  void arrow(P2 a, P2 b, const std::string& colour, double width, double head = 10) {
    const double dx = b.x - a.x, dy = b.y - a.y, len = std::hypot(dx, dy);
    if (len < 1e-6) return;
    const double ux = dx / len, uy = dy / len;
    const double h = std::min(head, 0.6 * len);
    const P2 base{b.x - ux * h, b.y - uy * h};
    line(a, base, attrs(colour, width, "none", "stroke-linecap=\"round\""));
    polygon({b, {base.x - uy * h * 0.45, base.y + ux * h * 0.45}, {base.x + uy * h * 0.45, base.y - ux * h * 0.45}},
            "stroke=\"none\" fill=\"" + colour + "\"");
  }

  std::string str(const std::string& title, const std::string& desc) const {
    std::ostringstream o;
    o << "<?xml version=\"1.0\" encoding=\"UTF-8\" standalone=\"no\"?>\n"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" version=\"1.1\" width=\"" << px(w_) << "\" height=\"" << px(h_)
      << "\" viewBox=\"0 0 " << px(w_) << " " << px(h_)
      << "\" font-family=\"DejaVu Sans, Arial, Helvetica, sans-serif\" font-size=\"13\">\n"
      << "<title>" << esc(title) << "</title>\n"
      << "<desc>" << esc(desc) << "</desc>\n";
    const std::string d = defs_.str();
    if (!d.empty()) o << "<defs>\n" << d << "</defs>\n";
    o << "<rect x=\"0\" y=\"0\" width=\"" << px(w_) << "\" height=\"" << px(h_) << "\" fill=\"#ffffff\"/>\n"
      << os_.str() << "</svg>\n";
    return o.str();
  }

 private:
  double w_, h_;
  std::ostringstream os_;
  std::ostringstream defs_;
};

// ---------------------------------------------------------------------------------
// Plots: a pixel rectangle showing a data rectangle (y up).

struct Bounds {
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  bool empty() const { return !(x1 >= x0 && y1 >= y0); }
  void add(double x, double y) {
    if (!std::isfinite(x) || !std::isfinite(y)) return;
    x0 = std::min(x0, x);
    x1 = std::max(x1, x);
    y0 = std::min(y0, y);
    y1 = std::max(y1, y);
  }
  void add(P2 p) { add(p.x, p.y); }
};

struct Plot {
  double left = 0, top = 0, w = 1, h = 1;  // pixels
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;   // data
  P2 map(double x, double y) const { return {left + (x - x0) / (x1 - x0) * w, top + h - (y - y0) / (y1 - y0) * h}; }
  P2 map(P2 p) const { return map(p.x, p.y); }
  double sx() const { return w / (x1 - x0); }  // pixels per data unit
  double sy() const { return h / (y1 - y0); }
};

//! Fits `b` (grown by `pad` of its size and to at least `min_span`) into the pixel
//! rectangle; equal_aspect keeps one scale for both axes (geometric pictures).
Plot make_plot(double left, double top, double w, double h, Bounds b, double pad, double min_span, bool equal_aspect) {
  if (b.empty()) b = Bounds{-min_span / 2, min_span / 2, -min_span / 2, min_span / 2};
  auto grow = [&](double& lo, double& hi) {
    double span = hi - lo;
    const double c = 0.5 * (lo + hi);
    span = std::max(span * (1 + 2 * pad), min_span);
    lo = c - span / 2;
    hi = c + span / 2;
  };
  grow(b.x0, b.x1);
  grow(b.y0, b.y1);
  Plot p;
  p.left = left;
  p.top = top;
  p.w = w;
  p.h = h;
  p.x0 = b.x0;
  p.x1 = b.x1;
  p.y0 = b.y0;
  p.y1 = b.y1;
  if (equal_aspect) {
    const double s = std::min(w / (b.x1 - b.x0), h / (b.y1 - b.y0));
    const double cx = 0.5 * (b.x0 + b.x1), cy = 0.5 * (b.y0 + b.y1);
    p.x0 = cx - 0.5 * w / s;
    p.x1 = cx + 0.5 * w / s;
    p.y0 = cy - 0.5 * h / s;
    p.y1 = cy + 0.5 * h / s;
  }
  return p;
}

//! Grid, ticks, tick labels, frame and axis labels; defines clip path `clip_id`.
void draw_axes(Svg& svg, const Plot& p, const std::string& xlabel, const std::string& ylabel,
               const std::string& clip_id) {
  svg.def("<clipPath id=\"" + clip_id + "\"><rect x=\"" + px(p.left) + "\" y=\"" + px(p.top) + "\" width=\"" + px(p.w) +
          "\" height=\"" + px(p.h) + "\"/></clipPath>");
  const double xs = nice_step(p.x1 - p.x0, std::max(3.0, p.w / 90));
  const double ys = nice_step(p.y1 - p.y0, std::max(3.0, p.h / 70));
  const int xd = step_decimals(xs), yd = step_decimals(ys);
  const std::string grid = attrs("#e3e3e3", 1, "none");
  const std::string tick = attrs("#333333", 1, "none");
  for (double x = std::ceil(p.x0 / xs) * xs; x <= p.x1 + 1e-9 * xs; x += xs) {
    const P2 a = p.map(x, p.y0), b = p.map(x, p.y1);
    svg.line(a, b, grid);
    svg.line(a, {a.x, a.y + 5}, tick);
    svg.text({a.x, a.y + 19}, fmt(std::fabs(x) < 1e-9 * xs ? 0.0 : x, xd), "text-anchor=\"middle\" font-size=\"12\"");
  }
  for (double y = std::ceil(p.y0 / ys) * ys; y <= p.y1 + 1e-9 * ys; y += ys) {
    const P2 a = p.map(p.x0, y), b = p.map(p.x1, y);
    svg.line(a, b, grid);
    svg.line(a, {a.x - 5, a.y}, tick);
    svg.text({a.x - 8, a.y + 4}, fmt(std::fabs(y) < 1e-9 * ys ? 0.0 : y, yd), "text-anchor=\"end\" font-size=\"12\"");
  }
  svg.rect(p.left, p.top, p.w, p.h, attrs("#333333", 1, "none"));
  svg.text({p.left + p.w / 2, p.top + p.h + 40}, xlabel, "text-anchor=\"middle\" font-size=\"14\"");
  const P2 yl{p.left - 58, p.top + p.h / 2};
  svg.text(yl, ylabel,
           "text-anchor=\"middle\" font-size=\"14\" transform=\"rotate(-90 " + px(yl.x) + " " + px(yl.y) + ")\"");
}

//! Title and up to three lines of subtitle (long lines are wrapped at spaces).
void draw_title(Svg& svg, const std::string& title, const std::vector<std::string>& sub) {
  svg.text({20, 30}, title, "font-size=\"19\" font-weight=\"bold\"");
  constexpr size_t kChars = 150;
  std::vector<std::string> lines;
  for (std::string rest : sub) {
    while (rest.size() > kChars) {
      size_t cut = rest.rfind(' ', kChars);
      if (cut == std::string::npos || cut < kChars / 2) cut = kChars;
      lines.push_back(rest.substr(0, cut));
      rest = rest.substr(cut + (cut < rest.size() && rest[cut] == ' ' ? 1 : 0));
    }
    lines.push_back(rest);
  }
  if (lines.size() > 3) {
    lines.resize(3);
    lines[2] += " ...";
  }
  for (size_t i = 0; i < lines.size(); ++i)
    svg.text({20, 52 + 16 * static_cast<double>(i)}, lines[i], "font-size=\"12.5\" fill=\"#444444\"");
}

//! A legend panel: swatches drawn by callbacks, one entry per row.
class Legend {
 public:
  Legend(double x, double y, double w) : x_(x), y_(y), w_(w) {}
  void add(std::function<void(Svg&, P2)> swatch, std::string label) {
    entries_.push_back({std::move(swatch), std::move(label)});
  }
  //! Draws the panel and returns the y below it.
  double draw(Svg& svg) const {
    const double row = 22;
    const double h = 34 + row * static_cast<double>(entries_.size());
    svg.rect(x_, y_, w_, h, attrs("#999999", 1, "#fafafa"));
    svg.text({x_ + 10, y_ + 20}, "Legend", "font-weight=\"bold\"");
    double y = y_ + 42;
    for (const Entry& e : entries_) {
      e.swatch(svg, P2{x_ + 24, y - 4});
      svg.text({x_ + 46, y}, e.label, "font-size=\"12.5\"");
      y += row;
    }
    return y_ + h;
  }

 private:
  struct Entry {
    std::function<void(Svg&, P2)> swatch;
    std::string label;
  };
  double x_, y_, w_;
  std::vector<Entry> entries_;
};

//! A scale bar of a 1-2-5 length (data units `unit`) at most max_px long; returns y below.
double draw_scale_bar(Svg& svg, double x, double y, double px_per_unit, double max_px, const std::string& unit) {
  if (!(px_per_unit > 0)) return y;
  const double len = nice_floor(max_px / px_per_unit);
  const double l = len * px_per_unit;
  svg.text({x, y}, "Scale", "font-weight=\"bold\"");
  const double by = y + 16;
  const std::string st = attrs("#000000", 2, "none");
  svg.rect(x, by - 3, l / 2, 6, attrs("#000000", 1, "#000000"));
  svg.rect(x + l / 2, by - 3, l / 2, 6, attrs("#000000", 1, "#ffffff"));
  svg.line({x, by - 7}, {x, by + 7}, st);
  svg.line({x + l, by - 7}, {x + l, by + 7}, st);
  svg.text({x + l / 2, by + 22}, fmt(len, step_decimals(len)) + " " + unit,
           "text-anchor=\"middle\" font-size=\"12.5\"");
  return by + 30;
}

//! A text box next to `at` (right of it when it fits in the plot, else left), on a
//! white backing; the first line in bold. Draw it outside the plot's clip group.
void draw_label(Svg& svg, const Plot& p, P2 at, const std::vector<std::string>& lines, const std::string& colour) {
  size_t chars = 0;
  for (const std::string& l : lines) chars = std::max(chars, l.size());
  const double w = 7.6 * static_cast<double>(chars) + 10, h = 17.0 * static_cast<double>(lines.size()) + 6;
  double x = at.x + 8;
  if (x + w > p.left + p.w - 2) x = std::max(p.left + 2, at.x - 8 - w);
  const double y = std::min(std::max(at.y - h / 2, p.top + 2), p.top + p.h - h - 2);
  svg.rect(x, y, w, h, "stroke=\"" + colour + "\" stroke-width=\"0.8\" fill=\"#ffffff\" fill-opacity=\"0.88\"");
  for (size_t i = 0; i < lines.size(); ++i)
    svg.text({x + 5, y + 16 + 17.0 * static_cast<double>(i)}, lines[i],
             "font-size=\"12.5\" fill=\"" + colour + "\"" + (i == 0 ? " font-weight=\"bold\"" : ""));
}

//! A message in the middle of an empty plot.
void draw_note(Svg& svg, const Plot& p, const std::string& msg) {
  svg.text({p.left + p.w / 2, p.top + p.h / 2}, msg, "text-anchor=\"middle\" font-size=\"16\" fill=\"#a00000\"");
}

// ---------------------------------------------------------------------------------
// Geometry helpers

double cross2(const P2& o, const P2& a, const P2& b) { return (a.x - o.x) * (b.y - o.y) - (a.y - o.y) * (b.x - o.x); }

//! Convex hull (monotone chain), counter-clockwise in data coordinates.
std::vector<P2> convex_hull(std::vector<P2> pts) {
  std::sort(pts.begin(), pts.end(), [](const P2& a, const P2& b) { return a.x < b.x || (a.x == b.x && a.y < b.y); });
  if (pts.size() < 3) return pts;
  std::vector<P2> h(2 * pts.size());
  size_t k = 0;
  for (size_t i = 0; i < pts.size(); ++i) {
    while (k >= 2 && cross2(h[k - 2], h[k - 1], pts[i]) <= 1e-12) --k;
    h[k++] = pts[i];
  }
  for (size_t i = pts.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && cross2(h[k - 2], h[k - 1], pts[i]) <= 1e-12) --k;
    h[k++] = pts[i];
  }
  h.resize(k > 1 ? k - 1 : k);
  return h;
}

//! Orthographic view of the world: picture coordinates in millimetres.
struct View3 {
  V3 u, v;  // picture right and up (world unit vectors)
  V3 into;  // viewing direction (into the picture)
  P2 operator()(const V3& p) const { return {1000.0 * u.dot(p), 1000.0 * v.dot(p)}; }
};

struct Box3 {
  double x0, x1, y0, y1, z0, z1;
};

struct GraspFrame {
  V3 o, x, y, z;  // origin, closing, approach x closing, approach
  V3 at(double a, double b, double c) const { return o + x * a + y * b + z * c; }
};

std::vector<P2> box_outline(const GraspFrame& f, const Box3& b, const View3& view) {
  std::vector<P2> pts;
  pts.reserve(8);
  for (int k = 0; k < 8; ++k)
    pts.push_back(view(f.at((k & 1) ? b.x1 : b.x0, (k & 2) ? b.y1 : b.y0, (k & 4) ? b.z1 : b.z0)));
  return convex_hull(pts);
}

//! Draws a projected box outline (a polygon, or a segment when seen edge-on).
void draw_outline(Svg& svg, const Plot& p, const std::vector<P2>& hull, const std::string& style) {
  std::vector<P2> q;
  q.reserve(hull.size());
  for (const P2& h : hull) q.push_back(p.map(h));
  if (q.size() >= 3)
    svg.polygon(q, style);
  else if (q.size() == 2)
    svg.polyline(q, style);
}

// Height colour ramp (dark blue - teal - green - yellow), t in [0, 1].
std::string ramp(double t) {
  static const double stops[5][3] = {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  t = std::min(1.0, std::max(0.0, t)) * 4.0;
  const int i = std::min(3, static_cast<int>(t));
  const double f = t - i;
  // The channels are positive: floor(c + 0.5) is the truncation they were always
  // rounded with (std::lround(c) would differ where the sum c + 0.5 rounds up).
  const auto channel = [&](int c) {
    return static_cast<int>(std::floor(stops[i][c] + f * (stops[i + 1][c] - stops[i][c]) + 0.5));
  };
  char buf[16];
  std::snprintf(buf, sizeof buf, "#%02x%02x%02x", channel(0), channel(1), channel(2));
  return buf;
}

std::string status_line(const PlanResult& r) {
  if (r.status == Status::ok) return "grasp found";
  if (r.status == Status::no_grasp)
    return std::string("no grasp: ") + to_string(r.reason) + " - " + (r.message ? r.message : "");
  return std::string("planner status ") + to_string(r.status) + ": " + (r.message ? r.message : "");
}

// Palette
const char* kPoints = "#1f77b4";
const char* kPalm = "#555555";
const char* kFinger = "#e06000";
const char* kPad = "#d62728";
const char* kApproach = "#2ca02c";
const char* kClosing = "#9467bd";
const char* kPlane = "#8c564b";
const char* kAlternate = "#17becf";

// ---------------------------------------------------------------------------------
// 1 and 2: the object and the grasp from above and from the side

GraspFrame grasp_frame(const Grasp& gr) {
  GraspFrame f;
  f.o = gr.position.cast<double>();
  f.z = gr.approach.cast<double>().normalized();
  f.x = gr.closing.cast<double>().normalized();
  f.y = f.z.cross(f.x).normalized();
  return f;
}

//! The gripper's boxes in the grasp frame: open (max opening) and closed (the grasp's
//! width), and the approach arrow behind the palm.
struct GripperBoxes {
  Box3 palm;
  Box3 fingers_open[2], fingers_closed[2], pads_open[2], pads_closed[2];
  double half_width;  // of the grasp
  V3 ap_from, ap_to;  // the approach arrow
};

GripperBoxes gripper_boxes(const GripperGeometry& g, const Grasp& gr, const GraspFrame& f) {
  const double hf = 0.5 * g.finger_depth_m, hw = 0.5 * g.finger_width_m, t = g.finger_thickness_m;
  const double ho = 0.5 * g.max_opening_m, wc = 0.5 * gr.width;
  GripperBoxes bx{};
  bx.palm = {-(ho + t), ho + t, -0.5 * g.palm_width_m, 0.5 * g.palm_width_m, -hf - g.palm_depth_m, -hf};
  bx.fingers_open[0] = {-ho - t, -ho, -hw, hw, -hf, hf};
  bx.fingers_open[1] = {ho, ho + t, -hw, hw, -hf, hf};
  bx.fingers_closed[0] = {-wc - t, -wc, -hw, hw, -hf, hf};
  bx.fingers_closed[1] = {wc, wc + t, -hw, hw, -hf, hf};
  bx.pads_open[0] = {-ho, -ho, -hw, hw, -hf, hf};
  bx.pads_open[1] = {ho, ho, -hw, hw, -hf, hf};
  bx.pads_closed[0] = {-wc, -wc, -hw, hw, -hf, hf};
  bx.pads_closed[1] = {wc, wc, -hw, hw, -hf, hf};
  bx.half_width = wc;
  const double back = hf + g.palm_depth_m;  // behind the palm
  const double arrow_len = std::max(0.03, 0.75 * g.max_opening_m);
  bx.ap_from = f.o - f.z * (back + 0.01 + arrow_len);
  bx.ap_to = f.o - f.z * (back + 0.01);
  return bx;
}

//! What the top and the side picture share: the planner's outputs, the grasp and the view.
struct WorldScene {
  WorldScene(const Planner& planner_in, const PlanResult& result_in, bool top_in,
             const std::vector<Grasp>& alternates_in)
      : planner(planner_in),
        result(result_in),
        alternates(alternates_in),
        cfg(planner_in.config()),
        obj(planner_in.object_points()),
        top(top_in),
        ok(result_in.status == Status::ok),
        f(grasp_frame(result_in.grasp)),
        boxes(gripper_boxes(cfg.gripper, result_in.grasp, f)),
        plane_ref(ok ? f.o : planner_in.object_centroid().cast<double>()),
        show_plane(!top_in && planner_in.plane_found()) {}

  const Planner& planner;
  const PlanResult& result;
  const std::vector<Grasp>& alternates;  // the ranked grasps after the returned one
  const PlannerConfig& cfg;
  const PointSpan& obj;
  const bool top;
  const bool ok;
  const GraspFrame f;
  const GripperBoxes boxes;
  const V3 plane_ref;  // the side view's support plane is drawn through here
  const bool show_plane;
  View3 view;
  std::string xlabel, ylabel, seen;
};

//! Top: looking down world -z. Side: along the closing direction when it is near
//! horizontal (the two fingers overlap), else along world +y.
void choose_view(WorldScene& s) {
  if (s.top) {
    s.view.u = V3::UnitX();
    s.view.v = V3::UnitY();
    s.view.into = -V3::UnitZ();
    s.xlabel = "world x (mm)";
    s.ylabel = "world y (mm)";
    s.seen = "seen from above (looking down world -z)";
    return;
  }
  V3 d = V3::UnitY();
  if (s.ok && std::fabs(s.f.x.z()) < kNearHorizontal) {
    V3 h(s.f.x.x(), s.f.x.y(), 0.0);
    if (h.norm() > 1e-6) d = h.normalized();
  }
  View3& view = s.view;
  view.into = d;
  view.u = d.cross(V3::UnitZ()).normalized();
  view.v = V3::UnitZ();
  const bool along_y = (d - V3::UnitY()).norm() < 1e-9;
  s.xlabel = view.u.x() > 0.9999    ? "world x (mm)"
             : view.u.x() < -0.9999 ? "world -x (mm)"
             : view.u.y() > 0.9999  ? "world y (mm)"
             : view.u.y() < -0.9999 ? "world -y (mm)"
                                    : "horizontal s = p . " + vec_text(view.u, 2) + " (mm)";
  s.ylabel = "world z (mm)";
  s.seen = along_y ? "seen from the side, looking along world +y"
                   : "seen from the side, looking along the closing direction " + vec_text(d, 2) +
                         " (the two fingers overlap)";
}

//! Extent: the object, the gripper (open), the approach arrow and (side view) the
//! support plane below the reference point.
Bounds world_extent(const WorldScene& s) {
  const Planner& planner = s.planner;
  const View3& view = s.view;
  Bounds b;
  for (uint32_t i = 0; i < s.obj.size(); ++i) b.add(view(s.obj[i].cast<double>()));
  if (!s.top && planner.plane_found() && s.obj.size() > 0 && std::fabs(planner.plane().n.z()) > 0.5) {
    const P2 q = view(s.plane_ref);
    b.add(q.x, q.y - 1000.0 * planner.plane().height(s.plane_ref.cast<float>()) / planner.plane().n.z());
  }
  if (s.ok) {
    for (const P2& q : box_outline(s.f, s.boxes.palm, view)) b.add(q);
    for (const Box3& fb : s.boxes.fingers_open)
      for (const P2& q : box_outline(s.f, fb, view)) b.add(q);
    b.add(view(s.boxes.ap_from));
    b.add(view(s.f.o));
  }
  return b;
}

void draw_world_title(Svg& svg, const WorldScene& s) {
  const Grasp& gr = s.result.grasp;
  std::vector<std::string> sub;
  sub.push_back(std::to_string(s.obj.size()) + " object points (voxel centroids, " + fmt(s.cfg.voxel_leaf_m * 1000, 1) +
                " mm leaf), " + s.seen);
  if (!s.ok) sub.push_back(status_line(s.result));
  if (s.ok)
    sub.push_back("grasp at " + vec_text(s.f.o * 1000, 1) + " mm, approach " + vec_text(s.f.z, 2) + ", closing " +
                  vec_text(s.f.x, 2) + ", width " + fmt(gr.width * 1000, 1) + " mm");
  draw_title(svg, s.top ? "Object cloud and grasp, top view" : "Object cloud and grasp, side view", sub);
}

//! Support plane (side view): its trace in the vertical picture plane through the
//! grasp (or the object centroid), with hatching below it.
void draw_support_plane(Svg& svg, const Plot& p, const WorldScene& s) {
  const Plane& pl = s.planner.plane();
  const V3 n = pl.n.cast<double>();
  const View3& view = s.view;
  const double depth = view.into.dot(s.plane_ref);
  auto h_at = [&](double s_mm) {  // picture height (mm) of the plane at picture x s_mm
    const double sm = s_mm / 1000.0;
    return 1000.0 * -(pl.d + depth * n.dot(view.into) + sm * n.dot(view.u)) / n.z();
  };
  if (std::fabs(n.z()) > 1e-6) {
    const P2 a = p.map(p.x0, h_at(p.x0)), c = p.map(p.x1, h_at(p.x1));
    svg.def(
        "<pattern id=\"hatch\" patternUnits=\"userSpaceOnUse\" width=\"10\" height=\"10\">"
        "<path d=\"M0,10 L10,0\" stroke=\"#c9a89a\" stroke-width=\"1\"/></pattern>");
    svg.polygon({a, c, {c.x, p.top + p.h + 50}, {a.x, p.top + p.h + 50}}, "stroke=\"none\" fill=\"url(#hatch)\"");
    svg.line(a, c, attrs(kPlane, 2.5, "none"));
  }
}

//! Other points of the scene (neither the target nor the support plane) in reach of
//! the picture: neighbouring objects, occluders. Returns how many were drawn.
uint32_t draw_other_points(Svg& svg, const Plot& p, const WorldScene& s) {
  uint32_t n_other = 0;
  const VoxelGrid& grid = s.planner.voxels();
  const double m = 8.0;  // mm beyond the frame
  svg.open("g stroke=\"none\" fill=\"#b0b0b0\" fill-opacity=\"0.7\"");
  for (uint32_t i = 0; i < grid.size() && s.obj.size() > 0; ++i) {
    const uint8_t st = s.planner.voxel_state(i);
    if (st == kVoxelRemoved || st == kVoxelTarget) continue;
    const P2 q = s.view(grid.centroid(i).cast<double>());
    if (q.x < p.x0 - m || q.x > p.x1 + m || q.y < p.y0 - m || q.y > p.y1 + m) continue;
    svg.circle(p.map(q), 1.3, "");
    ++n_other;
  }
  svg.close("g");
  return n_other;
}

struct HeightRange {
  double min = 0, max = 0;  // mm
};

//! Object points: seen from above, coloured by height and drawn low to high. Returns
//! the heights' range (above the support plane when there is one, else world z).
HeightRange draw_object_points(Svg& svg, const Plot& p, const WorldScene& s) {
  const PointSpan& obj = s.obj;
  const double r = std::min(4.0, std::max(1.0, 0.45 * s.cfg.voxel_leaf_m * 1000 * p.sx()));
  double hmin = 0, hmax = 0;
  std::vector<uint32_t> order(obj.size());
  std::vector<double> height(obj.size());
  for (uint32_t i = 0; i < obj.size(); ++i) {
    order[i] = i;
    height[i] = 1000.0 * (s.planner.plane_found() ? s.planner.plane().height(obj[i]) : obj[i].z());
    hmin = i == 0 ? height[i] : std::min(hmin, height[i]);
    hmax = i == 0 ? height[i] : std::max(hmax, height[i]);
  }
  if (s.top) {
    std::sort(order.begin(), order.end(), [&](uint32_t a, uint32_t c) { return height[a] < height[c]; });
    svg.open("g stroke=\"none\" fill-opacity=\"0.85\"");
    for (const uint32_t i : order)
      svg.circle(p.map(s.view(obj[i].cast<double>())), r,
                 "fill=\"" + ramp(hmax > hmin ? (height[i] - hmin) / (hmax - hmin) : 0.5) + "\"");
  } else {
    svg.open(std::string("g stroke=\"none\" fill=\"") + kPoints + "\" fill-opacity=\"0.55\"");
    for (const uint32_t i : order) svg.circle(p.map(s.view(obj[i].cast<double>())), r, "");
  }
  svg.close("g");
  return {hmin, hmax};
}

//! Palm, fingers (open dashed, closed filled), pads, arrows and the grasp centre.
void draw_gripper(Svg& svg, const Plot& p, const WorldScene& s) {
  const GraspFrame& f = s.f;
  const GripperBoxes& bx = s.boxes;
  const View3& view = s.view;
  draw_outline(svg, p, box_outline(f, bx.palm, view), attrs(kPalm, 1.5, kPalm, "fill-opacity=\"0.22\""));
  for (const Box3& fb : bx.fingers_open)
    draw_outline(svg, p, box_outline(f, fb, view),
                 attrs(kFinger, 1.5, kFinger, "fill-opacity=\"0.08\" stroke-dasharray=\"6,4\""));
  for (const Box3& fb : bx.pads_open)
    draw_outline(svg, p, box_outline(f, fb, view), attrs(kPad, 1.5, "none", "stroke-dasharray=\"6,4\""));
  for (const Box3& fb : bx.fingers_closed)
    draw_outline(svg, p, box_outline(f, fb, view), attrs("#a04000", 1.5, kFinger, "fill-opacity=\"0.45\""));
  for (const Box3& fb : bx.pads_closed)
    draw_outline(svg, p, box_outline(f, fb, view),
                 attrs(kPad, 3, kPad, "fill-opacity=\"0.35\" stroke-linejoin=\"round\""));

  const P2 c = p.map(view(f.o));
  // Approach: an arrow behind the palm, or a symbol when it points into / out of the picture.
  const P2 a0 = p.map(view(bx.ap_from)), a1 = p.map(view(bx.ap_to));
  const bool long_arrow = std::hypot(a1.x - a0.x, a1.y - a0.y) > 15;
  if (long_arrow) svg.arrow(a0, a1, kApproach, 3, 13);
  if (!long_arrow || std::fabs(f.z.dot(view.into)) > 0.7) {
    const bool into = f.z.dot(view.into) > 0;
    svg.circle(c, 13, attrs(kApproach, 2.5, "none"));
    if (into) {
      svg.line({c.x - 9, c.y - 9}, {c.x + 9, c.y + 9}, attrs(kApproach, 2.5, "none"));
      svg.line({c.x - 9, c.y + 9}, {c.x + 9, c.y - 9}, attrs(kApproach, 2.5, "none"));
    } else {
      svg.circle(c, 3.5, attrs("none", 0, kApproach));
    }
  }
  // Closing: from the left pad to the right one.
  const double wc = bx.half_width;
  const P2 c0 = p.map(view(f.o - f.x * std::max(wc, 0.01))), c1 = p.map(view(f.o + f.x * std::max(wc, 0.01)));
  if (std::hypot(c1.x - c0.x, c1.y - c0.y) > 12) svg.arrow(c0, c1, kClosing, 2.5, 11);
  svg.circle(c, 4.5, attrs("#000000", 1.5, "#ffffff"));
  svg.line({c.x - 7, c.y}, {c.x + 7, c.y}, attrs("#000000", 1.2, "none"));
  svg.line({c.x, c.y - 7}, {c.x, c.y + 7}, attrs("#000000", 1.2, "none"));
}

//! The ranked alternates: each its closing line between the contacts and its rank.
void draw_alternates(Svg& svg, const Plot& p, const WorldScene& s) {
  for (size_t k = 0; k < s.alternates.size(); ++k) {
    const Grasp& g = s.alternates[k];
    const V3 o = g.position.cast<double>(), x = g.closing.cast<double>();
    const double hw = std::max(0.5 * static_cast<double>(g.width), 0.005);
    svg.line(p.map(s.view(o - x * hw)), p.map(s.view(o + x * hw)),
             attrs(kAlternate, 2.5, "none", "stroke-dasharray=\"5,3\""));
    const P2 c = p.map(s.view(o));
    svg.circle(c, 8, attrs(kAlternate, 1.5, "#ffffff"));
    svg.text({c.x, c.y + 4}, std::to_string(k + 1), "font-size=\"11\" text-anchor=\"middle\"");
  }
}

//! The legend's entries of the gripper (a grasp was found).
void add_gripper_legend(Legend& lg) {
  lg.add(
      [](Svg& s, P2 q) {
        s.circle(q, 4.5, attrs("#000000", 1.5, "#ffffff"));
        s.line({q.x - 7, q.y}, {q.x + 7, q.y}, attrs("#000000", 1.2, "none"));
      },
      "grasp position");
  lg.add([](Svg& s, P2 q) { s.rect(q.x - 14, q.y - 6, 28, 12, attrs(kPalm, 1.5, kPalm, "fill-opacity=\"0.22\"")); },
         "palm");
  lg.add(
      [](Svg& s, P2 q) {
        s.rect(q.x - 14, q.y - 6, 28, 12,
               attrs(kFinger, 1.5, kFinger, "fill-opacity=\"0.08\" stroke-dasharray=\"6,4\""));
      },
      "fingers, open (max opening)");
  lg.add(
      [](Svg& s, P2 q) { s.rect(q.x - 14, q.y - 6, 28, 12, attrs("#a04000", 1.5, kFinger, "fill-opacity=\"0.45\"")); },
      "fingers, closed (width)");
  lg.add(
      [](Svg& s, P2 q) {
        s.line({q.x - 14, q.y}, {q.x + 14, q.y}, attrs(kPad, 3, "none"));
      },
      "finger pads (dashed: open)");
  lg.add(
      [](Svg& s, P2 q) {
        s.arrow({q.x - 15, q.y}, {q.x + 15, q.y}, kApproach, 3, 10);
      },
      "approach (\u2297: into the picture)");
  lg.add([](Svg& s, P2 q) { s.arrow({q.x - 15, q.y}, {q.x + 15, q.y}, kClosing, 2.5, 10); }, "closing direction");
}

//! The legend panel; returns the y below it.
double draw_world_legend(Svg& svg, const WorldScene& s, uint32_t n_other) {
  Legend lg(760, 110, 265);
  if (s.top) {
    lg.add(
        [&](Svg& sv, P2 q) {
          for (int k = 0; k < 4; ++k)
            sv.circle({q.x - 9 + 6.0 * k, q.y}, 2.5, "stroke=\"none\" fill=\"" + ramp(k / 3.0) + "\"");
        },
        "object point (colour: height)");
  } else {
    lg.add(
        [&](Svg& sv, P2 q) {
          for (int k = 0; k < 4; ++k)
            sv.circle({q.x - 9 + 6.0 * k, q.y}, 2.5, std::string("stroke=\"none\" fill=\"") + kPoints + "\"");
        },
        "object point");
  }
  lg.add(
      [](Svg& sv, P2 q) {
        sv.polygon({{q.x, q.y - 6}, {q.x + 6, q.y}, {q.x, q.y + 6}, {q.x - 6, q.y}}, attrs("#000000", 1.2, "none"));
      },
      "object centroid");
  if (n_other > 0)
    lg.add(
        [](Svg& sv, P2 q) {
          for (int k = 0; k < 4; ++k) sv.circle({q.x - 9 + 6.0 * k, q.y}, 1.6, "stroke=\"none\" fill=\"#b0b0b0\"");
        },
        "other points (not target/table)");
  if (s.show_plane)
    lg.add(
        [](Svg& sv, P2 q) {
          sv.line({q.x - 14, q.y}, {q.x + 14, q.y}, attrs(kPlane, 2.5, "none"));
        },
        "support plane");
  if (s.ok) add_gripper_legend(lg);
  if (!s.alternates.empty())
    lg.add(
        [](Svg& sv, P2 q) {
          sv.line({q.x - 14, q.y}, {q.x + 14, q.y}, attrs(kAlternate, 2.5, "none", "stroke-dasharray=\"5,3\""));
          sv.circle(q, 7, attrs(kAlternate, 1.5, "#ffffff"));
        },
        "ranked alternates 1.." + std::to_string(s.alternates.size()) + " (closing line)");
  return lg.draw(svg);
}

//! The top view's colour bar of the heights; returns the y below it.
double draw_height_bar(Svg& svg, const WorldScene& s, HeightRange h, double y) {
  svg.def(
      "<linearGradient id=\"heightramp\" x1=\"0\" y1=\"0\" x2=\"1\" y2=\"0\">"
      "<stop offset=\"0\" stop-color=\"" +
      ramp(0) + "\"/><stop offset=\"0.25\" stop-color=\"" + ramp(0.25) + "\"/><stop offset=\"0.5\" stop-color=\"" +
      ramp(0.5) + "\"/><stop offset=\"0.75\" stop-color=\"" + ramp(0.75) + "\"/><stop offset=\"1\" stop-color=\"" +
      ramp(1) + "\"/></linearGradient>");
  svg.text({760, y}, s.planner.plane_found() ? "Height above support plane" : "Height (world z)",
           "font-weight=\"bold\"");
  svg.rect(760, y + 8, 220, 14, "stroke=\"#666666\" stroke-width=\"1\" fill=\"url(#heightramp)\"");
  svg.text({760, y + 38}, fmt(h.min, 0) + " mm", "font-size=\"12\"");
  svg.text({980, y + 38}, fmt(h.max, 0) + " mm", "font-size=\"12\" text-anchor=\"end\"");
  return y + 66;
}

std::string world_picture(const Planner& planner, const PlanResult& result, bool top,
                          const std::vector<Grasp>& alternates) {
  WorldScene s(planner, result, top, alternates);
  choose_view(s);
  Svg svg(1040, 780);
  const Plot p = make_plot(95, 110, 640, 590, world_extent(s), 0.06, 20.0, true);
  draw_world_title(svg, s);
  draw_axes(svg, p, s.xlabel, s.ylabel, top ? "clip_top" : "clip_side");

  svg.open(std::string("g clip-path=\"url(#") + (top ? "clip_top" : "clip_side") + ")\"");
  if (s.show_plane) draw_support_plane(svg, p, s);
  const uint32_t n_other = draw_other_points(svg, p, s);
  const HeightRange heights = draw_object_points(svg, p, s);
  if (s.ok) draw_gripper(svg, p, s);
  if (s.ok) draw_alternates(svg, p, s);
  // Object centroid.
  if (s.obj.size() > 0) {
    const P2 oc = p.map(s.view(planner.object_centroid().cast<double>()));
    svg.polygon({{oc.x, oc.y - 6}, {oc.x + 6, oc.y}, {oc.x, oc.y + 6}, {oc.x - 6, oc.y}},
                attrs("#000000", 1.2, "none"));
  }
  svg.close("g");
  if (s.obj.size() == 0) draw_note(svg, p, "no object points (" + status_line(result) + ")");

  // Legend, colour bar and scale bar.
  double y = draw_world_legend(svg, s, n_other) + 28;
  if (top && s.obj.size() > 0) y = draw_height_bar(svg, s, heights, y);
  draw_scale_bar(svg, 760, y, p.sx(), 200, "mm");
  return svg.str(top ? "forcegrasp: object and grasp, top view" : "forcegrasp: object and grasp, side view",
                 "Object cloud in the world frame and the planned parallel-gripper grasp; " + s.seen + ".");
}

// ---------------------------------------------------------------------------------
// 3: the silhouette of one viewpoint

int32_t picture_view(const Planner& planner) {
  if (planner.chosen_view() >= 0 && static_cast<uint32_t>(planner.chosen_view()) < planner.view_count())
    return planner.chosen_view();
  int32_t best = -1;
  for (uint32_t i = 0; i < planner.view_count(); ++i) {
    const ViewRecord& v = planner.view(i);
    if (v.has_candidate && (best < 0 || v.beta < planner.view(static_cast<uint32_t>(best)).beta))
      best = static_cast<int32_t>(i);
  }
  if (best < 0 && planner.view_count() > 0) best = 0;
  return best;
}

//! The chosen (or best) viewpoint's analysis, which the silhouette picture shows.
struct SilhouetteScene {
  const Planner& planner;
  const PlanResult& result;
  int32_t vi;  // the viewpoint, -1 when none was analysed
  Status st;   // of analyze_view
  const ViewDetail& d;
  bool have;    // analyze_view succeeded
  bool chosen;  // vi is the viewpoint the grasp came from
};

//! A text box drawn after the plot's clip group (draw_label).
struct Label {
  P2 at;
  std::vector<std::string> lines;
  std::string colour;
};

std::vector<std::string> silhouette_subtitle(const SilhouetteScene& s) {
  const ViewDetail& d = s.d;
  std::vector<std::string> sub;
  uint32_t kept = 0, hit = 0;
  for (uint32_t j = 0; s.have && j < d.n_lines; ++j) {
    kept += d.lines[j].kept ? 1u : 0u;
    hit += d.lines[j].hit ? 1u : 0u;
  }
  if (s.vi >= 0) {
    const ViewRecord& v = s.planner.view(static_cast<uint32_t>(s.vi));
    sub.push_back(std::string(s.chosen ? "chosen viewpoint " : "viewpoint (none chosen; best beta) ") +
                  std::to_string(s.vi) + ": family " + to_string(v.family) + ", theta " +
                  fmt(v.theta * 180.0 / kPi, 1) + " deg; seen along its Z " + vec_text(v.Z.cast<double>(), 2) +
                  ", origin at the object centroid");
    sub.push_back(std::to_string(d.n_points) + " projected points, " + std::to_string(d.n_contour) +
                  "-vertex concave hull, " + std::to_string(d.n_lines) + " scan lines (" + std::to_string(hit) +
                  " crossing, " + std::to_string(kept) + " graspable)");
  }
  sub.push_back(status_line(s.result));
  return sub;
}

//! The scan lines' x range (mm): the contour's, 4 mm wider on each side.
struct XRange {
  double x0, x1;
};
XRange scan_line_range(const ViewDetail& d) {
  double cx0 = 0, cx1 = 0;
  for (uint32_t i = 0; i < d.n_contour; ++i) {
    cx0 = i == 0 ? d.contour[i].x : std::min<double>(cx0, d.contour[i].x);
    cx1 = i == 0 ? d.contour[i].x : std::max<double>(cx1, d.contour[i].x);
  }
  return {1000.0 * cx0 - 4, 1000.0 * cx1 + 4};
}

//! Points, contour.
void draw_silhouette(Svg& svg, const Plot& p, const ViewDetail& d, const PlannerConfig& cfg) {
  const double r = std::min(3.0, std::max(0.9, 0.35 * cfg.voxel_leaf_m * 1000 * p.sx()));
  svg.open("g stroke=\"none\" fill=\"#7a8ca8\" fill-opacity=\"0.55\"");
  for (uint32_t i = 0; i < d.n_points; ++i) svg.circle(p.map(1000.0 * d.points[i].x, 1000.0 * d.points[i].y), r, "");
  svg.close("g");
  std::vector<P2> poly;
  poly.reserve(d.n_contour);
  for (uint32_t i = 0; i < d.n_contour; ++i) poly.push_back(p.map(1000.0 * d.contour[i].x, 1000.0 * d.contour[i].y));
  svg.polygon(poly, attrs(kPoints, 1.6, kPoints, "fill-opacity=\"0.10\" stroke-linejoin=\"round\""));
}

//! Scan lines: all thin grey; the graspable ones green between L and R.
void draw_scan_lines(Svg& svg, const Plot& p, const ViewDetail& d, XRange cx, const PlannerConfig& cfg) {
  svg.open("g stroke=\"#9a9a9a\" stroke-width=\"0.6\"");
  for (uint32_t j = 0; j < d.n_lines; ++j) {
    const double y = 1000.0 * d.lines[j].y;
    svg.line(p.map(cx.x0, y), p.map(cx.x1, y), "");
  }
  svg.close("g");
  const double lr = std::max(1.6, std::min(3.0, 0.3 * cfg.scan_delta_m * 1000 * p.sy()));
  svg.open("g stroke=\"#2ca02c\" stroke-width=\"1.2\"");
  for (uint32_t j = 0; j < d.n_lines; ++j)
    if (d.lines[j].kept)
      svg.line(p.map(1000.0 * d.lines[j].left, 1000.0 * d.lines[j].y),
               p.map(1000.0 * d.lines[j].right, 1000.0 * d.lines[j].y), "");
  svg.close("g");
  svg.open("g stroke=\"#105010\" stroke-width=\"0.8\"");
  for (uint32_t j = 0; j < d.n_lines; ++j) {
    if (!d.lines[j].kept) continue;
    svg.circle(p.map(1000.0 * d.lines[j].left, 1000.0 * d.lines[j].y), lr, "fill=\"#2ca02c\"");
    svg.circle(p.map(1000.0 * d.lines[j].right, 1000.0 * d.lines[j].y), lr, "fill=\"#ffffff\"");
  }
  svg.close("g");
}

//! Best window: its band and the two fitted sides x = a y + b.
void draw_best_window(Svg& svg, const Plot& p, const ViewDetail& d, XRange cx, std::vector<Label>& labels) {
  const SideFit& w = d.best;
  const double y0 = d.lines[w.first].y, y1 = d.lines[w.first + w.count - 1].y;
  const P2 b0 = p.map(cx.x0, 1000.0 * y1), b1 = p.map(cx.x1, 1000.0 * y0);
  svg.rect(b0.x, b0.y, b1.x - b0.x, b1.y - b0.y, "stroke=\"none\" fill=\"#d62728\" fill-opacity=\"0.10\"");
  auto side = [&](double a, double bb, double y) { return p.map(1000.0 * (a * y + bb), 1000.0 * y); };
  // Thin dashed extensions show the fitted directions beyond the window.
  const double ext = std::max(0.5 * (y1 - y0), 0.006);
  for (int s = 0; s < 2; ++s) {
    const double a = s == 0 ? w.a_left : w.a_right, bb = s == 0 ? w.b_left : w.b_right;
    svg.line(side(a, bb, y0 - ext), side(a, bb, y1 + ext), attrs(kPad, 1, "none", "stroke-dasharray=\"4,3\""));
    svg.line(side(a, bb, y0), side(a, bb, y1), attrs(kPad, 3.2, "none", "stroke-linecap=\"round\""));
  }
  const P2 lab = side(w.a_right, w.b_right, y1 + ext);
  labels.push_back({lab,
                    {"beta = " + rad_text(w.beta) + " rad (" + fmt(w.beta * 180.0 / kPi, 2) + " deg)",
                     "best window: width " + fmt(w.width * 1000, 1) + " mm"},
                    kPad});
}

//! The planned grasp in this frame (its window may be another of the viewpoint's candidates).
void draw_grasp_in_view(Svg& svg, const Plot& p, const SilhouetteScene& s, std::vector<Label>& labels) {
  const PlannerConfig& cfg = s.planner.config();
  const PlanResult& result = s.result;
  const ViewRecord& v = s.planner.view(static_cast<uint32_t>(s.vi));
  const V3 rel = (result.grasp.position - s.planner.object_centroid()).cast<double>();
  const double gx = 1000.0 * v.X.cast<double>().dot(rel), gy = 1000.0 * v.Y.cast<double>().dot(rel);
  const double hw = 500.0 * cfg.gripper.finger_width_m, wc = 500.0 * result.grasp.width;
  for (int k = -1; k <= 1; k += 2)
    svg.line(p.map(gx + k * wc, gy - hw), p.map(gx + k * wc, gy + hw),
             attrs(kFinger, 4, "none", "stroke-opacity=\"0.85\""));
  const P2 c = p.map(gx, gy);
  svg.circle(c, 4.5, attrs("#000000", 1.5, "#ffffff"));
  svg.line({c.x - 7, c.y}, {c.x + 7, c.y}, attrs("#000000", 1.2, "none"));
  svg.line({c.x, c.y - 7}, {c.x, c.y + 7}, attrs("#000000", 1.2, "none"));
  labels.push_back({p.map(gx + wc, gy - hw),
                    {"planned grasp", "beta " + rad_text(result.grasp.beta) + " rad, width " +
                                          fmt(result.grasp.width * 1000, 1) + " mm"},
                    "#a04000"});
}

//! The legend panel and the scale bar.
void draw_silhouette_legend(Svg& svg, const Plot& p, bool show_grasp) {
  Legend lg(760, 110, 265);
  lg.add(
      [](Svg& s, P2 q) {
        for (int k = 0; k < 4; ++k) s.circle({q.x - 9 + 6.0 * k, q.y}, 2, "stroke=\"none\" fill=\"#7a8ca8\"");
      },
      "projected object point");
  lg.add([](Svg& s, P2 q) { s.rect(q.x - 14, q.y - 7, 28, 14, attrs(kPoints, 1.6, kPoints, "fill-opacity=\"0.10\"")); },
         "concave hull contour");
  lg.add([](Svg& s, P2 q) { s.line({q.x - 14, q.y}, {q.x + 14, q.y}, attrs("#9a9a9a", 0.8, "none")); }, "scan line");
  lg.add(
      [](Svg& s, P2 q) {
        s.line({q.x - 14, q.y}, {q.x + 14, q.y}, attrs("#2ca02c", 1.5, "none"));
      },
      "graspable line (width < opening)");
  lg.add(
      [](Svg& s, P2 q) {
        s.circle({q.x - 7, q.y}, 3, attrs("#105010", 0.8, "#2ca02c"));
        s.circle({q.x + 7, q.y}, 3, attrs("#105010", 0.8, "#ffffff"));
      },
      "L_j (filled), R_j (open)");
  lg.add(
      [](Svg& s, P2 q) { s.rect(q.x - 14, q.y - 7, 28, 14, "stroke=\"none\" fill=\"#d62728\" fill-opacity=\"0.15\""); },
      "best window of the viewpoint");
  lg.add(
      [](Svg& s, P2 q) {
        s.line({q.x - 14, q.y}, {q.x + 14, q.y}, attrs(kPad, 3.2, "none"));
      },
      "fitted sides x = a y + b");
  if (show_grasp)
    lg.add(
        [](Svg& s, P2 q) {
          s.line({q.x - 10, q.y - 7}, {q.x - 10, q.y + 7}, attrs(kFinger, 4, "none"));
          s.line({q.x + 10, q.y - 7}, {q.x + 10, q.y + 7}, attrs(kFinger, 4, "none"));
          s.circle(q, 3.5, attrs("#000000", 1.2, "#ffffff"));
        },
        "planned grasp: centre, pads");
  const double y = lg.draw(svg) + 28;
  draw_scale_bar(svg, 760, y, p.sx(), 200, "mm");
}

std::string silhouette_picture(Planner& planner, const PlanResult& result) {
  const PlannerConfig& cfg = planner.config();
  const int32_t vi = picture_view(planner);
  auto detail = std::make_unique<ViewDetail>();
  Status st = Status::invalid_argument;
  if (vi >= 0) st = planner.analyze_view(static_cast<uint32_t>(vi), *detail);
  const ViewDetail& d = *detail;
  const SilhouetteScene s{planner, result, vi, st, d, st == Status::ok, vi >= 0 && vi == planner.chosen_view()};

  Bounds b;
  if (s.have) {
    for (uint32_t i = 0; i < d.n_points; ++i) b.add(1000.0 * d.points[i].x, 1000.0 * d.points[i].y);
    for (uint32_t i = 0; i < d.n_contour; ++i) b.add(1000.0 * d.contour[i].x, 1000.0 * d.contour[i].y);
  }
  Svg svg(1040, 780);
  const Plot p = make_plot(95, 110, 640, 590, b, 0.06, 20.0, true);
  draw_title(svg, "Silhouette, scan lines and force balance (XOY)", silhouette_subtitle(s));
  draw_axes(svg, p, "x: closing direction X (mm)", "y: principal axis Y (mm)", "clip_sil");

  std::vector<Label> labels;
  svg.open("g clip-path=\"url(#clip_sil)\"");
  if (s.have) {
    const XRange cx = scan_line_range(d);
    draw_silhouette(svg, p, d, cfg);
    draw_scan_lines(svg, p, d, cx, cfg);
    if (d.has_best && d.best.count > 0 && d.best.first + d.best.count <= d.n_lines)
      draw_best_window(svg, p, d, cx, labels);
    if (s.chosen && result.status == Status::ok) draw_grasp_in_view(svg, p, s, labels);
  }
  svg.close("g");
  for (const Label& l : labels) draw_label(svg, p, l.at, l.lines, l.colour);
  if (!s.have)
    draw_note(svg, p,
              vi < 0 ? "no viewpoint was analysed (" + status_line(result) + ")"
                     : std::string("analyze_view failed: ") + to_string(st));

  draw_silhouette_legend(svg, p, s.chosen && result.status == Status::ok);
  return svg.str("forcegrasp: silhouette of the chosen viewpoint",
                 "Object points projected onto the viewpoint's XOY plane, their concave hull, the scan lines, "
                 "the graspable lines with their leftmost and rightmost contour points, and the best window's "
                 "fitted sides with their angle beta.");
}

// ---------------------------------------------------------------------------------
// 4: beta and dz over the viewpoints

void draw_marker(Svg& svg, ViewFamily f, P2 c, double r, const std::string& style) {
  switch (f) {
    case ViewFamily::sensor_arc:
      svg.circle(c, r, style);
      break;
    case ViewFamily::full_circle:
      svg.rect(c.x - r * 0.9, c.y - r * 0.9, 1.8 * r, 1.8 * r, style);
      break;
    case ViewFamily::middle_axis:
      svg.polygon({{c.x, c.y - 1.2 * r}, {c.x + 1.1 * r, c.y + 0.8 * r}, {c.x - 1.1 * r, c.y + 0.8 * r}}, style);
      break;
    case ViewFamily::minor_axis:
      svg.polygon({{c.x, c.y - 1.25 * r}, {c.x + 1.25 * r, c.y}, {c.x, c.y + 1.25 * r}, {c.x - 1.25 * r, c.y}}, style);
      break;
    case ViewFamily::support_normal:
    case ViewFamily::support_major:
    case ViewFamily::support_minor:  // a triangle pointing down: the support plane's frame
      svg.polygon({{c.x, c.y + 1.2 * r}, {c.x + 1.1 * r, c.y - 0.8 * r}, {c.x - 1.1 * r, c.y - 0.8 * r}}, style);
      break;
  }
}
const char* family_colour(ViewFamily f) {
  switch (f) {
    case ViewFamily::sensor_arc:
      return "#1f77b4";
    case ViewFamily::full_circle:
      return "#ff7f0e";
    case ViewFamily::middle_axis:
      return "#2ca02c";
    case ViewFamily::minor_axis:
      return "#9467bd";
    case ViewFamily::support_normal:
      return "#8c564b";
    case ViewFamily::support_major:
      return "#e377c2";
    case ViewFamily::support_minor:
      return "#7f7f7f";
  }
  return "#000000";
}

//! The viewpoints the balance picture plots: each one's best candidate with contacts.
struct BalanceRows {
  struct Row {
    ViewFamily f;
    double theta_deg, beta, dz_mm;
    uint32_t index;
  };
  std::vector<Row> rows;
  uint32_t no_cand = 0, no_contact = 0;  // left out: without a candidate, with dz = -1
  bool fam_used[kViewFamilies] = {};
  Bounds tb;  // of every viewpoint's theta (deg)
};

BalanceRows balance_rows(const Planner& planner) {
  BalanceRows b;
  for (uint32_t i = 0; i < planner.view_count(); ++i) {
    const ViewRecord& v = planner.view(i);
    b.tb.add(v.theta * 180.0 / kPi, 0);
    if (!v.has_candidate) {
      ++b.no_cand;
      continue;
    }
    if (v.dz < 0) {
      ++b.no_contact;
      continue;
    }
    b.rows.push_back({v.family, v.theta * 180.0 / kPi, v.beta, v.dz * 1000.0, i});
    b.fam_used[static_cast<int>(v.family)] = true;
  }
  return b;
}

//! One panel's marks (0: beta with beta_max, 1: dz) inside its clip group.
void draw_balance_panel(Svg& svg, const Plot& p, int panel, const BalanceRows& b, const Planner& planner,
                        const PlanResult& result, bool have_chosen) {
  const double beta_max = planner.config().beta_max_rad;
  svg.open(std::string("g clip-path=\"url(#") + (panel == 0 ? "clip_beta" : "clip_dz") + ")\"");
  if (panel == 0) {
    svg.line(p.map(p.x0, beta_max), p.map(p.x1, beta_max), attrs(kPad, 1.8, "none", "stroke-dasharray=\"8,5\""));
    const P2 lab = p.map(p.x1, beta_max);
    svg.text({lab.x - 6, lab.y - 6}, "beta_max = " + fmt(beta_max, 3) + " rad",
             std::string("text-anchor=\"end\" font-size=\"12\" fill=\"") + kPad + "\"");
  }
  if (have_chosen) {
    const double th = planner.view(static_cast<uint32_t>(planner.chosen_view())).theta * 180.0 / kPi;
    const double val = panel == 0 ? result.grasp.beta : result.grasp.dz * 1000.0;
    svg.line(p.map(th, p.y0), p.map(th, p.y1), attrs("#d62728", 1, "none", "stroke-opacity=\"0.35\""));
    svg.circle(p.map(th, val), 10, attrs("#d62728", 2.5, "#ffd84d", "fill-opacity=\"0.6\""));
  }
  for (const BalanceRows::Row& r : b.rows) {
    const P2 c = p.map(r.theta_deg, panel == 0 ? r.beta : r.dz_mm);
    draw_marker(svg, r.f, c, 4.2, attrs("#222222", 0.8, family_colour(r.f), "fill-opacity=\"0.85\""));
  }
  if (b.rows.empty()) draw_note(svg, p, "no viewpoint has a candidate with contacts");
  svg.close("g");
}

//! The legend panel and the selection rule below it.
void draw_balance_legend(Svg& svg, const BalanceRows& b, bool have_chosen) {
  Legend lg(760, 110, 265);
  for (int k = 0; k < kViewFamilies; ++k) {
    const ViewFamily f = static_cast<ViewFamily>(k);
    if (!b.fam_used[k] && k != 0) continue;
    lg.add([f](Svg& s, P2 q) { draw_marker(s, f, q, 4.5, attrs("#222222", 0.8, family_colour(f))); },
           std::string("viewpoint, ") + to_string(f));
  }
  if (have_chosen)
    lg.add([](Svg& s, P2 q) { s.circle(q, 9, attrs("#d62728", 2.5, "#ffd84d", "fill-opacity=\"0.6\"")); },
           "chosen grasp (its candidate)");
  lg.add(
      [](Svg& s, P2 q) {
        s.line({q.x - 14, q.y}, {q.x + 14, q.y}, attrs(kPad, 1.8, "none", "stroke-dasharray=\"8,5\""));
      },
      "beta_max (balanced below)");
  const double y = lg.draw(svg) + 30;
  svg.text({760, y}, "Selection (design E.3):", "font-weight=\"bold\" font-size=\"12.5\"");
  svg.text({760, y + 18}, "among beta <= beta_max the smallest", "font-size=\"12\"");
  svg.text({760, y + 34}, "dz wins, else the smallest beta, then", "font-size=\"12\"");
  svg.text({760, y + 50}, "the executability checks.", "font-size=\"12\"");
}

std::string balance_picture(const Planner& planner, const PlanResult& result) {
  const PlannerConfig& cfg = planner.config();
  const double beta_max = cfg.beta_max_rad;
  const BalanceRows b = balance_rows(planner);
  const bool ok = result.status == Status::ok;
  const int32_t cv = planner.chosen_view();
  const bool have_chosen = ok && cv >= 0 && static_cast<uint32_t>(cv) < planner.view_count();
  double bmax = beta_max, dmax = 0;
  for (const BalanceRows::Row& r : b.rows) {
    bmax = std::max(bmax, r.beta);
    dmax = std::max(dmax, r.dz_mm);
  }
  if (have_chosen) {
    bmax = std::max<double>(bmax, result.grasp.beta);
    dmax = std::max<double>(dmax, result.grasp.dz * 1000.0);
  }
  if (!(dmax > 0)) dmax = 1;
  Bounds tb = b.tb;
  if (tb.empty()) tb.add(0, 0);
  const double span = std::max(10.0, tb.x1 - tb.x0);
  const double tx0 = tb.x0 - 0.04 * span, tx1 = tb.x1 + 0.04 * span;

  Svg svg(1040, 800);
  Plot pb;
  pb.left = 95;
  pb.top = 110;
  pb.w = 640;
  pb.h = 270;
  pb.x0 = tx0;
  pb.x1 = tx1;
  pb.y0 = 0;
  pb.y1 = bmax * 1.1;
  Plot pd = pb;
  pd.top = 455;
  pd.y1 = dmax * 1.1;

  std::vector<std::string> sub;
  sub.push_back(std::to_string(planner.view_count()) + " viewpoints analysed, " + std::to_string(b.rows.size()) +
                " plotted; left out: " + std::to_string(b.no_cand) + " without a candidate, " +
                std::to_string(b.no_contact) + " with no contact within the pads' reach (dz = -1)");
  sub.push_back("each viewpoint's best candidate (smallest rank); " + status_line(result) +
                (have_chosen ? "; chosen grasp: beta " + rad_text(result.grasp.beta) + " rad, dz " +
                                   fmt(result.grasp.dz * 1000, 2) + " mm"
                             : ""));
  draw_title(svg, "Force balance over the virtual viewpoints", sub);
  draw_axes(svg, pb, "viewpoint angle theta about the family's axis (deg)", "beta (rad)", "clip_beta");
  draw_axes(svg, pd, "viewpoint angle theta about the family's axis (deg)", "dz (mm)", "clip_dz");
  svg.text({pb.left + 8, pb.top + 18}, "XOY balance: angle between the fitted sides",
           "font-size=\"12.5\" fill=\"#444444\"");
  svg.text({pd.left + 8, pd.top + 18}, "XOZ balance: depth difference of the contact regions",
           "font-size=\"12.5\" fill=\"#444444\"");
  draw_balance_panel(svg, pb, 0, b, planner, result, have_chosen);
  draw_balance_panel(svg, pd, 1, b, planner, result, have_chosen);
  draw_balance_legend(svg, b, have_chosen);
  return svg.str("forcegrasp: force balance over the viewpoints",
                 "beta (XOY force balance, rad) and dz (XOZ force balance, mm) of each viewpoint's best "
                 "candidate against the viewpoint angle, by viewpoint family.");
}

// ---------------------------------------------------------------------------------

std::string index_html(const PlanResult& result) {
  std::ostringstream o;
  o << "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\"/>\n"
    << "<title>forcegrasp pictures</title>\n"
    << "<style>body{font-family:sans-serif;margin:20px;max-width:1100px}"
       "img{max-width:100%;border:1px solid #ccc;margin:6px 0 24px 0}</style>\n"
    << "</head>\n<body>\n<h1>forcegrasp: planner stages</h1>\n<p>" << esc(status_line(result));
  if (result.status == Status::ok) {
    const Grasp& g = result.grasp;
    o << ": position " << esc(vec_text(g.position.cast<double>(), 4)) << " m, approach "
      << esc(vec_text(g.approach.cast<double>(), 3)) << ", closing " << esc(vec_text(g.closing.cast<double>(), 3))
      << ", width " << fmt(g.width * 1000, 1) << " mm, beta " << rad_text(g.beta) << " rad, dz " << fmt(g.dz * 1000, 2)
      << " mm (" << to_string(g.family) << ", viewpoint " << fmt(g.viewpoint, 3) << " rad)";
  }
  o << ". " << result.points.object << " object points, " << result.viewpoints << " viewpoints, " << result.candidates
    << " candidates.</p>\n";
  const char* pics[4][2] = {{"object_top.svg", "Object cloud and grasp from above"},
                            {"object_side.svg", "Object cloud and grasp from the side, with the support plane"},
                            {"silhouette.svg", "Silhouette of the chosen viewpoint: contour, scan lines, fitted sides"},
                            {"balance.svg", "Force balance (beta, dz) over the viewpoints"}};
  for (const auto& pic : pics)
    o << "<h2>" << pic[1] << "</h2>\n<p><a href=\"" << pic[0] << "\"><img src=\"" << pic[0] << "\" alt=\"" << pic[1]
      << "\"/></a></p>\n";
  o << "</body>\n</html>\n";
  return o.str();
}

[[nodiscard]] bool write_file(const std::filesystem::path& path, const std::string& text, std::string& error) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  if (!out) {
    error = "cannot write " + path.string() + ": " + std::strerror(errno);
    return false;
  }
  out.write(text.data(), static_cast<std::streamsize>(text.size()));
  out.close();
  if (!out) {
    error = "cannot write " + path.string() + ": write failed";
    return false;
  }
  return true;
}

}  // namespace

bool write_pictures(Planner& planner, const PlanResult& result, const std::string& dir, std::string& error,
                    const std::vector<Grasp>& alternates) {
  try {
    namespace fs = std::filesystem;
    if (dir.empty()) {
      error = "the pictures folder name is empty";
      return false;
    }
    const fs::path root(dir);
    std::error_code ec;
    fs::create_directories(root, ec);
    if (ec || !fs::is_directory(root, ec)) {
      error = "cannot create the pictures folder " + dir + (ec ? ": " + ec.message() : ": not a directory");
      return false;
    }
    const std::pair<const char*, std::string> files[] = {
        {"object_top.svg", world_picture(planner, result, true, alternates)},
        {"object_side.svg", world_picture(planner, result, false, alternates)},
        {"silhouette.svg", silhouette_picture(planner, result)},
        {"balance.svg", balance_picture(planner, result)},
        {"index.html", index_html(result)},
    };
    for (const auto& f : files)
      if (!write_file(root / f.first, f.second, error)) return false;
    return true;
  } catch (const std::exception& e) {
    error = std::string("cannot write the pictures into ") + dir + ": " + e.what();
    return false;
  }
}

}  // namespace fg::host
