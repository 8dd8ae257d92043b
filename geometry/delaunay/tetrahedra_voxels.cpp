// Method 3's tetrahedra sampled on a voxel grid (see tetrahedra_voxels.h).
#include "geometry/delaunay/tetrahedra_voxels.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>

namespace xsect {

namespace {

constexpr int kSide = BlockGrid<float>::kSide;
constexpr int kVoxels = BlockGrid<float>::kVoxels;

/// A tetrahedron's voxel centres to visit: the index box of its centres (inclusive, in the grid)
/// and the real planes holding its vertices.
struct TetrahedronBox {
  std::array<int, 3> lo{0, 0, 0}, hi{-1, -1, -1};
  std::array<int, 4> plane{-1, -1, -1, -1};
  bool empty() const { return hi[0] < lo[0] || hi[1] < lo[1] || hi[2] < lo[2]; }
};

/// The four face planes of a tetrahedron: n·x + d <= 0 inside, n outward and of unit length.
struct Faces {
  std::array<Vec3, 4> n;
  std::array<double, 4> d;
};

Faces facesOf(const std::array<Vec3, 4>& t) {
  Faces f;
  for (int q = 0; q < 4; ++q) {
    const Vec3& a = t[std::size_t((q + 1) % 4)];
    const Vec3& b = t[std::size_t((q + 2) % 4)];
    const Vec3& c = t[std::size_t((q + 3) % 4)];
    Vec3 n = (b - a).cross(c - a);
    n /= n.norm();  // not flat: checked before
    if (n.dot(t[std::size_t(q)] - a) > 0) n = -n;
    f.n[std::size_t(q)] = n;
    f.d[std::size_t(q)] = -n.dot(a);
  }
  return f;
}

bool flat(const std::array<Vec3, 4>& t) {
  double longest = 0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) longest = std::max(longest, (t[std::size_t(a)] - t[std::size_t(b)]).norm());
  const double volume = std::abs((t[1] - t[0]).dot((t[2] - t[0]).cross(t[3] - t[0])));
  return !(volume > 1e-12 * longest * longest * longest);
}

/// The first real plane holding sections within `tol` of x (-1: none).
int planeOf(const Vec3& x, const std::vector<CuttingPlane>& planes, const std::vector<int>& holding, double tol) {
  for (const int p : holding)
    if (std::abs(planes[std::size_t(p)].plane.signedDistance(x)) <= tol) return p;
  return -1;
}

/// The voxel centres to visit for a tetrahedron: those in its bounding box, grown by `margin` mm
/// (half a voxel for the cube rule: a cube meets the tetrahedron only if its centre lies within
/// half a voxel of the box).
TetrahedronBox boxOf(const std::array<Vec3, 4>& t, const GridSpec& grid, double margin) {
  TetrahedronBox b;
  if (flat(t)) return b;
  for (int a = 0; a < 3; ++a) {
    double lo = t[0][a], hi = t[0][a];
    for (int v = 1; v < 4; ++v) lo = std::min(lo, t[std::size_t(v)][a]), hi = std::max(hi, t[std::size_t(v)][a]);
    lo -= margin, hi += margin;
    const double l = std::ceil((lo - grid.origin[a]) / grid.voxel - 1e-6);
    const double h = std::floor((hi - grid.origin[a]) / grid.voxel + 1e-6);
    b.lo[std::size_t(a)] = int(std::clamp(l, 0.0, double(grid.dims[a])));
    b.hi[std::size_t(a)] = int(std::clamp(h, -1.0, double(grid.dims[a] - 1)));
  }
  return b;
}

/// A tetrahedron as slabs lo <= n·x <= hi that a voxel centre x must lie in: its four face planes
/// (centre rule, lo = -inf), or every separating axis of the tetrahedron and a voxel's cube,
/// widened by the cube's half-extent along the axis (cube rule: the three box normals, the four
/// face normals, the cross products of the box's edges with the tetrahedron's six edges).
struct Slabs {
  std::vector<Vec3> n;
  std::vector<double> lo, hi;
};

Slabs slabsOf(const std::array<Vec3, 4>& t, VoxelRule rule, double voxel, double tol) {
  Slabs s;
  const Faces f = facesOf(t);
  if (rule == VoxelRule::centre) {
    for (int q = 0; q < 4; ++q) {
      s.n.push_back(f.n[std::size_t(q)]);
      s.lo.push_back(-1e300);
      s.hi.push_back(tol - f.d[std::size_t(q)]);
    }
    return s;
  }
  std::vector<Vec3> axes{Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitZ()};
  for (int q = 0; q < 4; ++q) axes.push_back(f.n[std::size_t(q)]);
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      for (int e = 0; e < 3; ++e) {
        Vec3 n = Vec3::Unit(e).cross(t[std::size_t(b)] - t[std::size_t(a)]);
        const double len = n.norm();
        if (len > 1e-12 * (t[std::size_t(b)] - t[std::size_t(a)]).norm()) axes.push_back(n / len);
      }
  for (const Vec3& n : axes) {
    double lo = n.dot(t[0]), hi = lo;
    for (int v = 1; v < 4; ++v) lo = std::min(lo, n.dot(t[std::size_t(v)])), hi = std::max(hi, n.dot(t[std::size_t(v)]));
    const double r = 0.5 * voxel * n.cwiseAbs().sum() + tol;
    s.n.push_back(n);
    s.lo.push_back(lo - r);
    s.hi.push_back(hi + r);
  }
  return s;
}

/// Fills the rows of blocks of one layer, row by row (see tetrahedra_voxels.h).
class LayerScan {
 public:
  LayerScan(const TetrahedronSet& tetrahedra, const std::vector<TetrahedronBox>& boxes,
            const std::vector<CuttingPlane>& planes, VoxelRule rule, SampledReconstruction& out)
      : tetrahedra_(tetrahedra), boxes_(boxes), planes_(planes), rule_(rule), out_(out), grid_(out.inside.grid()),
        width_(out.inside.blockDims()[0] * kSide), tol_(1e-6 * grid_.voxel) {}

