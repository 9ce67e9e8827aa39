#include "sim/obj_mesh.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <mutex>
#include <numeric>
#include <sstream>
#include <string_view>
#include <unordered_map>
#include <utility>

namespace fg::sim {

namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kLeafSize = 4;
constexpr int kStackSize = 64;  // the tree is balanced: depth <= log2(triangles) + 1

// Nearest feature of a triangle: its face, a corner k or the edge from corner k to k + 1.
enum class Feature { face, corner0, corner1, corner2, edge01, edge12, edge20 };

// Closest point of segment a-b to p; t in [0, 1] along it.
V3 closest_on_segment(const V3& p, const V3& a, const V3& b, double& t) {
  const V3 ab = b - a;
  const double len2 = ab.squaredNorm();
  t = len2 > 0.0 ? std::clamp((p - a).dot(ab) / len2, 0.0, 1.0) : 0.0;
  return a + t * ab;
}

// Closest point of triangle abc to p and the feature it lies on (Ericson, Real-Time
// Collision Detection 5.1.5). Zero-area triangles are treated as their three edges.
V3 closest_on_triangle(const V3& p, const V3& a, const V3& b, const V3& c, Feature& feature) {
  const V3 ab = b - a, ac = c - a;
  if (ab.cross(ac).squaredNorm() <= 0.0) {
    const V3* ends[3][2] = {{&a, &b}, {&b, &c}, {&c, &a}};
    const Feature edges[3] = {Feature::edge01, Feature::edge12, Feature::edge20};
    const Feature corners[3] = {Feature::corner0, Feature::corner1, Feature::corner2};
    V3 best = a;
    double best_d2 = kInf;
    for (int k = 0; k < 3; ++k) {
      double t;
      const V3 q = closest_on_segment(p, *ends[k][0], *ends[k][1], t);
      const double d2 = (p - q).squaredNorm();
      if (d2 < best_d2) {
        best_d2 = d2;
        best = q;
        feature = t <= 0.0 ? corners[k] : t >= 1.0 ? corners[(k + 1) % 3] : edges[k];
      }
    }
    return best;
  }
  const V3 ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0.0 && d2 <= 0.0) {
    feature = Feature::corner0;
    return a;
  }
  const V3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0.0 && d4 <= d3) {
    feature = Feature::corner1;
    return b;
  }
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0) {
    feature = Feature::edge01;
    return a + (d1 / (d1 - d3)) * ab;
  }
  const V3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0.0 && d5 <= d6) {
    feature = Feature::corner2;
    return c;
  }
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0) {
    feature = Feature::edge20;
    return a + (d2 / (d2 - d6)) * ac;
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0.0 && d4 - d3 >= 0.0 && d5 - d6 >= 0.0) {
    feature = Feature::edge12;
    return b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b);
  }
  const double denom = 1.0 / (va + vb + vc);
  feature = Feature::face;
  return a + ab * (vb * denom) + ac * (vc * denom);
}

// Moller-Trumbore; inclusive edges so that rays through shared edges are not lost.
[[nodiscard]] bool ray_triangle(const V3& o, const V3& d, const V3& a, const V3& b, const V3& c, double& t) {
  const V3 e1 = b - a, e2 = c - a;
  const V3 pv = d.cross(e2);
  const double det = e1.dot(pv);
  if (det == 0.0) return false;
  const double inv = 1.0 / det;
  const V3 tv = o - a;
  const double u = tv.dot(pv) * inv;
  if (u < 0.0 || u > 1.0) return false;
  const V3 qv = tv.cross(e1);
  const double v = d.dot(qv) * inv;
  if (v < 0.0 || u + v > 1.0) return false;
  t = e2.dot(qv) * inv;
  return true;
}

double box_distance2(const Aabb& b, const V3& p) {
  const V3 below = (b.lo - p).cwiseMax(0.0);
  const V3 above = (p - b.hi).cwiseMax(0.0);
  return (below + above).squaredNorm();
}

// Angle of a triangle at corner a (between a->b and a->c); 0 when degenerate.
double corner_angle(const V3& a, const V3& b, const V3& c) {
  const V3 u = b - a, v = c - a;
  const double s = u.cross(v).norm();
  if (s == 0.0) return 0.0;
  return std::atan2(s, u.dot(v));
}

}  // namespace

