// Marching squares with oriented segments (see iso_contours.h). The field is padded by one
// outside pixel (so every contour closes) and walked over the inside pixels' box only; cells whose
// four corners agree are skipped with one comparison, and crossings live in compact arrays
// indexed through a per-edge slot table.
// labelIsoContours: the same walk over a material map, each mixed cell split among its materials
// (see the comment before it), oriented segments per label, traced into rings per label.
#include "segmentation/iso_contours.h"

#include <opencv2/core.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <array>
#include <cstdint>

namespace xsect {

std::vector<Ring> isoContours(const cv::Mat& field) {
  CV_Assert(field.type() == CV_32F);
  // Only cells with an inside corner hold crossings: the walk covers the bounding box of the
  // inside pixels widened by one pixel, which beyond the image is the padding (-1). A small object
  // in a large frame costs its box, not the frame (issue 17: 2000 frames of 640 x 480 px).
  const cv::Rect box = cv::boundingRect(field > 0.0f);
  if (box.empty()) return {};
  const cv::Rect wide(box.x - 1, box.y - 1, box.width + 2, box.height + 2);
  const cv::Rect clip = wide & cv::Rect(0, 0, field.cols, field.rows);
  cv::Mat f;
  cv::copyMakeBorder(field(clip), f, clip.y - wide.y, wide.br().y - clip.br().y, clip.x - wide.x,
                     wide.br().x - clip.br().x, cv::BORDER_CONSTANT | cv::BORDER_ISOLATED, cv::Scalar(-1.0f));
  const int W = f.cols, H = f.rows;
  // f's node (0, 0) is node (box.x, box.y) of the image padded by one pixel on each side.
  const int ox = box.x, oy = box.y;
  // Inside = strictly positive; zero counts as outside (nudged to a tiny negative value).
  cv::Mat inside = f > 0.0f;
  for (int j = 0; j < H; ++j) {
    float* r = f.ptr<float>(j);
    for (int i = 0; i < W; ++i)
      if (r[i] == 0.0f) r[i] = -1e-6f;
  }
  // Edge ids: 2*(j*W+i) for (i,j)-(i+1,j); 2*(j*W+i)+1 for (i,j)-(i,j+1).
  std::vector<std::int32_t> slot(std::size_t(2) * W * H, -1);
  std::vector<Vec2> where;
  std::vector<std::int32_t> next;
  const auto crossing = [&](int ia, int ja, int ib, int jb, std::int64_t id) -> std::int32_t {
    std::int32_t& s = slot[std::size_t(id)];
    if (s >= 0) return s;
    const float fa = f.at<float>(ja, ia), fb = f.at<float>(jb, ib);
    const double t = fa / double(fa - fb);
    s = std::int32_t(where.size());
    where.emplace_back((ia + ox) + t * (ib - ia) - 1.0, (ja + oy) + t * (jb - ja) - 1.0);
    next.push_back(-1);
    return s;
  };
  for (int j = 0; j + 1 < H; ++j) {
    const unsigned char* m0 = inside.ptr<unsigned char>(j);
    const unsigned char* m1 = inside.ptr<unsigned char>(j + 1);
    for (int i = 0; i + 1 < W; ++i) {
      // Corners counter-clockwise: c0 (i,j), c1 (i+1,j), c2 (i+1,j+1), c3 (i,j+1).
      const bool in[4] = {m0[i] != 0, m0[i + 1] != 0, m1[i + 1] != 0, m1[i] != 0};
      if (in[0] == in[1] && in[1] == in[2] && in[2] == in[3]) continue;
      const int ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
      const std::int64_t eid[4] = {2 * (std::int64_t(j) * W + i), 2 * (std::int64_t(j) * W + i + 1) + 1,
                                   2 * (std::int64_t(j + 1) * W + i), 2 * (std::int64_t(j) * W + i) + 1};
      int exits[2], entries[2], ne = 0, nn = 0;  // in->out and out->in crossings, CCW order
      std::int32_t at[4];
      for (int k = 0; k < 4; ++k) {
        const int k1 = (k + 1) % 4;
        if (in[k] == in[k1]) continue;
        at[k] = crossing(ci[k], cj[k], ci[k1], cj[k1], eid[k]);
        if (in[k]) exits[ne++] = k; else entries[nn++] = k;
      }
      if (ne == 1) {
        next[at[exits[0]]] = at[entries[0]];
        continue;
      }
      // Saddle: decided by the bilinear value at the cell centre.
      const bool joined =  // inside corners connected through the cell
          saddleJoinsInside(f.at<float>(j, i), f.at<float>(j, i + 1), f.at<float>(j + 1, i + 1), f.at<float>(j + 1, i));
      for (int a = 0; a < 2; ++a) {
        const int e = exits[a];
        int best = -1;  // next out->in crossing counter-clockwise after e (joined) or before e
        for (int s = 1; s < 4 && best < 0; ++s) {
          const int k = joined ? (e + s) % 4 : (e + 4 - s) % 4;
          if (k == entries[0] || k == entries[1]) best = k;
        }
        next[at[e]] = at[best];
      }
    }
  }
  std::vector<Ring> rings;
  std::vector<char> used(where.size(), 0);
  for (std::size_t s = 0; s < where.size(); ++s) {
    if (used[s] || next[s] < 0) continue;
    Ring ring;
    std::int32_t c = std::int32_t(s);
    while (c >= 0 && !used[c]) {
      used[c] = 1;
      ring.push_back(where[c]);
      c = next[c];
    }
    if (ring.size() >= 3) rings.push_back(std::move(ring));
  }
  return rings;
}

// ---------------------------------------------------------------------------------------------
// Several labels. A cell whose corners hold one material is skipped. Otherwise the cell is first
// split into background and non-background as isoContours splits it (same saddle rule, on
// F = max_L f_L; label | background crossings at the zero of that label's field), so with one
// label, or with an unsmoothed label image, the union of all labels' regions is the region
// isoContours finds for "image != 0". Each non-background polygon of the
// cell is then split among the labels of its corners: two runs of corners are separated by one
// segment between the two transition points (a crossing on a cell edge, or a point on a
// background chord where f_A - f_B changes sign); three or four runs of distinct labels meet at
// the mean of their transition points; a label on two opposite corners keeps them joined (its two
// rivals' corners are cut off; with two labels, the one whose f_A - f_B sums positive over the
// corners is joined, as isoContours decides saddles). No label ever touches itself at a single
// point, so every point has at most one outgoing segment per label and rings trace uniquely.
namespace {

struct LabelSegment {
  int label;
  std::int32_t from, to;
};

class LabelContourer {
 public:
  LabelContourer(cv::Size size, const std::vector<LabelField>& fields, float background)
      : W_(size.width + 2), H_(size.height + 2), fields_(fields),
        background_(background == 0.0f ? -1e-6f : background) {
    CV_Assert(background <= 0.0f);
    int maxLabel = 0;
    const cv::Rect image(0, 0, size.width, size.height);
    for (const auto& f : fields) {
      CV_Assert(f.label >= 1 && f.label <= 65535 && f.field.type() == CV_32F &&
                f.field.size() == f.box.size() && (f.box & image) == f.box);
      maxLabel = std::max(maxLabel, f.label);
    }
    index_.assign(std::size_t(maxLabel) + 1, -1);
    for (std::size_t k = 0; k < fields.size(); ++k) {
      CV_Assert(index_[fields[k].label] < 0);  // labels distinct
      index_[fields[k].label] = int(k);
    }
    // Material map and F = max_L f_L on the padded grid (ascending labels: ties -> smaller).
    material_ = cv::Mat(H_, W_, CV_16U, cv::Scalar(0));
    fmax_ = cv::Mat(H_, W_, CV_32F, cv::Scalar(-1.0f));
    fmax_(cv::Rect(1, 1, size.width, size.height)).setTo(background_);
    std::vector<int> order(fields.size());
    for (std::size_t k = 0; k < order.size(); ++k) order[k] = int(k);
    std::sort(order.begin(), order.end(),
              [&](int a, int b) { return fields[a].label < fields[b].label; });
    for (int k : order) {
      const LabelField& f = fields[k];
      for (int y = 0; y < f.box.height; ++y) {
        const float* src = f.field.ptr<float>(y);
        float* dst = fmax_.ptr<float>(f.box.y + y + 1) + f.box.x + 1;
        std::uint16_t* m = material_.ptr<std::uint16_t>(f.box.y + y + 1) + f.box.x + 1;
        for (int x = 0; x < f.box.width; ++x) {
          const float v = src[x] == 0.0f ? -1e-6f : src[x];
          if (v > dst[x]) {
            dst[x] = v;
            if (v > 0.0f) m[x] = std::uint16_t(f.label);
          }
        }
      }
    }
    slot_.assign(std::size_t(2) * W_ * H_, -1);
  }