  /// Row of blocks (bj, bk) from the tetrahedra `list` (ascending); returns its largest lift, mm.
  double row(int bj, int bk, const int* list, std::size_t count) const {
    const std::size_t n = std::size_t(kSide) * kSide * std::size_t(width_);
    std::vector<std::uint8_t> in(n, 0);
    std::vector<int> plane(n, -1);
    double lift = 0;
    const double h = grid_.voxel;
    for (std::size_t q = 0; q < count; ++q) {
      const int t = list[q];
      const TetrahedronBox& box = boxes_[std::size_t(t)];
      const Slabs f = slabsOf(tetrahedra_.at(std::size_t(t)), rule_, h, tol_);
      const int k0 = std::max(box.lo[2], bk * kSide), k1 = std::min(box.hi[2], bk * kSide + kSide - 1);
      const int j0 = std::max(box.lo[1], bj * kSide), j1 = std::min(box.hi[1], bj * kSide + kSide - 1);
      for (int k = k0; k <= k1; ++k)
        for (int j = j0; j <= j1; ++j) {
          // The centres (i, j, k) with lo <= n·x <= hi for every slab: lo - c <= n_x h i <= hi - c.
          const double y = grid_.origin.y() + h * j, z = grid_.origin.z() + h * k;
          double lo = box.lo[0], hi = box.hi[0];
          const double last = double(grid_.dims[0]) + 1;
          for (std::size_t s = 0; s < f.n.size() && lo <= hi; ++s) {
            const Vec3& nf = f.n[s];
            const double c = nf.y() * y + nf.z() * z + nf.x() * grid_.origin.x();
            const double a = nf.x() * h;
            if (a == 0) {
              if (c > f.hi[s] || c < f.lo[s]) hi = lo - 1;
            } else if (a > 0) {
              hi = std::min(hi, std::floor(std::clamp((f.hi[s] - c) / a, -2.0, last)));
              lo = std::max(lo, std::ceil(std::clamp((f.lo[s] - c) / a, -2.0, last)));
            } else {
              lo = std::max(lo, std::ceil(std::clamp((f.hi[s] - c) / a, -2.0, last)));
              hi = std::min(hi, std::floor(std::clamp((f.lo[s] - c) / a, -2.0, last)));
            }
          }
          const std::size_t rowStart = (std::size_t(k - bk * kSide) * kSide + std::size_t(j - bj * kSide)) * std::size_t(width_);
          for (int i = int(lo); i <= int(hi); ++i) {
            const std::size_t at = rowStart + std::size_t(i);
            if (in[at]) continue;
            in[at] = 1;
            // The nearest of the planes holding the tetrahedron's vertices (ties: lowest index).
            const Vec3 x = grid_.centre(i, j, k);
            int best = -1;
            double bestDistance = 0;
            for (const int p : box.plane) {
              if (p < 0) continue;
              const double dist = std::abs(planes_[std::size_t(p)].plane.signedDistance(x));
              if (best < 0 || dist < bestDistance || (dist == bestDistance && p < best)) best = p, bestDistance = dist;
            }
            plane[at] = best;
            if (best >= 0) lift = std::max(lift, bestDistance);
          }
        }
    }
    // The row's blocks; voxels beyond the grid repeat the block's first voxel (a uniform block
    // within the grid stays a tile).
    std::array<std::uint8_t, kVoxels> blockIn;
    std::array<int, kVoxels> blockPlane;
    for (int bi = 0; bi < out_.inside.blockDims()[0]; ++bi) {
      const std::int64_t b = out_.inside.block(bi, bj, bk);
      for (int dk = 0; dk < kSide; ++dk)
        for (int dj = 0; dj < kSide; ++dj)
          for (int di = 0; di < kSide; ++di) {
            const std::size_t at = (std::size_t(dk) * kSide + std::size_t(dj)) * std::size_t(width_) + std::size_t(bi * kSide + di);
            const int o = BlockGrid<float>::offset(di, dj, dk);
            blockIn[std::size_t(o)] = in[at];
            blockPlane[std::size_t(o)] = plane[at];
          }
      forEachBeyondGrid(grid_, out_.inside.blockOrigin(b), [&](int o) {
        blockIn[std::size_t(o)] = blockIn[0];
        blockPlane[std::size_t(o)] = blockPlane[0];
      });
      out_.inside.setBlock(b, blockIn.data());
      out_.section_plane.setBlock(b, blockPlane.data());
    }
    return lift;
  }

