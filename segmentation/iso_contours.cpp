// Marching squares with oriented segments (see iso_contours.h).
#include "segmentation/iso_contours.h"

#include <cstdint>

namespace xsect {

std::vector<Ring> isoContours(const cv::Mat& field) {
  CV_Assert(field.type() == CV_32F);
  const int W = field.cols + 2, H = field.rows + 2;  // padded by one outside pixel per side
  const auto value = [&](int i, int j) -> float {    // padded coordinates
    if (i <= 0 || j <= 0 || i >= W - 1 || j >= H - 1) return -1.0f;
    const float f = field.at<float>(j - 1, i - 1);
    return f > 0.0f ? f : std::min(f, -1e-6f);  // zero counts as outside
  };
  // Crossing ids: 2*(j*W+i) for edge (i,j)-(i+1,j); 2*(j*W+i)+1 for edge (i,j)-(i,j+1).
  std::vector<std::int64_t> next(std::size_t(2) * W * H, -1);
  std::vector<Vec2> where(std::size_t(2) * W * H);
  const auto crossing = [&](int ia, int ja, int ib, int jb, std::int64_t id) {
    const float fa = value(ia, ja), fb = value(ib, jb);
    const double t = fa / double(fa - fb);
    where[id] = Vec2(ia + t * (ib - ia) - 1.0, ja + t * (jb - ja) - 1.0);
    return id;
  };
  for (int j = 0; j + 1 < H; ++j) {
    for (int i = 0; i + 1 < W; ++i) {
      // Corners counter-clockwise: c0 (i,j), c1 (i+1,j), c2 (i+1,j+1), c3 (i,j+1).
      const int ci[4] = {i, i + 1, i + 1, i}, cj[4] = {j, j, j + 1, j + 1};
      bool in[4];
      int nin = 0;
      for (int k = 0; k < 4; ++k) nin += (in[k] = value(ci[k], cj[k]) > 0.0f);
      if (nin == 0 || nin == 4) continue;
      // Edge k joins corner k and k+1; ids of the four edges of the cell.
      const std::int64_t eid[4] = {2 * (std::int64_t(j) * W + i),
                                   2 * (std::int64_t(j) * W + i + 1) + 1,
                                   2 * (std::int64_t(j + 1) * W + i),
                                   2 * (std::int64_t(j) * W + i) + 1};
      int exits[2], entries[2], ne = 0, nn = 0;  // in->out and out->in crossings, CCW order
      for (int k = 0; k < 4; ++k) {
        const int k1 = (k + 1) % 4;
        if (in[k] == in[k1]) continue;
        crossing(ci[k], cj[k], ci[k1], cj[k1], eid[k]);
        if (in[k]) exits[ne++] = k; else entries[nn++] = k;
      }
      if (ne == 1) {
        next[eid[exits[0]]] = eid[entries[0]];
        continue;
      }
      // Saddle: exits and entries alternate around the cell.
      double centre = 0;
      for (int k = 0; k < 4; ++k) centre += value(ci[k], cj[k]);
      const bool joined = centre > 0.0;  // inside corners connected through the cell
      for (int a = 0; a < 2; ++a) {
        const int e = exits[a];
        // next out->in crossing counter-clockwise after e (joined) or before e (separated)
        int best = -1;
        for (int s = 1; s < 4 && best < 0; ++s) {
          const int k = joined ? (e + s) % 4 : (e + 4 - s) % 4;
          if (k == entries[0] || k == entries[1]) best = k;
        }
        next[eid[e]] = eid[best];
      }
    }
  }
  std::vector<Ring> rings;
  std::vector<char> used(next.size(), 0);
  for (std::size_t s = 0; s < next.size(); ++s) {
    if (next[s] < 0 || used[s]) continue;
    Ring ring;
    std::int64_t c = std::int64_t(s);
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