// ---------------------------------------------------------------------------- TriangleMesh

struct TriangleMesh::Nearest {
  double d2 = kInf;
  int triangle = -1;
  Feature feature = Feature::face;
  V3 point = V3::Zero();
};

TriangleMesh::TriangleMesh(std::vector<V3> vertices, std::vector<Triangle> triangles, std::vector<int> groups,
                           std::vector<std::string> group_names, std::string source)
    : source_(std::move(source)),
      vertices_(std::move(vertices)),
      triangles_(std::move(triangles)),
      groups_(std::move(groups)),
      group_names_(std::move(group_names)) {
  const size_t nt = triangles_.size();
  const size_t ng = group_names_.size();
  auto corner = [&](size_t t, int k) -> const V3& {
    return vertices_[static_cast<size_t>(triangles_[t][static_cast<size_t>(k)])];
  };

  // Volumes per group fix the orientation: a group wound inside out is reversed.
  std::vector<double> group_volume(ng, 0.0);
  std::vector<V3> group_moment(ng, V3::Zero());
  for (size_t t = 0; t < nt; ++t) {
    const V3 &a = corner(t, 0), &b = corner(t, 1), &c = corner(t, 2);
    const double v = a.dot(b.cross(c)) / 6.0;
    const size_t g = static_cast<size_t>(groups_[t]);
    group_volume[g] += v;
    group_moment[g] += v * 0.25 * (a + b + c);
  }
  std::vector<double> orientation(ng, 1.0);
  for (size_t g = 0; g < ng; ++g) {
    if (group_volume[g] < 0.0) orientation[g] = -1.0;
    volume_ += orientation[g] * group_volume[g];
    centroid_ += orientation[g] * group_moment[g];
  }
  for (const V3& v : vertices_) bounds_.extend(v);
  if (volume_ > 0.0) {
    centroid_ /= volume_;
  } else {
    centroid_ = V3::Zero();
    for (const V3& v : vertices_) centroid_ += v;
    if (!vertices_.empty()) centroid_ /= static_cast<double>(vertices_.size());
  }

  face_normals_.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    const V3 n = (corner(t, 1) - corner(t, 0)).cross(corner(t, 2) - corner(t, 0));
    const double len = n.norm();
    face_normals_[t] = len > 0.0 ? V3(orientation[static_cast<size_t>(groups_[t])] * n / len) : V3(V3::Zero());
  }

  // Pseudo-normals shared by the triangles of a group around a vertex or an edge. Vertices
  // at the same position are one vertex here, so a seam of duplicated vertices stays closed.
  std::vector<int> weld(vertices_.size());
  {
    std::map<std::array<double, 3>, int> first_at;
    for (size_t i = 0; i < vertices_.size(); ++i) {
      const V3& v = vertices_[i];
      weld[i] = first_at.emplace(std::array<double, 3>{v.x(), v.y(), v.z()}, static_cast<int>(i)).first->second;
    }
  }
  std::map<std::array<int, 2>, V3> vertex_sum;  // (group, vertex)
  std::map<std::array<int, 3>, V3> edge_sum;    // (group, lower vertex, higher vertex)
  auto edge_key = [&](size_t t, int k) {
    const int a = weld[static_cast<size_t>(triangles_[t][static_cast<size_t>(k)])];
    const int b = weld[static_cast<size_t>(triangles_[t][static_cast<size_t>((k + 1) % 3)])];
    return std::array<int, 3>{groups_[t], std::min(a, b), std::max(a, b)};
  };
  auto vertex_key = [&](size_t t, int k) {
    return std::array<int, 2>{groups_[t], weld[static_cast<size_t>(triangles_[t][static_cast<size_t>(k)])]};
  };
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      const double angle = corner_angle(corner(t, k), corner(t, (k + 1) % 3), corner(t, (k + 2) % 3));
      auto vi = vertex_sum.emplace(vertex_key(t, k), V3::Zero()).first;
      vi->second += angle * face_normals_[t];
      auto ei = edge_sum.emplace(edge_key(t, k), V3::Zero()).first;
      ei->second += face_normals_[t];
    }
  }
  corner_normals_.resize(nt);
  edge_normals_.resize(nt);
  for (size_t t = 0; t < nt; ++t) {
    for (int k = 0; k < 3; ++k) {
      corner_normals_[t][static_cast<size_t>(k)] = vertex_sum.at(vertex_key(t, k));
      edge_normals_[t][static_cast<size_t>(k)] = edge_sum.at(edge_key(t, k));
    }
  }

  // One hierarchy per group (median splits: balanced, so the traversal stacks stay short).
  order_.resize(nt);
  std::iota(order_.begin(), order_.end(), 0);
  std::stable_sort(order_.begin(), order_.end(),
                   [&](int a, int b) { return groups_[static_cast<size_t>(a)] < groups_[static_cast<size_t>(b)]; });
  std::vector<V3> centres(nt);
  for (size_t t = 0; t < nt; ++t) centres[t] = (corner(t, 0) + corner(t, 1) + corner(t, 2)) / 3.0;
  nodes_.reserve(2 * nt / kLeafSize + 2 * ng + 1);
  roots_.assign(ng, -1);
  size_t begin = 0;
  while (begin < nt) {
    const int g = groups_[static_cast<size_t>(order_[begin])];
    size_t end = begin;
    while (end < nt && groups_[static_cast<size_t>(order_[end])] == g) ++end;
    roots_[static_cast<size_t>(g)] = build(static_cast<int>(begin), static_cast<int>(end), centres);
    begin = end;
  }
}

