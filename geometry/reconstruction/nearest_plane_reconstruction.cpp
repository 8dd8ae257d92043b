// Method 1 with block culling of planes (see nearest_plane_reconstruction.h).
#include "geometry/reconstruction/nearest_plane_reconstruction.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/reconstruction/plane_rows.h"

namespace xsect {

namespace {

/// Planes of `from` that may be nearest somewhere in the box [c - e, c + e]: those whose lower
/// distance bound does not exceed the smallest upper bound. One pass keeps every plane under the
/// running smallest upper bound; a second pass over the (few) kept ones applies the final bound.
/// With observed pieces (issue 20) the distance to P's piece is sqrt(s² + o²), o the in-plane
/// distance of the projection to the piece, bounded over the box's projection (within the disc of
/// half-diagonal rho about the centre's projection) by ObservedPiece::bounds. Empty pieces are
/// never nearest. `covered` (null, or one flag per plane): pieces known to hold the projection of
/// a box holding this one, whose planes are whole over it.
template <bool kObserved>
void cull(const std::vector<PlaneRow>& rows, const std::vector<ObservedPiece>* pieces,
          const std::vector<int>& from, const Vec3& c, const Vec3& e, std::vector<int>& out,
          std::vector<double>& lo, const std::vector<std::uint8_t>* covered = nullptr) {
  double minHi = std::numeric_limits<double>::infinity();
  out.clear();
  lo.clear();
  for (const int k : from) {
    const PlaneRow& p = rows[k];
    const double r = p.ax * e.x() + p.ay * e.y() + p.az * e.z();
    const double a = std::abs(p.s(c));
    double l = a - r, hi = a + r;
    if constexpr (kObserved) {
      const ObservedPiece& piece = (*pieces)[std::size_t(k)];
      if (!piece.whole && !(l > minHi) && !(covered && (*covered)[std::size_t(k)])) {  // (a piece is no nearer than its plane)
        const double pa = p.ux * c.x() + p.uy * c.y() + p.uz * c.z() - p.uo;
        const double pb = p.vx * c.x() + p.vy * c.y() + p.vz * c.z() - p.vo;
        const double rho = planeNorm(std::abs(p.ux) * e.x() + std::abs(p.uy) * e.y() + std::abs(p.uz) * e.z(),
                                      std::abs(p.vx) * e.x() + std::abs(p.vy) * e.y() + std::abs(p.vz) * e.z());
        if (!covers(piece, pa, pb, rho)) {  // covered: o = 0 over the box, the whole plane's bounds
          double olo, ohi;
          piece.bounds(pa, pb, rho, &olo, &ohi);
          if (!std::isfinite(olo)) continue;
          l = planeNorm(std::max(0.0, l), olo);
          hi = planeNorm(hi, ohi);
        }
      }
    }
    if (l > minHi) continue;
    minHi = std::min(minHi, hi);
    out.push_back(k);
    lo.push_back(l);
  }
  std::size_t n = 0;
  for (std::size_t q = 0; q < out.size(); ++q)
    if (lo[q] <= minHi) out[n++] = out[q];
  out.resize(n);
}

/// forEachNearestPlaneBlock, on whole planes (kObserved false: the thesis' method 1, unchanged) or
/// on the planes' observed pieces: the candidate planes per 32³ super-box (pass 1), then per 8³
/// block an octree of boxes that culls them again (pass 2), each voxel scanning the survivors.
template <bool kObserved>
class NearestPieceScan {
 public:
  static constexpr int kSuper = 32, kBlock = BlockGrid<float>::kSide;

  NearestPieceScan(const std::vector<CuttingPlane>& planes, const std::vector<SectionDistanceField>& fields,
                   const std::vector<ObservedPiece>* pieces, const GridSpec& grid)
      : planes_(planes), fields_(fields), pieces_(pieces), grid_(grid), rows_(planeRows(planes)), h_(grid.voxel),
        near_(0.5 * std::sqrt(3.0) * grid.voxel * (1 + 1e-6)) {
    const auto& D = grid.dims;
    sx_ = (D[0] + kSuper - 1) / kSuper, sy_ = (D[1] + kSuper - 1) / kSuper, sz_ = (D[2] + kSuper - 1) / kSuper;
    bx_ = (D[0] + kBlock - 1) / kBlock, by_ = (D[1] + kBlock - 1) / kBlock, bz_ = (D[2] + kBlock - 1) / kBlock;
    superCandidates();
  }

