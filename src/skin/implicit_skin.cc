#include "skin/implicit_skin.h"

#include <algorithm>
#include <cmath>

#include "common/check.h"

namespace viscera::skin {
namespace {

uint64_t CellKey(const Vec3& p, double inv_cell) {
  constexpr int64_t kOffset = int64_t{1} << 20;
  constexpr uint64_t kMask = (uint64_t{1} << 21) - 1;
  auto c = [&](double x) {
    return static_cast<uint64_t>(static_cast<int64_t>(std::floor(x * inv_cell)) + kOffset) & kMask;
  };
  return c(p.x()) | (c(p.y()) << 21) | (c(p.z()) << 42);
}

}  // namespace

PointSkeletonField::PointSkeletonField(double support, bool blending_graph, double blend_gap,
                                       double block)
    : support_(support),
      support2_(support * support),
      blend_gap_(blend_gap),
      block_(block),
      blending_graph_(blending_graph) {}

void PointSkeletonField::Reset(const std::vector<Vec3>& points, double spacing, double weight) {
  points_ = &points;
  weight_ = weight;
  max_index_gap_ = std::max(1, static_cast<int>(std::floor(blend_gap_ / spacing)));
  const double inv = 1.0 / GridCell();
  sorted_.resize(points.size());
  for (size_t i = 0; i < points.size(); ++i)
    sorted_[i] = {CellKey(points[i], inv), static_cast<int>(i)};
  std::sort(sorted_.begin(), sorted_.end());
  cells_.Clear();
  for (size_t b = 0; b < sorted_.size();) {
    size_t e = b;
    while (e < sorted_.size() && sorted_[e].first == sorted_[b].first) ++e;
    cells_.Insert(sorted_[b].first, {static_cast<int>(b), static_cast<int>(e)});
    b = e;
  }
  blocks_.Clear();
  pool_.clear();
  pool_x_.clear();
  pool_y_.clear();
  pool_z_.clear();
}

std::pair<int, int> PointSkeletonField::Candidates(const Vec3& p) const {
  // The primitives within support + half a block diagonal of a block's centre are the only
  // ones that can reach a point of the block. Computed once per block and frame, sorted by
  // index (curve order) for the blending graph.
  const double block = block_;
  const uint64_t key = CellKey(p, 1.0 / block);
  if (const std::pair<int, int>* hit = blocks_.Find(key)) return *hit;
  const Vec3 centre((std::floor(p.x() / block) + 0.5) * block,
                    (std::floor(p.y() / block) + 0.5) * block,
                    (std::floor(p.z() / block) + 0.5) * block);
  const double reach = support_ + 0.5 * std::sqrt(3.0) * block;
  const double grid = GridCell();
  const double inv = 1.0 / grid;
  const int begin = static_cast<int>(pool_.size());
  const int i0 = static_cast<int>(std::floor((centre.x() - reach) * inv)),
            i1 = static_cast<int>(std::floor((centre.x() + reach) * inv));
  const int j0 = static_cast<int>(std::floor((centre.y() - reach) * inv)),
            j1 = static_cast<int>(std::floor((centre.y() + reach) * inv));
  const int k0 = static_cast<int>(std::floor((centre.z() - reach) * inv)),
            k1 = static_cast<int>(std::floor((centre.z() + reach) * inv));
  for (int k = k0; k <= k1; ++k) {
    for (int j = j0; j <= j1; ++j) {
      for (int i = i0; i <= i1; ++i) {
        const Vec3 cell_centre((i + 0.5) * grid, (j + 0.5) * grid, (k + 0.5) * grid);
        const std::pair<int, int>* range = cells_.Find(CellKey(cell_centre, inv));
        if (range == nullptr) continue;
        for (int s = range->first; s < range->second; ++s) {
          const int index = sorted_[s].second;
          if (((*points_)[index] - centre).squaredNorm() < reach * reach) pool_.push_back(index);
        }
      }
    }
  }
  std::sort(pool_.begin() + begin, pool_.end());
  // copy the candidates' coordinates next to each other (structure of arrays) for Value
  for (size_t c = begin; c < pool_.size(); ++c) {
    const Vec3& x = (*points_)[pool_[c]];
    pool_x_.push_back(x.x());
    pool_y_.push_back(x.y());
    pool_z_.push_back(x.z());
  }
  const std::pair<int, int> range{begin, static_cast<int>(pool_.size())};
  blocks_.Insert(key, range);
  return range;
}

double PointSkeletonField::Value(const Vec3& p) const {
  const auto [begin, end] = Candidates(p);
  const double px = p.x(), py = p.y(), pz = p.z(), inv_rho2 = 1.0 / support2_;
  const double* xs = pool_x_.data();
  const double* ys = pool_y_.data();
  const double* zs = pool_z_.data();
  if (!blending_graph_) {
    // branch-free soft-object kernel: vectorizes
    double sum = 0.0;
    for (int c = begin; c < end; ++c) {
      const double dx = xs[c] - px, dy = ys[c] - py, dz = zs[c] - pz;
      const double a = std::max(0.0, 1.0 - (dx * dx + dy * dy + dz * dz) * inv_rho2);
      sum += a * a * a;
    }
    return weight_ * sum;
  }
  // blending graph: runs of nearby indices blend (sum), runs combine by max (union)
  double best = 0.0, group = 0.0;
  int last = -1;
  for (int c = begin; c < end; ++c) {
    const double dx = xs[c] - px, dy = ys[c] - py, dz = zs[c] - pz;
    const double a = 1.0 - (dx * dx + dy * dy + dz * dz) * inv_rho2;
    if (a <= 0.0) continue;
    const int index = pool_[c];
    if (last >= 0 && index - last > max_index_gap_) {
      best = std::max(best, group);
      group = 0.0;
    }
    group += a * a * a;
    last = index;
  }
  return weight_ * std::max(best, group);
}

ImplicitSkin::ImplicitSkin(double radius, const ImplicitOptions& options)
    : radius_(radius),
      options_(options),
      spacing_(options.spacing_factor * radius),
      iso_(0.0),
      // candidate blocks of one support: measured no slower than half-support blocks even
      // with cells of 0.25 R, and fewer candidate lists to build with cells of 0.5 R
      field_(options.support_factor * radius, options.blending_graph,
             options.blend_arc_factor * radius, options.support_factor * radius) {
  ThrowUnless(radius > 0.0, "skin radius must be > 0, got ", radius);
  ThrowUnless(options.spacing_factor > 0.0 && options.spacing_factor <= 1.0,
              "implicit spacing_factor must be in (0, 1], got ", options.spacing_factor);
  ThrowUnless(options.support_factor > 1.2, "implicit support_factor must be > 1.2, got ",
              options.support_factor);
  ThrowUnless(options.cell_factor > 0.02 && options.cell_factor <= 1.0,
              "implicit cell_factor must be in (0.02, 1], got ", options.cell_factor);
  // iso = (1 / spacing) integral over x of K(R^2 + x^2): the field of a straight line of
  // primitives at distance R, averaged over their phase (Simpson, 2000 intervals).
  const double rho = options.support_factor * radius;
  const double half = std::sqrt(rho * rho - radius * radius);
  const int n = 2000;
  double integral = 0.0;
  for (int i = 0; i <= n; ++i) {
    const double x = -half + 2.0 * half * i / n;
    const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
    integral += w * SoftObjectKernel(radius * radius + x * x, rho * rho);
  }
  iso_ = integral * (2.0 * half / n) / 3.0 / spacing_;
}

void ImplicitSkin::Bind(int num_control_points) { curve_.emplace(num_control_points); }

void ImplicitSkin::Build(const Points& q, Mesh* out) {
  CheckSnapshot(q, curve_.has_value() ? curve_->num_points() : 0);
  // primitives uniform in arc length; their count follows the curve length
  arc_table_.Build(*curve_, q);
  const double length = arc_table_.total_length();
  const int intervals = std::max(1, static_cast<int>(std::ceil(length / spacing_)));
  const double spacing = length / intervals;
  primitives_.resize(intervals + 1);
  for (int i = 0; i <= intervals; ++i) {
    primitives_[i] = curve_->Position(q, arc_table_.ParameterAt(i * spacing));
  }
  field_.Reset(primitives_, spacing, spacing / spacing_);

  // seeds: short rays perpendicular to the curve through the expected surface
  seeds_.clear();
  const double cell = options_.cell_factor * radius_;
  const int stride = 8;
  for (int step = 0; step * stride < intervals + stride; ++step) {
    const int i = std::min(step * stride, intervals);
    const Vec3 t = primitives_[std::min(i + 1, intervals)] - primitives_[std::max(i - 1, 0)];
    Eigen::Index axis;
    t.cwiseAbs().minCoeff(&axis);
    const Vec3 n = t.cross(Vec3::Unit(axis)).normalized();
    for (double r = 0.5 * radius_; r <= 1.5 * radius_; r += 0.5 * cell)
      seeds_.push_back(primitives_[i] + r * n);
  }
  // a generous budget: ~ 4x the cells of the tube's own surface
  const double surface_cells = 2.0 * 3.14159 * radius_ * (length + 2.0 * radius_) / (cell * cell);
  const int budget = static_cast<int>(std::min(2.0e8, 4.0 * surface_cells + 1.0e5));
  polygonizer_.Run(field_, iso_, cell, seeds_, budget, out);
  ComputeVertexNormals(out);
  stats_.vertices = out->num_vertices();
  stats_.triangles = out->num_triangles();
  stats_.field_evaluations = polygonizer_.field_evaluations();
  stats_.primitives = static_cast<int>(primitives_.size());
}

}  // namespace viscera::skin
