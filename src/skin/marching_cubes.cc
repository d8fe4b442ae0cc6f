#include "skin/marching_cubes.h"

#include <cmath>
#include <limits>
#include <memory>

#include "common/check.h"

namespace viscera::skin {
namespace {

Vec3 CornerOffset(int c) { return Vec3(c & 1, (c >> 1) & 1, (c >> 2) & 1); }

// The two axes other than `axis`, in increasing order.
std::array<int, 2> OtherAxes(int axis) {
  return axis == 0   ? std::array<int, 2>{1, 2}
         : axis == 1 ? std::array<int, 2>{0, 2}
                     : std::array<int, 2>{0, 1};
}

int EdgeBetween(int c0, int c1) {
  const int diff = c0 ^ c1;
  const int axis = diff == 1 ? 0 : diff == 2 ? 1 : 2;
  const int low = std::min(c0, c1);
  const std::array<int, 2> o = OtherAxes(axis);
  return 4 * axis + ((low >> o[0]) & 1) + 2 * ((low >> o[1]) & 1);
}

// Grid point key: 21 bits per coordinate, offset so that negative indices fit.
uint64_t Key(int i, int j, int k) {
  constexpr int64_t kOffset = int64_t{1} << 20;
  constexpr uint64_t kMask = (uint64_t{1} << 21) - 1;
  return (static_cast<uint64_t>(i + kOffset) & kMask) |
         ((static_cast<uint64_t>(j + kOffset) & kMask) << 21) |
         ((static_cast<uint64_t>(k + kOffset) & kMask) << 42);
}

// True if the two cube edges lie on a common face (their corners agree on some bit that is
// not the direction of either).
bool ShareFace(int e0, int e1) {
  const std::array<int, 2> a = MarchingCubesTable::EdgeCorners(e0),
                           b = MarchingCubesTable::EdgeCorners(e1);
  for (int axis = 0; axis < 3; ++axis) {
    const int bit = 1 << axis;
    const bool fixed_a = (a[0] & bit) == (a[1] & bit), fixed_b = (b[0] & bit) == (b[1] & bit);
    if (fixed_a && fixed_b && (a[0] & bit) == (b[0] & bit)) return true;
  }
  return false;
}

}  // namespace

std::array<int, 2> MarchingCubesTable::EdgeCorners(int edge) {
  const int axis = edge / 4, m = edge % 4;
  const std::array<int, 2> o = OtherAxes(axis);
  const int c0 = ((m & 1) << o[0]) | (((m >> 1) & 1) << o[1]);
  return {c0, c0 | (1 << axis)};
}

MarchingCubesTable::MarchingCubesTable() {
  for (int config = 0; config < 256; ++config) {
    auto inside = [config](int c) { return ((config >> c) & 1) != 0; };
    std::array<int, 12> next;
    next.fill(-1);
    auto mid = [](int edge) {
      const std::array<int, 2> c = EdgeCorners(edge);
      return Vec3(0.5 * (CornerOffset(c[0]) + CornerOffset(c[1])));
    };
    // Orient a face segment so that walking it, n_face x g points along it (g: towards the
    // inside); then the loops run counter-clockwise seen from outside the surface.
    auto link = [&](int e0, int e1, const Vec3& n_face, const Vec3& g) {
      const Vec3 along = mid(e1) - mid(e0);
      if (along.dot(n_face.cross(g)) < 0.0) std::swap(e0, e1);
      VISCERA_DEMAND(next[e0] == -1);
      next[e0] = e1;
    };
    for (int axis = 0; axis < 3; ++axis) {
      const std::array<int, 2> o = OtherAxes(axis);
      for (int side = 0; side < 2; ++side) {
        // the face's corners in cyclic order
        const int base = side << axis;
        const std::array<int, 4> q = {base, base | (1 << o[0]), base | (1 << o[0]) | (1 << o[1]),
                                      base | (1 << o[1])};
        const Vec3 n_face = (2.0 * side - 1.0) * Vec3::Unit(axis);
        std::array<int, 4> crossing;
        int count = 0;
        Vec3 in_sum = Vec3::Zero(), out_sum = Vec3::Zero();
        int in_count = 0;
        for (int k = 0; k < 4; ++k) {
          if (inside(q[k]) != inside(q[(k + 1) % 4]))
            crossing[count++] = EdgeBetween(q[k], q[(k + 1) % 4]);
          if (inside(q[k])) {
            in_sum += CornerOffset(q[k]);
            ++in_count;
          } else {
            out_sum += CornerOffset(q[k]);
          }
        }
        if (count == 2) {
          link(crossing[0], crossing[1], n_face, in_sum / in_count - out_sum / (4 - in_count));
        } else if (count == 4) {
          // ambiguous face: cut off each inside corner separately
          for (int k = 0; k < 4; ++k) {
            if (!inside(q[k])) continue;
            const int e0 = EdgeBetween(q[(k + 3) % 4], q[k]),
                      e1 = EdgeBetween(q[k], q[(k + 1) % 4]);
            link(e0, e1, n_face, CornerOffset(q[k]) - 0.5 * (mid(e0) + mid(e1)));
          }
        }
      }
    }
    // loops -> triangle fans
    std::array<int8_t, 37>& out = cases_[config];
    out.fill(-1);
    int written = 0;
    std::array<bool, 12> used{};
    for (int start = 0; start < 12; ++start) {
      if (next[start] == -1 || used[start]) continue;
      std::array<int, 12> loop;
      int length = 0;
      for (int e = start; !used[e]; e = next[e]) {
        VISCERA_DEMAND(next[e] != -1);
        used[e] = true;
        loop[length++] = e;
      }
      // Fan from an apex whose diagonals never join two vertices of one cube face: the cell
      // across that face could use the same pair of vertices, and the edge would then be
      // shared by more than two triangles.
      int apex = -1;
      for (int a = 0; a < length && apex < 0; ++a) {
        bool ok = true;
        for (int t = 2; t + 1 < length && ok; ++t) ok = !ShareFace(loop[a], loop[(a + t) % length]);
        if (ok) apex = a;
      }
      VISCERA_DEMAND(apex >= 0);
      for (int t = 1; t + 1 < length; ++t) {
        out[written++] = static_cast<int8_t>(loop[apex]);
        out[written++] = static_cast<int8_t>(loop[(apex + t) % length]);
        out[written++] = static_cast<int8_t>(loop[(apex + t + 1) % length]);
      }
    }
    VISCERA_DEMAND(written <= 36);
  }
}

NarrowBandPolygonizer::Brick* NarrowBandPolygonizer::BrickAt(int bi, int bj, int bk) {
  const uint64_t key = Key(bi, bj, bk);
  if (key == last_key_) return last_brick_;
  int* slot = brick_index_.Find(key);
  int index;
  if (slot != nullptr) {
    index = *slot;
  } else {
    // take the next pooled brick (allocated once, reused every frame) and reset it
    index = bricks_used_++;
    if (index == static_cast<int>(bricks_.size())) bricks_.push_back(std::make_unique<Brick>());
    Brick& b = *bricks_[index];
    // (vertex[] is reset point by point when the point's value is first computed)
    std::fill(std::begin(b.value), std::end(b.value), std::numeric_limits<double>::quiet_NaN());
    std::fill(std::begin(b.visited), std::end(b.visited), 0);
    brick_index_.Insert(key, index);
  }
  last_key_ = key;
  last_brick_ = bricks_[index].get();
  return last_brick_;
}

void NarrowBandPolygonizer::Run(const ScalarField& field, double iso, double cell,
                                const std::vector<Vec3>& seeds, int max_cells, Mesh* out) {
  VISCERA_DEMAND(cell > 0.0);
  brick_index_.Clear();
  bricks_used_ = 0;
  last_key_ = FlatHashMap<int>::kEmpty;
  last_brick_ = nullptr;
  queue_.clear();
  out->Clear();
  cells_visited_ = 0;
  evaluations_ = 0;
  hit_budget_ = false;
  // grid point (i, j, k) lives in brick (i, j, k) >> kBrickShift (arithmetic shift = floor)
  auto local = [](int i, int j, int k) {
    return (i & kBrickMask) | ((j & kBrickMask) << kBrickShift) |
           ((k & kBrickMask) << (2 * kBrickShift));
  };
  auto brick = [this](int i, int j, int k) {
    return BrickAt(i >> kBrickShift, j >> kBrickShift, k >> kBrickShift);
  };
  // marks cell (i, j, k), named by its lowest corner, visited; true if it was not
  auto visit = [&](int i, int j, int k) {
    uint8_t& flag = brick(i, j, k)->visited[local(i, j, k)];
    if (flag) return false;
    flag = 1;
    return true;
  };
  const double inv = 1.0 / cell;
  for (const Vec3& s : seeds) {
    const int i = static_cast<int>(std::floor(s.x() * inv)),
              j = static_cast<int>(std::floor(s.y() * inv)),
              k = static_cast<int>(std::floor(s.z() * inv));
    if (visit(i, j, k)) queue_.push_back({i, j, k});
  }
  while (!queue_.empty()) {
    if (cells_visited_ >= max_cells) {
      hit_budget_ = true;
      break;
    }
    const std::array<int, 3> c = queue_.back();
    queue_.pop_back();
    ++cells_visited_;
    // corner values, evaluated once per grid point and frame; the corners' bricks and slots
    // (one brick for most cells: fast path without look-ups)
    Brick* corner_brick[8];
    int corner_slot[8];
    const int li = c[0] & kBrickMask, lj = c[1] & kBrickMask, lk = c[2] & kBrickMask;
    if (li < kBrickMask && lj < kBrickMask && lk < kBrickMask) {
      Brick* b = brick(c[0], c[1], c[2]);
      const int base = local(c[0], c[1], c[2]);
      for (int n = 0; n < 8; ++n) {
        corner_brick[n] = b;
        corner_slot[n] = base + (n & 1) + (((n >> 1) & 1) << kBrickShift) +
                         (((n >> 2) & 1) << (2 * kBrickShift));
      }
    } else {
      for (int n = 0; n < 8; ++n) {
        const int i = c[0] + (n & 1), j = c[1] + ((n >> 1) & 1), k = c[2] + ((n >> 2) & 1);
        corner_brick[n] = brick(i, j, k);
        corner_slot[n] = local(i, j, k);
      }
    }
    double v[8];
    int config = 0;
    for (int n = 0; n < 8; ++n) {
      Brick* b = corner_brick[n];
      const int at = corner_slot[n];
      double& value = b->value[at];
      if (std::isnan(value)) {
        const int i = c[0] + (n & 1), j = c[1] + ((n >> 1) & 1), k = c[2] + ((n >> 2) & 1);
        value = field.Value(Vec3(i * cell, j * cell, k * cell));
        b->vertex[at][0] = b->vertex[at][1] = b->vertex[at][2] = -1;
        ++evaluations_;
      }
      v[n] = value;
      if (v[n] > iso) config |= 1 << n;
    }
    if (config == 0 || config == 255) continue;  // the surface does not cross this cell

    // triangles, with one vertex per crossed grid edge shared by the four cells around it
    const std::array<int8_t, 37>& tris = table_.Case(config);
    int ids[3];
    for (int t = 0; tris[t] >= 0; t += 3) {
      for (int a = 0; a < 3; ++a) {
        const int edge = tris[t + a];
        const std::array<int, 2> ec = MarchingCubesTable::EdgeCorners(edge);
        const int axis = edge / 4;
        int& vertex = corner_brick[ec[0]]->vertex[corner_slot[ec[0]]][axis];
        if (vertex < 0) {
          const int i = c[0] + (ec[0] & 1), j = c[1] + ((ec[0] >> 1) & 1),
                    k = c[2] + ((ec[0] >> 2) & 1);
          const double f0 = v[ec[0]], f1 = v[ec[1]];
          const double s = std::clamp((iso - f0) / (f1 - f0), 0.0, 1.0);
          Vec3 p(i * cell, j * cell, k * cell);
          p[axis] += s * cell;
          vertex = static_cast<int>(out->positions.size());
          out->positions.push_back(p);
        }
        ids[a] = vertex;
      }
      out->triangles.emplace_back(ids[0], ids[1], ids[2]);
    }
    // continue across the faces the surface crosses
    for (int axis = 0; axis < 3; ++axis) {
      const std::array<int, 2> o = OtherAxes(axis);
      for (int side = 0; side < 2; ++side) {
        const int base = side << axis;
        const int f = ((config >> base) & 1) + ((config >> (base | 1 << o[0])) & 1) +
                      ((config >> (base | 1 << o[1])) & 1) +
                      ((config >> (base | 1 << o[0] | 1 << o[1])) & 1);
        if (f == 0 || f == 4) continue;
        std::array<int, 3> n = c;
        n[axis] += 2 * side - 1;
        if (visit(n[0], n[1], n[2])) queue_.push_back(n);
      }
    }
  }
}

}  // namespace viscera::skin