  std::vector<LabelRing> run() {
    for (int j = 0; j + 1 < H_; ++j) {
      const std::uint16_t* m0 = material_.ptr<std::uint16_t>(j);
      const std::uint16_t* m1 = material_.ptr<std::uint16_t>(j + 1);
      for (int i = 0; i + 1 < W_; ++i) {
        if (m0[i] == m0[i + 1] && m0[i] == m1[i + 1] && m0[i] == m1[i]) continue;
        cell(i, j, {m0[i], m0[i + 1], m1[i + 1], m1[i]});
      }
    }
    return trace();
  }

 private:
  // Value of label L's field at padded grid node (pi, pj); zero counts as outside.
  float value(int label, int pi, int pj) const {
    if (pi <= 0 || pj <= 0 || pi >= W_ - 1 || pj >= H_ - 1) return -1.0f;
    const LabelField& f = fields_[index_[label]];
    const int x = pi - 1 - f.box.x, y = pj - 1 - f.box.y;
    if (x < 0 || y < 0 || x >= f.box.width || y >= f.box.height) return background_;
    const float v = f.field.at<float>(y, x);
    return v == 0.0f ? -1e-6f : v;
  }
  double contrast(int a, int b, int pi, int pj) const {  // f_a - f_b
    return double(value(a, pi, pj)) - double(value(b, pi, pj));
  }