  /// Every block of the grid, in chunks (progress after each), its values given to visitBlock.
  void run(const std::function<void(std::int64_t, const NearestPlaneBlock&)>& visitBlock, bool wholeBlocks,
           const std::function<void(std::int64_t, std::int64_t)>& progress) const {
    const std::int64_t blocks = bx_ * by_ * bz_;
    const std::int64_t chunk = std::max<std::int64_t>(256, blocks / 16);
    for (std::int64_t first = 0; first < blocks; first += chunk) {
      const std::int64_t last = std::min(blocks, first + chunk);
      tbb::parallel_for(tbb::blocked_range<std::int64_t>(first, last, 16), [&](const tbb::blocked_range<std::int64_t>& r) {
        Scratch w;
        for (std::int64_t b = r.begin(); b != r.end(); ++b) doBlock(b, w, visitBlock, wholeBlocks);
      });
      if (progress) progress(last, blocks);
    }
  }

 private:
    // Pass 2: inside each 8³ box, an octree of boxes (8 -> 4 -> 2) culls the list again at every
    // level (planes crossing a box shrink with its size: with hundreds of random planes the 8³ list
    // holds dozens, the 2³ list a handful); voxels scan the survivors, each candidate's distance
    // updated incrementally from the box corner.
    struct Scratch {
      std::vector<int> lists[4];  // candidates at box sizes 8, 4, 2 (index = level)
      std::vector<double> lo, s0, nx, ny, nz;
      NearestPlaneBlock block;
      std::vector<std::uint8_t> covered;  // per plane: superCovered of the super-box `super`
      int super = -1;
    };

  /// The box of voxels [i0, i1) x [j0, j1) x [k0, k1): its centre and half extents.
  void box(int i0, int j0, int k0, int i1, int j1, int k1, Vec3* c, Vec3* e) const {
    const Vec3 a = grid_.centre(i0, j0, k0), b = grid_.centre(i1 - 1, j1 - 1, k1 - 1);
    *c = 0.5 * (a + b);
    *e = 0.5 * (b - a);
  }

  /// Pass 1: planes that may be nearest in each 32³ super-box.
  /// With observed pieces, also the candidates whose piece holds the whole super-box's projection:
  /// their planes are whole over every box inside it, and the culls and voxels below skip their
  /// piece (most planes of a dense sweep, away from the edges of the probe's field of view).
  void superCandidates() {
    const auto& D = grid_.dims;
    const int supers = sx_ * sy_ * sz_;
    std::vector<int> all(planes_.size());
    for (std::size_t i = 0; i < all.size(); ++i) all[i] = int(i);
    superCand_.resize(std::size_t(supers));
    superCovered_.resize(kObserved ? std::size_t(supers) : 0);
    tbb::parallel_for(0, supers, [&](int s) {
      const int bi = s % sx_, bj = (s / sx_) % sy_, bk = s / (sx_ * sy_);
      const int i0 = bi * kSuper, j0 = bj * kSuper, k0 = bk * kSuper;
      Vec3 c, e;
      box(i0, j0, k0, std::min(D[0], i0 + kSuper), std::min(D[1], j0 + kSuper),
          std::min(D[2], k0 + kSuper), &c, &e);
      std::vector<double> lo;
      cull<kObserved>(rows_, pieces_, all, c, e, superCand_[s], lo);
      if constexpr (kObserved)
        for (const int k : superCand_[s]) {
          const PlaneRow& r = rows_[std::size_t(k)];
          const double ra = std::abs(r.ux) * e.x() + std::abs(r.uy) * e.y() + std::abs(r.uz) * e.z();
          const double rb = std::abs(r.vx) * e.x() + std::abs(r.vy) * e.y() + std::abs(r.vz) * e.z();
          if (covers((*pieces_)[std::size_t(k)], r.ux * c.x() + r.uy * c.y() + r.uz * c.z() - r.uo,
                     r.vx * c.x() + r.vy * c.y() + r.vz * c.z() - r.vo, planeNorm(ra, rb)))
            superCovered_[std::size_t(s)].push_back(k);
        }
    });
  }

  /// Points w.covered at super-box s's covered planes.
  void coverSuper(int s, Scratch& w) const {
    if constexpr (kObserved) {
      if (w.super == s) return;
      w.covered.resize(planes_.size(), 0);
      if (w.super >= 0)
        for (const int k : superCovered_[std::size_t(w.super)]) w.covered[std::size_t(k)] = 0;
      for (const int k : superCovered_[std::size_t(s)]) w.covered[std::size_t(k)] = 1;
      w.super = s;
    }
  }