int TriangleMesh::build(int begin, int end, const std::vector<V3>& centres) {
  Node node;
  for (int i = begin; i < end; ++i)
    for (int v : triangles_[static_cast<size_t>(order_[static_cast<size_t>(i)])])
      node.box.extend(vertices_[static_cast<size_t>(v)]);
  const int index = static_cast<int>(nodes_.size());
  if (end - begin <= kLeafSize) {
    node.first = begin;
    node.count = end - begin;
    nodes_.push_back(node);
    return index;
  }
  Aabb centre_box;
  for (int i = begin; i < end; ++i) centre_box.extend(centres[static_cast<size_t>(order_[static_cast<size_t>(i)])]);
  int axis;
  centre_box.size().maxCoeff(&axis);
  const int mid = begin + (end - begin) / 2;
  std::nth_element(order_.begin() + begin, order_.begin() + mid, order_.begin() + end, [&](int a, int b) {
    return centres[static_cast<size_t>(a)][axis] < centres[static_cast<size_t>(b)][axis];
  });
  nodes_.push_back(node);
  build(begin, mid, centres);  // lands at index + 1
  const int right = build(mid, end, centres);
  nodes_[static_cast<size_t>(index)].right = right;
  return index;
}

void TriangleMesh::project(const V3& u, double& lo, double& hi) const {
  lo = kInf;
  hi = -kInf;
  for (const V3& v : vertices_) {
    const double s = u.dot(v);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
}

double TriangleMesh::extent_along(const V3& u) const {
  double lo, hi;
  project(u, lo, hi);
  return vertices_.empty() ? 0.0 : hi - lo;
}

bool TriangleMesh::intersect(const V3& o, const V3& d, double tmin, double tmax, double& t, V3& normal,
                             int* triangle) const {
  const V3 inv_d(1.0 / d.x(), 1.0 / d.y(), 1.0 / d.z());
  double best = tmax;
  int best_tri = -1;
  int stack[kStackSize];
  for (int root : roots_) {
    if (root < 0) continue;
    int top = 0;
    stack[top++] = root;
    while (top > 0) {
      const int ni = stack[--top];
      const Node& node = nodes_[static_cast<size_t>(ni)];
      double t0 = tmin, t1 = best;
      if (!node.box.ray_overlap(o, inv_d, t0, t1)) continue;
      if (node.count > 0) {
        for (int i = node.first; i < node.first + node.count; ++i) {
          const int tri = order_[static_cast<size_t>(i)];
          const Triangle& f = triangles_[static_cast<size_t>(tri)];
          double th;
          if (ray_triangle(o, d, vertices_[static_cast<size_t>(f[0])], vertices_[static_cast<size_t>(f[1])],
                           vertices_[static_cast<size_t>(f[2])], th) &&
              th >= tmin && th <= best && (best_tri < 0 || th < best)) {
            best = th;
            best_tri = tri;
          }
        }
        continue;
      }
      // Nearer child on top of the stack.
      const int left = ni + 1, right = node.right;
      double la = tmin, lb = best, ra = tmin, rb = best;
      const bool hit_left = nodes_[static_cast<size_t>(left)].box.ray_overlap(o, inv_d, la, lb);
      const bool hit_right = nodes_[static_cast<size_t>(right)].box.ray_overlap(o, inv_d, ra, rb);
      if (hit_left && hit_right) {
        stack[top++] = la <= ra ? right : left;
        stack[top++] = la <= ra ? left : right;
      } else if (hit_left) {
        stack[top++] = left;
      } else if (hit_right) {
        stack[top++] = right;
      }
    }
  }
  if (best_tri < 0) return false;
  t = best;
  normal = face_normals_[static_cast<size_t>(best_tri)];
  if (triangle) *triangle = best_tri;
  return true;
}

void TriangleMesh::nearest_in_group(int group, const V3& p, Nearest& best) const {
  const int root = roots_[static_cast<size_t>(group)];
  if (root < 0) return;
  int stack[kStackSize];
  int top = 0;
  stack[top++] = root;
  while (top > 0) {
    const int ni = stack[--top];
    const Node& node = nodes_[static_cast<size_t>(ni)];
    if (box_distance2(node.box, p) >= best.d2) continue;
    if (node.count > 0) {
      for (int i = node.first; i < node.first + node.count; ++i) {
        const int tri = order_[static_cast<size_t>(i)];
        const Triangle& f = triangles_[static_cast<size_t>(tri)];
        Feature feature = Feature::face;
        const V3 q = closest_on_triangle(p, vertices_[static_cast<size_t>(f[0])], vertices_[static_cast<size_t>(f[1])],
                                         vertices_[static_cast<size_t>(f[2])], feature);
        const double d2 = (p - q).squaredNorm();
        if (d2 < best.d2) {
          best.d2 = d2;
          best.triangle = tri;
          best.feature = feature;
          best.point = q;
        }
      }
      continue;
    }
    const int left = ni + 1, right = node.right;
    const double dl = box_distance2(nodes_[static_cast<size_t>(left)].box, p);
    const double dr = box_distance2(nodes_[static_cast<size_t>(right)].box, p);
    const int near = dl <= dr ? left : right, far = dl <= dr ? right : left;
    if (std::max(dl, dr) < best.d2) stack[top++] = far;
    if (std::min(dl, dr) < best.d2) stack[top++] = near;
  }
}

// +1 outside, -1 inside, by the pseudo-normal of the nearest feature.
double TriangleMesh::sign_of(const V3& p, const Nearest& n) const {
  const size_t t = static_cast<size_t>(n.triangle);
  V3 pseudo = face_normals_[t];
  switch (n.feature) {
    case Feature::face:
      break;
    case Feature::corner0:
      pseudo = corner_normals_[t][0];
      break;
    case Feature::corner1:
      pseudo = corner_normals_[t][1];
      break;
    case Feature::corner2:
      pseudo = corner_normals_[t][2];
      break;
    case Feature::edge01:
      pseudo = edge_normals_[t][0];
      break;
    case Feature::edge12:
      pseudo = edge_normals_[t][1];
      break;
    case Feature::edge20:
      pseudo = edge_normals_[t][2];
      break;
  }
  return (p - n.point).dot(pseudo) < 0.0 ? -1.0 : 1.0;
}

double TriangleMesh::distance(const V3& p) const {
  Nearest best;
  for (size_t g = 0; g < roots_.size(); ++g) nearest_in_group(static_cast<int>(g), p, best);
  return std::sqrt(best.d2);
}

double TriangleMesh::signed_distance(const V3& p) const {
  double result = kInf;
  for (size_t g = 0; g < roots_.size(); ++g) {
    const int root = roots_[g];
    if (root < 0) continue;
    // Outside a group's box its signed distance is at least the distance to the box.
    const double box_d2 = box_distance2(nodes_[static_cast<size_t>(root)].box, p);
    if (box_d2 > 0.0 && result <= std::sqrt(box_d2)) continue;
    Nearest n;
    nearest_in_group(static_cast<int>(g), p, n);
    if (n.triangle >= 0) result = std::min(result, sign_of(p, n) * std::sqrt(n.d2));
  }
  return result;
}

// ---------------------------------------------------------------------------- OBJ reader

namespace {

void split_words(std::string_view line, std::vector<std::string_view>& words) {
  words.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() &&
           (line[i] == ' ' || line[i] == '\t' || line[i] == '\r' || line[i] == '\f' || line[i] == '\v'))
      ++i;
    const size_t start = i;
    while (i < line.size() &&
           !(line[i] == ' ' || line[i] == '\t' || line[i] == '\r' || line[i] == '\f' || line[i] == '\v'))
      ++i;
    if (i > start) words.push_back(line.substr(start, i - start));
  }
}

