// The readers' side of crossing-contour repair (geometry/core/ring_repair.h): its refusal, rings
// that doubles cannot hold once repaired, as an InputError naming the file, place and line.
#pragma once

#include <stdexcept>
#include <string>
#include <vector>

#include "geometry/core/ring_repair.h"
#include "io/input_error.h"

namespace xsect {

inline RingRepair repairedOrRefused(const std::vector<Ring>& outers, const std::vector<Ring>& holes,
                                    const std::string& file, const std::string& where, int line) {
  try {
    return repairRings(outers, holes);
  } catch (const std::invalid_argument& e) {
    throw InputError(file, where, e.what(), line);
  }
}

}  // namespace xsect
