// Lattice samples of a shape's medial axis from its signed distance (see medial_axis_samples.h).
#include "geometry/evaluation/medial_axis_samples.h"

#include <tbb/parallel_for.h>

#include <cmath>
#include <stdexcept>

namespace xsect {

MedialAxisSamples medialAxisSamples(const std::function<double(const Vec3&)>& sdf, const Vec3& lo, const Vec3& hi,
                                    double spacing, double ridge, double margin) {
  if (!(spacing > 0) || !(ridge > 0 && ridge < 1)) throw std::invalid_argument("medialAxisSamples: bad parameters");
  MedialAxisSamples out;
  out.spacing_mm = spacing;
  int n[3];
  for (int a = 0; a < 3; ++a) n[a] = std::max(1, int(std::ceil((hi[a] - lo[a]) / spacing)) + 1);
  std::vector<std::vector<Vec3>> in(static_cast<std::size_t>(n[2])), ex(static_cast<std::size_t>(n[2]));
  tbb::parallel_for(0, n[2], [&](int k) {
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i) {
        const Vec3 x = lo + spacing * Vec3(i, j, k);
        const double f = sdf(x);
        if (std::abs(f) < margin) continue;
        Vec3 g;
        for (int a = 0; a < 3; ++a) {
          const Vec3 d = spacing * Vec3::Unit(a);
          g[a] = (sdf(x + d) - sdf(x - d)) / (2 * spacing);
        }
        if (g.norm() >= ridge) continue;
        (f < 0 ? in : ex)[std::size_t(k)].push_back(x);
      }
  });
  for (int k = 0; k < n[2]; ++k) {
    out.interior.insert(out.interior.end(), in[std::size_t(k)].begin(), in[std::size_t(k)].end());
    out.exterior.insert(out.exterior.end(), ex[std::size_t(k)].begin(), ex[std::size_t(k)].end());
  }
  return out;
}

}  // namespace xsect
