// The upper median of a list of values (the middle value, or the higher of the two middle ones):
// one home for the robust "typical value" of pose smoothing, the automatic end margin and the
// automatic voxel size. (conform_stage.cpp reports the classic median, the mean of the two.)
#pragma once

#include <algorithm>
#include <vector>

namespace xsect {

/// Upper median of `values`; 0 for none.
inline double upperMedian(std::vector<double> values) {
  if (values.empty()) return 0;
  std::nth_element(values.begin(), values.begin() + std::ptrdiff_t(values.size() / 2), values.end());
  return values[values.size() / 2];
}

}  // namespace xsect