 private:
  const TetrahedronSet& tetrahedra_;
  const std::vector<TetrahedronBox>& boxes_;
  const std::vector<CuttingPlane>& planes_;
  const VoxelRule rule_;
  SampledReconstruction& out_;
  const GridSpec& grid_;
  const int width_;    ///< voxels along x of a row of blocks (whole blocks)
  const double tol_;   ///< mm
};

/// The field from the solid: ±band, ∓voxel/2 at voxels with a face neighbour of the other side.
void fillField(SampledReconstruction& out, float band) {
  const BlockGrid<std::uint8_t>& in = out.inside;
  const GridSpec& grid = in.grid();
  const auto& D = grid.dims;
  const auto& B = in.blockDims();
  const float half = std::min(band, float(0.5 * grid.voxel));
  const auto at = [&](int i, int j, int k) -> std::uint8_t {
    return i < 0 || j < 0 || k < 0 || i >= D[0] || j >= D[1] || k >= D[2] ? 0 : in.at(i, j, k);
  };
  tbb::parallel_for(std::int64_t(0), in.blockCount(), [&](std::int64_t b) {
    const auto o = in.blockOrigin(b);
    if (!in.isLeaf(b)) {
      // A tile whose face neighbours are tiles of its value (outside the grid: 0) has no
      // boundary voxel.
      const std::uint8_t v = in.tile(b);
      const std::array<int, 3> bc{o[0] / kSide, o[1] / kSide, o[2] / kSide};
      bool uniform = true;
      for (int a = 0; a < 3 && uniform; ++a)
        for (const int step : {-1, 1}) {
          std::array<int, 3> nb = bc;
          nb[std::size_t(a)] += step;
          if (nb[std::size_t(a)] < 0 || nb[std::size_t(a)] >= B[std::size_t(a)]) {
            uniform = uniform && v == 0;
            continue;
          }
          const std::int64_t n = in.block(nb[0], nb[1], nb[2]);
          uniform = uniform && !in.isLeaf(n) && in.tile(n) == v;
        }
      if (uniform) {
        out.field.setTile(b, v ? -band : band);
        return;
      }
    }
    std::array<float, kVoxels> values;
    forEachVoxelOfBlock(grid, o, [&](int i, int j, int k, int q) {
      const std::uint8_t s = at(i, j, k);
      const bool boundary = at(i - 1, j, k) != s || at(i + 1, j, k) != s || at(i, j - 1, k) != s ||
                            at(i, j + 1, k) != s || at(i, j, k - 1) != s || at(i, j, k + 1) != s;
      values[std::size_t(q)] = s ? (boundary ? -half : -band) : (boundary ? half : band);
    });
    forEachBeyondGrid(grid, o, [&](int q) { values[std::size_t(q)] = values[0]; });
    out.field.setBlock(b, values.data());
  });
}

}  // namespace