  /// The voxels of a box, from the candidates `cand`.
  void evalVoxels(int i0, int j0, int k0, int i1, int j1, int k1, const std::vector<int>& cand, Scratch& w) const {
    const Vec3 x0 = grid_.centre(i0, j0, k0);
    const std::size_t m = cand.size();
    w.s0.resize(m);
    w.nx.resize(m);
    w.ny.resize(m);
    w.nz.resize(m);
    for (std::size_t q = 0; q < m; ++q) {  // contiguous copies: a tight scan per voxel
      const PlaneRow& r = rows_[cand[q]];
      w.s0[q] = r.s(x0);
      w.nx[q] = r.nx * h_;
      w.ny[q] = r.ny * h_;
      w.nz[q] = r.nz * h_;
    }
    const double* s0 = w.s0.data();
    const double *nx = w.nx.data(), *ny = w.ny.data(), *nz = w.nz.data();
    // Observed pieces that all hold the box's projection: their planes are whole over the box.
    bool covered = m > 0;  // (an empty list: no piece observed near the box, the observed branch)
    if constexpr (kObserved) {
      Vec3 c, e;
      box(i0, j0, k0, i1, j1, k1, &c, &e);
      for (std::size_t q = 0; q < m && covered; ++q) {
        if (w.covered[std::size_t(cand[q])]) continue;
        const PlaneRow& r = rows_[cand[q]];
        const double ra = std::abs(r.ux) * e.x() + std::abs(r.uy) * e.y() + std::abs(r.uz) * e.z();
        const double rb = std::abs(r.vx) * e.x() + std::abs(r.vy) * e.y() + std::abs(r.vz) * e.z();
        covered = covers((*pieces_)[std::size_t(cand[q])], r.ux * c.x() + r.uy * c.y() + r.uz * c.z() - r.uo,
                         r.vx * c.x() + r.vy * c.y() + r.vz * c.z() - r.vo, planeNorm(ra, rb));
      }
    }
    for (int k = k0; k < k1; ++k)
      for (int j = j0; j < j1; ++j)
        for (int i = i0; i < i1; ++i) {
          const double di = i - i0, dj = j - j0, dk = k - k0;
          const std::size_t o = std::size_t(BlockGrid<float>::offset(i, j, k));
          const Vec3 x = x0 + h_ * Vec3(di, dj, dk);
          double best = std::numeric_limits<double>::infinity();
          int bq = 0;
          if (!kObserved || covered) {
            for (std::size_t q = 0; q < m; ++q) {
              const double d = std::abs(s0[q] + nx[q] * di + ny[q] * dj + nz[q] * dk);
              if (d < best) {
                best = d;
                bq = int(q);
              }
            }
            const int bp = cand[bq];
            const PlaneRow& r = rows_[bp];
            const double a = r.ux * x.x() + r.uy * x.y() + r.uz * x.z() - r.uo;
            const double b = r.vx * x.x() + r.vy * x.y() + r.vz * x.z() - r.vo;
            w.block.value[o] = fields_[bp].sample(a, b);
            w.block.plane_distance[o] = float(best);
            w.block.nearest_plane[o] = bp;
          } else if constexpr (kObserved) {
            // The nearest piece: sqrt(s² + o²) >= |s|, so a plane no nearer than the best is skipped
            // before its in-plane distance is needed. The value is f_P at the piece's nearest point.
            double ba = 0, bb = 0;
            for (std::size_t q = 0; q < m; ++q) {
              const double sd = std::abs(s0[q] + nx[q] * di + ny[q] * dj + nz[q] * dk);
              if (!(sd < best)) continue;
              const PlaneRow& r = rows_[cand[q]];
              const double a = r.ux * x.x() + r.uy * x.y() + r.uz * x.z() - r.uo;
              const double b = r.vx * x.x() + r.vy * x.y() + r.vz * x.z() - r.vo;
              double na, nb;
              const double op = (*pieces_)[std::size_t(cand[q])].distance(a, b, &na, &nb);
              const double d = op > 0 ? planeNorm(sd, op) : sd;
              if (d < best) {
                best = d;
                bq = int(q);
                ba = na;
                bb = nb;
              }
            }
            const int bp = m ? cand[bq] : -1;
            w.block.value[o] = bp >= 0 && std::isfinite(best) ? fields_[bp].sample(ba, bb) : fields_.back().band;
            w.block.plane_distance[o] = float(best);
            w.block.nearest_plane[o] = bp;
          }
        }
  }