[[nodiscard]] bool parse_double(std::string_view s, double& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return r.ec == std::errc() && r.ptr == s.data() + s.size();
}

[[nodiscard]] bool parse_long(std::string_view s, long long& out) {
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  const auto r = std::from_chars(s.data(), s.data() + s.size(), out);
  return !s.empty() && r.ec == std::errc() && r.ptr == s.data() + s.size();
}

// A face corner "v", "v/t", "v//n" or "v/t/n": the vertex index and a check of the others.
[[nodiscard]] bool parse_corner(std::string_view word, long long& vertex) {
  const size_t slash = word.find('/');
  if (!parse_long(word.substr(0, slash), vertex)) return false;
  if (slash == std::string_view::npos) return true;
  const std::string_view rest = word.substr(slash + 1);
  const size_t slash2 = rest.find('/');
  long long ignored;
  const std::string_view tex = rest.substr(0, slash2);
  if (!tex.empty() && !parse_long(tex, ignored)) return false;
  if (slash2 == std::string_view::npos) return !tex.empty();
  return parse_long(rest.substr(slash2 + 1), ignored);
}

std::string quoted(std::string_view s) {
  std::string r = "'";
  r.append(s.substr(0, 40));
  if (s.size() > 40) r += "...";
  return r + "'";
}

}  // namespace

