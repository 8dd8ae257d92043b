// slices.yaml (docs/inputs.md): a list of slices, each an image, its 4x4
// image_to_world pose (pixel (i, j, 0, 1) -> mm) and an optional field-of-view mask.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "geometry/core/types.h"

namespace xsect {

struct SliceRecord {
  std::string image;               ///< path as written in the file (relative to the file)
  std::string image_resolved;      ///< absolute path, resolved against the file's folder
  Mat4 image_to_world = Mat4::Identity();
  std::optional<std::string> fov;  ///< as written
  std::optional<std::string> fov_resolved;
};

/// Reads and validates slices.yaml. Throws InputError naming the file, the key
/// (e.g. "slices[3].image_to_world") and line for: missing keys, wrong types, a matrix that is
/// not 4x4, non-finite numbers, a last row other than (0 0 0 1), zero or non-orthogonal pixel
/// axes, a missing image file. Unknown keys (other tools may add their own) are warned about.
std::vector<SliceRecord> readSlicesFile(const std::string& path,
                                        std::vector<std::string>* warnings = nullptr);

/// A planned slice (advice.yaml, or the planes given to `xsect slice`): a pose without an image.
struct PoseRecord {
  Mat4 image_to_world = Mat4::Identity();
  int width = 0, height = 0;  ///< image size in pixels when given (0: not given)
};

/// Reads a list `slices:` of entries with `image_to_world` (validated as in readSlicesFile) and
/// optional `width`, `height` (pixels, >= 1); an `image` key, if any, is ignored. Throws
/// InputError naming the file, key and line.
std::vector<PoseRecord> readPosesFile(const std::string& path);

/// Writes a poses file that readPosesFile reads back: `header` and each entry's `notes[i]` (if
/// given) as YAML comments (one line each).
void writePosesFile(const std::string& path, const std::vector<PoseRecord>& poses, const std::string& header,
                    const std::vector<std::string>& notes = {});

/// Writes slices.yaml with paths exactly as given in SliceRecord::image / fov.
void writeSlicesFile(const std::string& path, const std::vector<SliceRecord>& slices);

}  // namespace xsect