  /// Box of `size` voxels at (i0, j0, k0), candidates `from`; level 0 = 8³.
  void visit(int i0, int j0, int k0, int size, int level, const std::vector<int>& from, Scratch& w) const {
    const auto& D = grid_.dims;
    const int i1 = std::min(D[0], i0 + size), j1 = std::min(D[1], j0 + size),
              k1 = std::min(D[2], k0 + size);
    if (i0 >= i1 || j0 >= j1 || k0 >= k1) return;
    Vec3 c, e;
    box(i0, j0, k0, i1, j1, k1, &c, &e);
    if (size <= 2 && from.size() <= 12) {  // short list: a cull would cost as much as it saves
      evalVoxels(i0, j0, k0, i1, j1, k1, from, w);
      return;
    }
    std::vector<int>& list = w.lists[level];
    cull<kObserved>(rows_, pieces_, from, c, e, list, w.lo, &w.covered);
    if (size <= 2 || list.size() <= 2) {
      evalVoxels(i0, j0, k0, i1, j1, k1, list, w);
      return;
    }
    const int half = size / 2;
    for (int dz = 0; dz < 2; ++dz)
      for (int dy = 0; dy < 2; ++dy)
        for (int dx = 0; dx < 2; ++dx)
          visit(i0 + dx * half, j0 + dy * half, k0 + dz * half, half, level + 1, list, w);
  }

    // A whole block decided at once (issue 17): when every plane that may be nearest somewhere in it
    // sees the block's projection only where its raster is +band (no contour within the band, the
    // sections' outside) and lies farther than `near` from every voxel centre, every voxel's value
    // is +band and none is next to a plane: no voxel needs evaluating. The distances given are the
    // block's lower bound and the plane the first candidate (the solid needs neither).
  bool outsideBlock(int i0, int j0, int k0, const std::vector<int>& from, Scratch& w) const {
    const auto& D = grid_.dims;
    Vec3 c, e;
    box(i0, j0, k0, std::min(D[0], i0 + kBlock), std::min(D[1], j0 + kBlock), std::min(D[2], k0 + kBlock), &c, &e);
    std::vector<int>& list = w.lists[3];
    cull<kObserved>(rows_, pieces_, from, c, e, list, w.lo, &w.covered);
    if (list.empty()) return false;
    double lowest = std::numeric_limits<double>::infinity();
    const float band = fields_[std::size_t(list[0])].band;
    for (const int k : list) {
      const PlaneRow& r = rows_[std::size_t(k)];
      double l = std::abs(r.s(c)) - (r.ax * e.x() + r.ay * e.y() + r.az * e.z());
      const double a = r.ux * c.x() + r.uy * c.y() + r.uz * c.z() - r.uo;
      const double b = r.vx * c.x() + r.vy * c.y() + r.vz * c.z() - r.vo;
      const double ra = std::abs(r.ux) * e.x() + std::abs(r.uy) * e.y() + std::abs(r.uz) * e.z();
      const double rb = std::abs(r.vx) * e.x() + std::abs(r.vy) * e.y() + std::abs(r.vz) * e.z();
      double pad = 1e-9 * (ra + rb + h_);
      if constexpr (kObserved) {
        // The piece's nearest points to the block lie within o(c) + rho of the block's projection.
        const ObservedPiece& piece = (*pieces_)[std::size_t(k)];
        if (!w.covered[std::size_t(k)] && !covers(piece, a, b, planeNorm(ra, rb))) {
          double olo, ohi;
          piece.bounds(a, b, planeNorm(ra, rb), &olo, &ohi);
          if (!std::isfinite(olo)) return false;
          l = planeNorm(std::max(0.0, l), olo);
          // The block's projection entirely beyond the piece: every nearest point lies on the piece's
          // edge, where no section reaches (+band): nothing of this plane to check.
          if (olo > 0 && piece.edge_outside) {
            if (!(l > near_) || fields_[std::size_t(k)].band != band) return false;
            lowest = std::min(lowest, l);
            continue;
          }
          pad += ohi;
        }
      }
      if (!(l > near_) || fields_[std::size_t(k)].band != band) return false;
      lowest = std::min(lowest, l);
      if (!fields_[std::size_t(k)].outsideOver(a - ra - pad, a + ra + pad, b - rb - pad, b + rb + pad)) return false;
    }
    w.block.value.fill(band);
    w.block.plane_distance.fill(float(lowest));
    w.block.nearest_plane.fill(list[0]);
    w.block.far_outside = true;
    return true;
  }