bool load_obj_text(const std::string& text, const std::string& name, TriangleMesh& out, std::string& error) {
  std::vector<V3> vertices;
  std::vector<TriangleMesh::Triangle> triangles;
  std::vector<int> groups;
  std::vector<std::string> group_names;
  std::unordered_map<std::string, int> group_ids;
  int group = -1;  // faces before any o / g go to an unnamed group
  std::vector<std::string_view> words;
  std::vector<int> polygon;
  size_t line_no = 0;
  size_t pos = 0;
  auto fail = [&](const std::string& problem) {
    error = name + ":" + std::to_string(line_no) + ": " + problem;
    return false;
  };
  while (pos < text.size()) {
    size_t eol = text.find('\n', pos);
    if (eol == std::string::npos) eol = text.size();
    std::string_view line(text.data() + pos, eol - pos);
    pos = eol + 1;
    ++line_no;
    const size_t hash = line.find('#');
    if (hash != std::string_view::npos) line = line.substr(0, hash);
    split_words(line, words);
    if (words.empty()) continue;
    const std::string_view key = words[0];
    if (key == "v") {
      if (words.size() < 4) return fail("a vertex needs 3 coordinates");
      if (vertices.size() >= kObjMaxVertices) return fail("more than " + std::to_string(kObjMaxVertices) + " vertices");
      V3 v;
      for (int i = 0; i < 3; ++i) {
        const std::string_view w = words[static_cast<size_t>(i) + 1];
        if (!parse_double(w, v[i])) return fail("malformed number " + quoted(w));
        if (!std::isfinite(v[i])) return fail("non-finite number " + quoted(w));
      }
      vertices.push_back(v);
    } else if (key == "f") {
      if (words.size() < 4) return fail("a face needs at least 3 vertices");
      polygon.clear();
      for (size_t i = 1; i < words.size(); ++i) {
        long long idx;
        if (!parse_corner(words[i], idx)) return fail("malformed face vertex " + quoted(words[i]));
        const long long n = static_cast<long long>(vertices.size());
        if (idx == 0) return fail("face index 0 (indices start at 1)");
        const long long resolved = idx > 0 ? idx - 1 : n + idx;
        if (resolved < 0 || resolved >= n)
          return fail("face index " + std::to_string(idx) + " out of range (" + std::to_string(n) +
                      " vertices so far)");
        polygon.push_back(static_cast<int>(resolved));
      }
      if (group < 0) {
        group = static_cast<int>(group_names.size());
        group_names.emplace_back();
        group_ids.emplace("", group);
      }
      for (size_t k = 1; k + 1 < polygon.size(); ++k) {
        triangles.push_back({polygon[0], polygon[k], polygon[k + 1]});
        groups.push_back(group);
      }
    } else if (key == "o" || key == "g") {
      std::string group_name;
      for (size_t i = 1; i < words.size(); ++i) {
        if (i > 1) group_name += ' ';
        group_name.append(words[i]);
      }
      const auto it = group_ids.emplace(group_name, static_cast<int>(group_names.size()));
      if (it.second) group_names.push_back(group_name);
      group = it.first->second;
    }
  }
  if (triangles.empty()) return fail("no faces");
  // Groups without faces are dropped.
  std::vector<int> remap(group_names.size(), -1);
  std::vector<std::string> used_names;
  for (int& g : groups) {
    int& r = remap[static_cast<size_t>(g)];
    if (r < 0) {
      r = static_cast<int>(used_names.size());
      used_names.push_back(group_names[static_cast<size_t>(g)]);
    }
    g = r;
  }
  out = TriangleMesh(std::move(vertices), std::move(triangles), std::move(groups), std::move(used_names), name);
  return true;
}

