#include "fg/core/near_list.hpp"

#include <algorithm>

namespace fg {

NearGrid NearGrid::around(const Vec3& centre, float r, uint32_t cell_bits) {
  NearGrid g{centre - Vec3::Constant(r), {}, {(cell_bits + 2) / 3, (cell_bits + 1) / 3, cell_bits / 3}};
  for (int a = 0; a < 3; ++a) g.inv_cell[a] = static_cast<float>(1u << g.bits[a]) / (2.f * r);
  return g;
}

void sort_by_cell(uint32_t* a, uint32_t n, uint32_t index_bits, uint32_t cell_bits, uint32_t* next, uint32_t* end) {
  const uint32_t cells = 1u << cell_bits;
  for (uint32_t b = 0; b < cells; ++b) end[b] = 0;
  for (uint32_t i = 0; i < n; ++i) ++end[a[i] >> index_bits];
  uint32_t sum = 0;
  for (uint32_t b = 0; b < cells; ++b) {
    next[b] = sum;
    sum += end[b];
    end[b] = sum;
  }
  // Cell by cell, the entry at the cell's next free place is carried to its own cell's
  // next free place, and the one it displaces onward, until one belongs here: every
  // step settles one entry for good, so all steps together are at most n.
  for (uint32_t b = 0; b < cells; ++b) {
    while (next[b] < end[b]) {
      uint32_t e = a[next[b]];
      for (uint32_t t = e >> index_bits; t != b; t = e >> index_bits) {
        const uint32_t displaced = a[next[t]];
        a[next[t]++] = e;
        e = displaced;
      }
      a[next[b]++] = e;
    }
  }
}

bool near_list_hits(const uint32_t* entries, uint32_t n, uint32_t index_bits, const NearGrid& g, const Vec3* points,
                    const uint8_t* state, const Vec3& pos, const Vec3 axes[3], const FrameBox& b, float tol) {
  const float x0 = b.x0 + tol, x1 = b.x1 - tol, y0 = b.y0 + tol, y1 = b.y1 - tol, z0 = b.z0 + tol, z1 = b.z1 - tol;
  if (!(x0 < x1 && y0 < y1 && z0 < z1)) return false;  // shrunk to nothing
  const Vec3 centre = pos + axes[0] * (0.5f * (x0 + x1)) + axes[1] * (0.5f * (y0 + y1)) + axes[2] * (0.5f * (z0 + z1));
  const Vec3 half = axes[0].cwiseAbs() * (0.5f * (x1 - x0)) + axes[1].cwiseAbs() * (0.5f * (y1 - y0)) +
                    axes[2].cwiseAbs() * (0.5f * (z1 - z0));
  // Padded by 0.1 mm, far below a cell, for the rounding of the corners' sums.
  const Vec3 lo = centre - half - Vec3::Constant(1e-4f), hi = centre + half + Vec3::Constant(1e-4f);
  const uint32_t cx0 = g.axis(lo.x(), 0), cx1 = g.axis(hi.x(), 0);
  const uint32_t cy0 = g.axis(lo.y(), 1), cy1 = g.axis(hi.y(), 1);
  const uint32_t cz0 = g.axis(lo.z(), 2), cz1 = g.axis(hi.z(), 2);
  const uint32_t mask = (1u << index_bits) - 1u;
  const uint32_t* const end = entries + n;
  // Columns are visited in increasing cell order, so each search starts where the last
  // column's scan stopped.
  const uint32_t* from = entries;
  for (uint32_t cx = cx0; cx <= cx1; ++cx) {
    for (uint32_t cy = cy0; cy <= cy1; ++cy) {
      const uint64_t first = static_cast<uint64_t>(g.cell(cx, cy, cz0)) << index_bits;
      const uint64_t last = static_cast<uint64_t>(g.cell(cx, cy, cz1) + 1u) << index_bits;
      const uint32_t* e = std::lower_bound(from, end, first, [](uint32_t v, uint64_t key) { return v < key; });
      for (; e < end && *e < last; ++e) {
        const uint32_t i = *e & mask;
        if (state[i] == 0) continue;
        const Vec3 d = points[i] - pos;
        if (b.holds(axes[0].dot(d), axes[1].dot(d), axes[2].dot(d), tol)) return true;
      }
      from = e;
    }
  }
  return false;
}

}  // namespace fg