  void doBlock(std::int64_t b, Scratch& w, const std::function<void(std::int64_t, const NearestPlaneBlock&)>& visitBlock,
               bool wholeBlocks) const {
    const int ib = int(b % bx_) * kBlock, jb = int((b / bx_) % by_) * kBlock, kb = int(b / (bx_ * by_)) * kBlock;
    const int s = (ib / kSuper) + sx_ * ((jb / kSuper) + sy_ * (kb / kSuper));
    coverSuper(s, w);
    NearestPlaneBlock& v = w.block;
    if (wholeBlocks && outsideBlock(ib, jb, kb, superCand_[s], w)) {
      visitBlock(b, v);
      return;
    }
    v.far_outside = false;
    visit(ib, jb, kb, kBlock, 0, superCand_[s], w);
    forEachBeyondGrid(grid_, {ib, jb, kb}, [&](int o) {
      v.value[std::size_t(o)] = v.value[0];
      v.plane_distance[std::size_t(o)] = v.plane_distance[0];
      v.nearest_plane[std::size_t(o)] = v.nearest_plane[0];
    });
    visitBlock(b, v);
  }

  const std::vector<CuttingPlane>& planes_;
  const std::vector<SectionDistanceField>& fields_;
  const std::vector<ObservedPiece>* pieces_;
  const GridSpec& grid_;
  const std::vector<PlaneRow> rows_;
  const double h_;
  const double near_;  ///< a voxel centre this near a plane is next to it
  int sx_ = 0, sy_ = 0, sz_ = 0;  ///< super-boxes along each axis
  std::int64_t bx_ = 0, by_ = 0, bz_ = 0;  ///< blocks along each axis
  std::vector<std::vector<int>> superCand_, superCovered_;
};

template <bool kObserved>
void nearestPieceBlocks(const std::vector<CuttingPlane>& planes, const std::vector<SectionDistanceField>& fields,
                        const std::vector<ObservedPiece>* pieces, const GridSpec& grid,
                        const std::function<void(std::int64_t, const NearestPlaneBlock&)>& visitBlock,
                        bool wholeBlocks, const std::function<void(std::int64_t, std::int64_t)>& progress) {
  NearestPieceScan<kObserved>(planes, fields, pieces, grid).run(visitBlock, wholeBlocks, progress);
}
}  // namespace

void forEachNearestPlaneBlock(const std::vector<CuttingPlane>& planes,
                              const std::vector<SectionDistanceField>& fields, const GridSpec& grid,
                              const std::function<void(std::int64_t, const NearestPlaneBlock&)>& visitBlock,
                              bool wholeBlocks, const std::function<void(std::int64_t, std::int64_t)>& progress,
                              const std::vector<ObservedPiece>* pieces) {
  if (planes.empty()) throw std::invalid_argument("method 1: no cutting plane");
  if (fields.size() != planes.size())
    throw std::invalid_argument("method 1: one distance raster per plane is required");
  if (pieces && pieces->size() != planes.size())
    throw std::invalid_argument("method 1: one observed piece per plane is required");
  if (!(grid.voxel > 0)) throw std::invalid_argument("method 1: voxel size must be positive");
  const bool observed =
      pieces && std::any_of(pieces->begin(), pieces->end(), [](const ObservedPiece& p) { return !p.whole; });
  if (observed)
    nearestPieceBlocks<true>(planes, fields, pieces, grid, visitBlock, wholeBlocks, progress);
  else
    nearestPieceBlocks<false>(planes, fields, nullptr, grid, visitBlock, wholeBlocks, progress);
}

NearestPlaneField nearestPlaneReconstruction(const std::vector<CuttingPlane>& planes,
                                             const std::vector<SectionDistanceField>& fields,
                                             const GridSpec& grid,
                                             const std::function<void(std::int64_t, std::int64_t)>& progress,
                                             const std::vector<ObservedPiece>* pieces) {
  NearestPlaneField out;
  out.value.grid = grid;
  const std::size_t n = std::size_t(grid.count());
  out.value.values.resize(n);
  out.plane_distance.resize(n);
  out.nearest_plane.resize(n);
  const BlockGrid<float> blocks(grid, 0.f);  // the numbering of the blocks
  forEachNearestPlaneBlock(planes, fields, grid, [&](std::int64_t b, const NearestPlaneBlock& v) {
    forEachVoxelOfBlock(grid, blocks.blockOrigin(b), [&](int i, int j, int k, int o) {
      const std::size_t idx = std::size_t(grid.index(i, j, k)), q = std::size_t(o);
      out.value.values[idx] = v.value[q];
      out.plane_distance[idx] = v.plane_distance[q];
      out.nearest_plane[idx] = v.nearest_plane[q];
    });
  }, false, progress, pieces);
  return out;
}

}  // namespace xsect