bool load_obj(const std::string& path, TriangleMesh& out, std::string& error) {
  std::ifstream f(path, std::ios::binary);
  if (!f) {
    error = path + ": cannot open the mesh file";
    return false;
  }
  std::ostringstream ss;
  ss << f.rdbuf();
  if (f.bad()) {
    error = path + ": read error";
    return false;
  }
  return load_obj_text(ss.str(), path, out, error);
}

std::shared_ptr<const TriangleMesh> load_obj_cached(const std::string& path, std::string& error) {
  static std::mutex mutex;
  static std::map<std::string, std::shared_ptr<const TriangleMesh>> cache;
  const std::lock_guard<std::mutex> lock(mutex);
  const auto it = cache.find(path);
  if (it != cache.end()) return it->second;
  auto mesh = std::make_shared<TriangleMesh>();
  if (!load_obj(path, *mesh, error)) return nullptr;
  cache.emplace(path, mesh);
  return mesh;
}

// ---------------------------------------------------------------------------- resting faces

namespace {

// Convex hull by quickhull: triangles with outward normals over the input points.
class ConvexHull {
 public:
  struct Face {
    std::array<int, 3> v;
    V3 n;        // outward unit normal
    double off;  // n . x = off on the plane
    bool alive = true;
    std::vector<int> outside;  // points above this face, not yet on the hull
  };