SampledReconstruction tetrahedraOnGrid(const TetrahedronSet& tetrahedra,
                                       const std::vector<CuttingPlane>& planes, std::size_t realPlanes,
                                       const GridSpec& grid, float band_mm, VoxelRule rule,
                                       const std::function<void(std::int64_t, std::int64_t)>& progress) {
  const auto t0 = std::chrono::steady_clock::now();
  SampledReconstruction out;
  out.field = BlockGrid<float>(grid, band_mm);
  out.inside = BlockGrid<std::uint8_t>(grid, 0);
  out.section_plane = BlockGrid<int>(grid, -1);

  // Each tetrahedron's box of voxel centres and its vertices' planes (section-vertices lie on the
  // real planes holding sections; a vertex on two planes, on their common line, takes the first).
  std::vector<int> holding;
  for (std::size_t p = 0; p < std::min(realPlanes, planes.size()); ++p)
    if (!planes[p].sections.empty()) holding.push_back(int(p));
  const double planeTol = 1e-3 * grid.voxel;
  std::vector<int> vertexPlane(tetrahedra.vertices.size());
  tbb::parallel_for(std::size_t(0), vertexPlane.size(), [&](std::size_t v) {
    vertexPlane[v] = planeOf(tetrahedra.vertices[v], planes, holding, planeTol);
  });
  std::vector<TetrahedronBox> boxes(tetrahedra.size());
  tbb::parallel_for(std::size_t(0), tetrahedra.size(), [&](std::size_t t) {
    boxes[t] = boxOf(tetrahedra.at(t), grid, rule == VoxelRule::cube ? 0.5 * grid.voxel : 0.0);
    if (boxes[t].empty()) return;
    for (int v = 0; v < 4; ++v)
      boxes[t].plane[std::size_t(v)] = vertexPlane[std::size_t(tetrahedra.corners[t][std::size_t(v)])];
  });

  // Layers of blocks along z, in order: the tetrahedra whose boxes meet the layer (kept in
  // ascending order), listed per row of blocks along y.
  const auto& B = out.inside.blockDims();
  std::vector<std::vector<int>> starting(static_cast<std::size_t>(B[2]));
  for (std::size_t t = 0; t < boxes.size(); ++t)
    if (!boxes[t].empty()) starting[std::size_t(boxes[t].lo[2] / kSide)].push_back(int(t));
  std::vector<int> active, merged, rowStart, rowList;
  std::atomic<std::int64_t> done{0};
  const std::int64_t rows = std::int64_t(B[1]) * B[2];
  std::vector<double> layerLift(static_cast<std::size_t>(B[1]));
  double maxLift = 0;
  LayerScan scan(tetrahedra, boxes, planes, rule, out);
  for (int bk = 0; bk < B[2]; ++bk) {
    active.erase(std::remove_if(active.begin(), active.end(),
                                [&](int t) { return boxes[std::size_t(t)].hi[2] / kSide < bk; }),
                 active.end());
    merged.clear();
    std::merge(active.begin(), active.end(), starting[std::size_t(bk)].begin(), starting[std::size_t(bk)].end(),
               std::back_inserter(merged));
    active.swap(merged);
    std::vector<int>().swap(starting[std::size_t(bk)]);
    // Rows of blocks (bj) as lists of tetrahedra, ascending (counting sort keeps the order).
    rowStart.assign(std::size_t(B[1]) + 1, 0);
    for (const int t : active)
      for (int bj = boxes[std::size_t(t)].lo[1] / kSide; bj <= boxes[std::size_t(t)].hi[1] / kSide; ++bj)
        ++rowStart[std::size_t(bj) + 1];
    for (int bj = 0; bj < B[1]; ++bj) rowStart[std::size_t(bj) + 1] += rowStart[std::size_t(bj)];
    rowList.resize(std::size_t(rowStart.back()));
    {
      std::vector<int> fill(rowStart.begin(), rowStart.end() - 1);
      for (const int t : active)
        for (int bj = boxes[std::size_t(t)].lo[1] / kSide; bj <= boxes[std::size_t(t)].hi[1] / kSide; ++bj)
          rowList[std::size_t(fill[std::size_t(bj)]++)] = t;
    }
    tbb::parallel_for(0, B[1], [&](int bj) {
      const std::size_t first = std::size_t(rowStart[std::size_t(bj)]);
      const std::size_t count = std::size_t(rowStart[std::size_t(bj) + 1]) - first;
      // A row no tetrahedron meets keeps its tiles (0, -1).
      layerLift[std::size_t(bj)] = count > 0 ? scan.row(bj, bk, rowList.data() + first, count) : 0.0;
      const std::int64_t d = ++done;
      if (progress) progress(d, rows);
    });
    for (const double l : layerLift) maxLift = std::max(maxLift, l);
  }

  fillField(out, band_mm);
  out.raw_inside = out.inside;
  out.max_lift_mm = maxLift;
  out.voxels_inside = out.inside.count(1);
  out.voxel_betti = voxelBetti(out.inside);
  out.storage.blocks = out.field.blockCount();
  out.storage.field_leaves = out.field.leafCount();
  out.storage.section_leaves = out.section_plane.leafCount();
  out.storage.inside_leaves = out.inside.leafCount();
  out.evaluate_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

SampledReconstruction tetrahedraOnGridLike(const TetrahedronSet& tetrahedra, const std::vector<CuttingPlane>& planes,
                                           std::size_t realPlanes, const GridSpec& grid, float band_mm,
                                           const Betti& target, int refinements, VoxelLikeness* how) {
  // An empty set never beats a non-empty one (its distance is the target's whole size otherwise).
  const auto distance = [&](const Betti& b) {
    const bool empty = b == Betti{0, 0, 0} && target != Betti{0, 0, 0};
    return (empty ? 1000000 : 0) + std::abs(b[0] - target[0]) + std::abs(b[1] - target[1]) + std::abs(b[2] - target[2]);
  };
  SampledReconstruction best;
  int bestDistance = -1;
  double seconds = 0;
  for (int level = 0; level <= refinements; ++level) {
    // The same box at 2^level voxels per voxel: centres of the coarse grid stay centres.
    GridSpec g = grid;
    const int f = 1 << level;
    g.voxel = grid.voxel / f;
    for (int a = 0; a < 3; ++a) g.dims[a] = (grid.dims[a] - 1) * f + 1;
    if (level > 0 && double(g.count()) > kMaxRefinedVoxels) break;
    for (const VoxelRule rule : {VoxelRule::centre, VoxelRule::cube}) {
      SampledReconstruction r = tetrahedraOnGrid(tetrahedra, planes, realPlanes, g, band_mm, rule);
      seconds += r.evaluate_seconds;
      const int d = distance(r.voxel_betti);
      if (bestDistance < 0 || d < bestDistance) {  // ties: the coarser grid, the centre rule
        best = std::move(r);
        bestDistance = d;
        *how = {rule, level, d == 0};
      }
      if (d == 0) {
        best.evaluate_seconds = seconds;
        return best;
      }
    }
  }
  best.evaluate_seconds = seconds;
  return best;
}

}  // namespace xsect