  std::int32_t newPoint(const Vec2& p) {
    where_.push_back(p);
    return std::int32_t(where_.size() - 1);
  }

  // Crossing on edge k of the current cell (corners k and k+1), shared with the neighbour cell.
  std::int32_t edgePoint(int k) {
    std::int32_t& s = slot_[std::size_t(eid_[k])];
    if (s >= 0) return s;
    const int k1 = (k + 1) % 4;
    const int ia = ci_[k], ja = cj_[k], ib = ci_[k1], jb = cj_[k1];
    const int ma = m_[k], mb = m_[k1];
    double t;
    if (ma == 0 || mb == 0) {  // label | background: zero of that label's field
      const int l = ma ? ma : mb;
      const float fa = value(l, ia, ja), fb = value(l, ib, jb);
      t = fa / double(fa - fb);
    } else {  // label | label: zero of f_a - f_b
      const double da = contrast(ma, mb, ia, ja), db = contrast(ma, mb, ib, jb);
      t = da - db > 0.0 ? da / (da - db) : 0.5;
      t = std::min(std::max(t, 1e-3), 1.0 - 1e-3);
    }
    s = newPoint(Vec2(ia + t * (ib - ia) - 1.0, ja + t * (jb - ja) - 1.0));
    return s;
  }

  // Point on the background chord x -> y where f_a - f_b changes sign (a before, b after).
  std::int32_t chordPoint(std::int32_t x, std::int32_t y, int kx, int ky, int a, int b) {
    const auto along = [&](std::int32_t p, int k) {  // f_a - f_b at a crossing on edge k
      const int k1 = (k + 1) % 4;
      const double s = std::abs(where_[p].x() + 1.0 - ci_[k]) + std::abs(where_[p].y() + 1.0 - cj_[k]);
      return (1.0 - s) * contrast(a, b, ci_[k], cj_[k]) + s * contrast(a, b, ci_[k1], cj_[k1]);
    };
    const double dx = along(x, kx), dy = along(y, ky);
    double u = dx > 0.0 && dy < 0.0 ? dx / (dx - dy) : 0.5;
    u = std::min(std::max(u, 0.01), 0.99);
    const Vec2 px = where_[x], py = where_[y];
    return newPoint(px + u * (py - px));
  }