  // False when the points are (nearly) flat or the construction failed numerically.
  [[nodiscard]] bool build(const std::vector<V3>& pts) {
    pts_ = &pts;
    Aabb box;
    for (const V3& p : pts) box.extend(p);
    if (pts.size() < 4) return false;
    eps_ = 1e-9 * std::max(box.size().norm(), 1e-12);
    // Initial tetrahedron from extreme points.
    int i0 = 0;
    for (size_t i = 0; i < pts.size(); ++i)
      if (pts[i].x() < pts[static_cast<size_t>(i0)].x()) i0 = static_cast<int>(i);
    const int i1 = farthest([&](const V3& p) { return (p - P(i0)).norm(); });
    const int i2 = farthest([&](const V3& p) { return (p - P(i0)).cross(P(i1) - P(i0)).norm(); });
    const V3 n012 = (P(i1) - P(i0)).cross(P(i2) - P(i0));
    if (n012.norm() <= eps_ * (P(i1) - P(i0)).norm()) return false;
    const int i3 = farthest([&](const V3& p) { return std::abs((p - P(i0)).dot(n012.normalized())); });
    const double h = (P(i3) - P(i0)).dot(n012.normalized());
    if (std::abs(h) <= eps_) return false;
    const V3 inner = 0.25 * (P(i0) + P(i1) + P(i2) + P(i3));
    const int tet[4][3] = {{i0, i1, i2}, {i0, i1, i3}, {i0, i2, i3}, {i1, i2, i3}};
    std::vector<int> fresh;
    for (const auto& t : tet) {
      int a = t[0], b = t[1], c = t[2];
      if ((P(b) - P(a)).cross(P(c) - P(a)).dot(inner - P(a)) > 0.0) std::swap(b, c);
      fresh.push_back(add_face(a, b, c));
    }
    std::vector<int> all(pts.size());
    std::iota(all.begin(), all.end(), 0);
    assign(all, fresh);
    // Grow: the farthest outside point of some face joins the hull each round.
    std::vector<int> work = fresh;
    while (!work.empty()) {
      const int fi = work.back();
      work.pop_back();
      if (!faces_[static_cast<size_t>(fi)].alive || faces_[static_cast<size_t>(fi)].outside.empty()) continue;
      int apex = -1;
      double far = -kInf;
      for (int q : faces_[static_cast<size_t>(fi)].outside) {
        const double d = height(fi, P(q));
        if (d > far) {
          far = d;
          apex = q;
        }
      }
      // Faces seen from the apex, found by walking across edges from fi.
      std::vector<int> visible{fi};
      std::vector<char> seen(faces_.size(), 0);
      seen[static_cast<size_t>(fi)] = 1;
      for (size_t k = 0; k < visible.size(); ++k) {
        const Face& f = faces_[static_cast<size_t>(visible[k])];
        for (int e = 0; e < 3; ++e) {
          const int nb = neighbour(f.v[static_cast<size_t>(e)], f.v[static_cast<size_t>((e + 1) % 3)]);
          if (nb < 0) return false;
          if (seen[static_cast<size_t>(nb)]) continue;
          seen[static_cast<size_t>(nb)] = 1;
          if (height(nb, P(apex)) > eps_) visible.push_back(nb);
        }
      }
      std::vector<char> is_visible(faces_.size(), 0);
      for (int v : visible) is_visible[static_cast<size_t>(v)] = 1;
      std::vector<std::array<int, 2>> horizon;
      std::vector<int> orphans;
      for (int v : visible) {
        Face& f = faces_[static_cast<size_t>(v)];
        for (int e = 0; e < 3; ++e) {
          const int a = f.v[static_cast<size_t>(e)], b = f.v[static_cast<size_t>((e + 1) % 3)];
          if (!is_visible[static_cast<size_t>(neighbour(a, b))]) horizon.push_back({a, b});
        }
        for (int q : f.outside)
          if (q != apex) orphans.push_back(q);
        f.outside.clear();
      }
      for (int v : visible) remove_face(v);
      fresh.clear();
      for (const auto& e : horizon) fresh.push_back(add_face(e[0], e[1], apex));
      assign(orphans, fresh);
      work.insert(work.end(), fresh.begin(), fresh.end());
    }
    // A closed hull has every edge twice, once each way.
    for (const Face& f : faces_) {
      if (!f.alive) continue;
      for (int e = 0; e < 3; ++e)
        if (neighbour(f.v[static_cast<size_t>(e)], f.v[static_cast<size_t>((e + 1) % 3)]) < 0) return false;
    }
    return true;
  }

  const std::vector<Face>& faces() const { return faces_; }
  int neighbour(int a, int b) const {
    const auto it = edges_.find(key(b, a));
    return it == edges_.end() ? -1 : it->second;
  }

