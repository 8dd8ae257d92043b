// Marching squares with oriented segments (see iso_contours.h). The field is padded by one
// outside pixel (so every contour closes), cells whose four corners agree are skipped with one
// comparison, and crossings live in compact arrays indexed through a per-edge slot table.
#include "segmentation/iso_contours.h"

#include <opencv2/core.hpp>

#include <cstdint>

namespace xsect {

std::vector<Ring> isoContours(const cv::Mat& field) {
  CV_Assert(field.type() == CV_32F);
  cv::Mat f;
  cv::copyMakeBorder(field, f, 1, 1, 1, 1, cv::BORDER_CONSTANT, cv::Scalar(-1.0f));
  const int W = f.cols, H = f.rows;
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
    where.emplace_back(ia + t * (ib - ia) - 1.0, ja + t * (jb - ja) - 1.0);
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
      const double centre = double(f.at<float>(j, i)) + f.at<float>(j, i + 1) +
                            f.at<float>(j + 1, i + 1) + f.at<float>(j + 1, i);
      const bool joined = centre > 0.0;  // inside corners connected through the cell
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

}  // namespace xsect