  void emit(int label, std::int32_t from, std::int32_t to) { segs_.push_back({label, from, to}); }

  // A non-background polygon of the cell: corners (cell corner indices, CCW) and, from each
  // corner to the next, either a cell edge or a background chord exit -> entry.
  struct Poly {
    int n = 0;
    int corner[4];
    bool chord[4];
    std::int32_t x[4], y[4];  // chord ends (exit, entry)
    int kx[4], ky[4];         // cell edges holding them
  };

  void cell(int i, int j, std::array<int, 4> m) {
    m_ = m;
    const int ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
    std::copy(ci, ci + 4, ci_);
    std::copy(cj, cj + 4, cj_);
    eid_[0] = 2 * (std::int64_t(j) * W_ + i);
    eid_[1] = 2 * (std::int64_t(j) * W_ + i + 1) + 1;
    eid_[2] = 2 * (std::int64_t(j + 1) * W_ + i);
    eid_[3] = 2 * (std::int64_t(j) * W_ + i) + 1;
    const bool in[4] = {m[0] != 0, m[1] != 0, m[2] != 0, m[3] != 0};
    Poly polys[2];
    int np = 0;
    if (in[0] && in[1] && in[2] && in[3]) {
      Poly& p = polys[np++];
      p.n = 4;
      for (int k = 0; k < 4; ++k) p.corner[k] = k, p.chord[k] = false;
    } else {
      struct Run { int entry, exit, n, corners[3]; } runs[2];
      int nr = 0;
      for (int k = 0; k < 4; ++k) {
        if (in[k] || !in[(k + 1) % 4]) continue;  // runs start after an entry edge
        Run& r = runs[nr++];
        r.entry = k;
        r.n = 0;
        int c = (k + 1) % 4;
        while (in[c]) r.corners[r.n++] = c, c = (c + 1) % 4;
        r.exit = (c + 3) % 4;
      }
      if (nr == 0) return;
      bool joined = false;
      if (nr == 2) {  // background saddle: isoContours' rule on F
        joined = saddleJoinsInside(fmax_.at<float>(j, i), fmax_.at<float>(j, i + 1), fmax_.at<float>(j + 1, i + 1),
                                   fmax_.at<float>(j + 1, i));
      }
      const auto addRun = [&](Poly& p, const Run& r, const Run& closeTo) {
        for (int c = 0; c < r.n; ++c) {
          const int at = p.n++;
          p.corner[at] = r.corners[c];
          p.chord[at] = c + 1 == r.n;
          if (p.chord[at]) {
            p.x[at] = edgePoint(r.exit), p.kx[at] = r.exit;
            p.y[at] = edgePoint(closeTo.entry), p.ky[at] = closeTo.entry;
          }
        }
      };
      if (joined) {
        Poly& p = polys[np++];
        addRun(p, runs[0], runs[1]);
        addRun(p, runs[1], runs[0]);
      } else {
        for (int r = 0; r < nr; ++r) addRun(polys[np++], runs[r], runs[r]);
      }
    }
    for (int k = 0; k < np; ++k) split(polys[k]);
  }