 private:
  const V3& P(int i) const { return (*pts_)[static_cast<size_t>(i)]; }
  static uint64_t key(int a, int b) {
    return (static_cast<uint64_t>(static_cast<uint32_t>(a)) << 32) | static_cast<uint32_t>(b);
  }
  double height(int f, const V3& p) const {
    const Face& face = faces_[static_cast<size_t>(f)];
    return face.n.dot(p) - face.off;
  }
  template <class F>
  int farthest(F measure) const {
    int best = 0;
    double best_value = -kInf;
    for (size_t i = 0; i < pts_->size(); ++i) {
      const double m = measure((*pts_)[i]);
      if (m > best_value) {
        best_value = m;
        best = static_cast<int>(i);
      }
    }
    return best;
  }
  int add_face(int a, int b, int c) {
    Face f;
    f.v = {a, b, c};
    const V3 n = (P(b) - P(a)).cross(P(c) - P(a));
    const double len = n.norm();
    f.n = len > 0.0 ? V3(n / len) : V3(V3::Zero());
    f.off = f.n.dot(P(a));
    const int index = static_cast<int>(faces_.size());
    faces_.push_back(std::move(f));
    for (int e = 0; e < 3; ++e) {
      const std::array<int, 3>& v = faces_.back().v;
      edges_[key(v[static_cast<size_t>(e)], v[static_cast<size_t>((e + 1) % 3)])] = index;
    }
    return index;
  }
  void remove_face(int f) {
    Face& face = faces_[static_cast<size_t>(f)];
    face.alive = false;
    for (int e = 0; e < 3; ++e) {
      const auto it = edges_.find(key(face.v[static_cast<size_t>(e)], face.v[static_cast<size_t>((e + 1) % 3)]));
      if (it != edges_.end() && it->second == f) edges_.erase(it);
    }
  }
  void assign(const std::vector<int>& points, const std::vector<int>& candidates) {
    for (int q : points) {
      for (int f : candidates) {
        if (height(f, P(q)) > eps_) {
          faces_[static_cast<size_t>(f)].outside.push_back(q);
          break;
        }
      }
    }
  }

  const std::vector<V3>* pts_ = nullptr;
  double eps_ = 0.0;
  std::vector<Face> faces_;
  std::unordered_map<uint64_t, int> edges_;  // directed edge (a, b) -> face holding it
};

// Is p (on the plane of triangle abc) inside it, up to tol (scaled with the triangle)?
bool in_triangle(const V3& p, const V3& a, const V3& b, const V3& c, const V3& n) {
  const double tol = -1e-12;
  return (b - a).cross(p - a).dot(n) >= tol && (c - b).cross(p - b).dot(n) >= tol && (a - c).cross(p - c).dot(n) >= tol;
}

}  // namespace

std::vector<RestingFace> resting_faces(const TriangleMesh& mesh) {
  std::vector<RestingFace> result;
  ConvexHull hull;
  if (!hull.build(mesh.vertices())) return result;
  const auto& faces = hull.faces();
  const auto& pts = mesh.vertices();
  // Coplanar neighbours form one face (union-find across shared edges).
  std::vector<int> parent(faces.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int i) {
    while (parent[static_cast<size_t>(i)] != i)
      i = parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    return i;
  };
  for (size_t i = 0; i < faces.size(); ++i) {
    if (!faces[i].alive) continue;
    for (int e = 0; e < 3; ++e) {
      const int nb = hull.neighbour(faces[i].v[static_cast<size_t>(e)], faces[i].v[static_cast<size_t>((e + 1) % 3)]);
      if (faces[i].n.dot(faces[static_cast<size_t>(nb)].n) > 1.0 - 1e-10)
        parent[static_cast<size_t>(root(static_cast<int>(i)))] = root(nb);
    }
  }
  struct Merged {
    V3 normal_sum = V3::Zero();
    double area = 0.0;
    bool stable = false;
  };
  std::map<int, Merged> merged;
  const V3& c = mesh.centroid();
  for (size_t i = 0; i < faces.size(); ++i) {
    const auto& f = faces[i];
    if (!f.alive) continue;
    const V3 &a = pts[static_cast<size_t>(f.v[0])], &b = pts[static_cast<size_t>(f.v[1])],
             &d = pts[static_cast<size_t>(f.v[2])];
    const double area = 0.5 * (b - a).cross(d - a).norm();
    Merged& m = merged[root(static_cast<int>(i))];
    m.normal_sum += area * f.n;
    m.area += area;
    const V3 foot = c - (f.n.dot(c) - f.off) * f.n;
    if (in_triangle(foot, a, b, d, f.n)) m.stable = true;
  }
  for (const auto& [id, m] : merged) {
    if (!m.stable || m.area <= 0.0) continue;
    RestingFace r;
    r.down = m.normal_sum.normalized();
    r.area = m.area;
    result.push_back(r);
  }
  return result;
}

}  // namespace fg::sim