  void split(const Poly& P) {
    const int n = P.n;
    int lab[4];
    for (int c = 0; c < n; ++c) lab[c] = m_[P.corner[c]];
    std::int32_t T[4];
    bool has[4] = {false, false, false, false};
    int r = 0;
    for (int c = 0; c < n; ++c) {
      const int d = (c + 1) % n;
      if (lab[c] == lab[d]) continue;
      T[c] = P.chord[c] ? chordPoint(P.x[c], P.y[c], P.kx[c], P.ky[c], lab[c], lab[d])
                        : edgePoint(P.corner[c]);
      has[c] = true;
      ++r;
    }
    if (r == 0) {
      for (int c = 0; c < n; ++c)
        if (P.chord[c]) emit(lab[0], P.x[c], P.y[c]);
      return;
    }
    // Runs of one label between transitions: background chords along them, then the closing.
    struct Run { int label; std::int32_t entry, exit; } runs[4];
    int nr = 0;
    for (int a = 0; a < n; ++a) {
      if (!has[a]) continue;
      int b = (a + 1) % n;
      while (!has[b]) b = (b + 1) % n;
      const int L = lab[(a + 1) % n];
      if (P.chord[a]) emit(L, T[a], P.y[a]);
      for (int c = (a + 1) % n; c != b; c = (c + 1) % n)
        if (P.chord[c]) emit(L, P.x[c], P.y[c]);
      if (P.chord[b]) emit(L, P.x[b], T[b]);
      runs[nr++] = {L, T[a], T[b]};
    }
    if (nr == 2) {
      for (int k = 0; k < 2; ++k) emit(runs[k].label, runs[k].exit, runs[k].entry);
      return;
    }
    const bool repeated = nr == 4 && (runs[0].label == runs[2].label || runs[1].label == runs[3].label);
    if (!repeated) {  // three or four distinct labels meet at the mean of their transitions
      Vec2 z = Vec2::Zero();
      for (int k = 0; k < nr; ++k) z += where_[runs[k].entry];
      const std::int32_t Z = newPoint(z / nr);
      for (int k = 0; k < nr; ++k) {
        emit(runs[k].label, runs[k].exit, Z);
        emit(runs[k].label, Z, runs[k].entry);
      }
      return;
    }
    int J;  // the label joined across the cell; the other corners are cut off
    if (runs[0].label == runs[2].label && runs[1].label == runs[3].label) {
      const int A = runs[0].label, B = runs[1].label;
      double s = 0.0;
      for (int k = 0; k < 4; ++k) s += contrast(A, B, ci_[k], cj_[k]);
      J = s > 0.0 ? A : s < 0.0 ? B : std::min(A, B);
    } else {
      J = runs[0].label == runs[2].label ? runs[0].label : runs[1].label;
    }
    for (int k = 0; k < 4; ++k) {
      if (runs[k].label == J) continue;
      emit(runs[k].label, runs[k].exit, runs[k].entry);
      emit(J, runs[k].entry, runs[k].exit);
    }
  }

  std::vector<LabelRing> trace() {
    std::sort(segs_.begin(), segs_.end(), [](const LabelSegment& a, const LabelSegment& b) {
      return a.label != b.label ? a.label < b.label : a.from != b.from ? a.from < b.from : a.to < b.to;
    });
    std::vector<LabelRing> rings;
    std::vector<char> used(segs_.size(), 0);
    for (std::size_t g0 = 0; g0 < segs_.size();) {
      std::size_t g1 = g0;
      while (g1 < segs_.size() && segs_[g1].label == segs_[g0].label) ++g1;
      const auto find = [&](std::int32_t from) -> std::ptrdiff_t {
        auto it = std::lower_bound(segs_.begin() + g0, segs_.begin() + g1, from,
                                   [](const LabelSegment& s, std::int32_t f) { return s.from < f; });
        for (; it != segs_.begin() + g1 && it->from == from; ++it)
          if (!used[it - segs_.begin()]) return it - segs_.begin();
        return -1;
      };
      for (std::size_t s = g0; s < g1; ++s) {
        if (used[s]) continue;
        used[s] = 1;
        LabelRing lr;
        lr.label = segs_[s].label;
        lr.ring.push_back(where_[segs_[s].from]);
        std::int32_t cur = segs_[s].to;
        while (cur != segs_[s].from) {
          const std::ptrdiff_t nx = find(cur);
          if (nx < 0) break;  // cannot happen for a consistent partition
          used[nx] = 1;
          lr.ring.push_back(where_[cur]);
          cur = segs_[nx].to;
        }
        if (lr.ring.size() >= 3) rings.push_back(std::move(lr));
      }
      g0 = g1;
    }
    return rings;
  }

  const int W_, H_;
  const std::vector<LabelField>& fields_;
  const float background_;
  std::vector<int> index_;
  cv::Mat material_, fmax_;
  std::vector<std::int32_t> slot_;
  std::vector<Vec2> where_;
  std::vector<LabelSegment> segs_;
  // current cell
  std::array<int, 4> m_{};
  int ci_[4], cj_[4];
  std::int64_t eid_[4];
};

}  // namespace

std::vector<LabelRing> labelIsoContours(cv::Size size, const std::vector<LabelField>& fields,
                                        float background) {
  return LabelContourer(size, fields, background).run();
}

}  // namespace xsect
