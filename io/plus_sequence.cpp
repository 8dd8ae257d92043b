// PLUS recordings as slices (see plus_sequence.h).
#include "io/plus_sequence.h"

#include <algorithm>
#include <map>

#include "io/input_error.h"

namespace xsect {

namespace {

/// The transforms' names, for a message.
std::string transformList(const std::vector<PlusTransform>& ts) {
  std::string s;
  for (const PlusTransform& t : ts) s += (s.empty() ? "" : ", ") + t.from + "To" + t.to;
  return s;
}

}  // namespace

PlusSequence readPlusSequence(const std::string& sequencePath, const std::string& deviceSetPath,
                              const std::string& referenceFrame) {
  PlusSequence s;
  s.header = readMetaImageHeader(sequencePath);
  s.device_set = readPlusDeviceSet(deviceSetPath);
  if (!s.device_set.image_frame.empty()) s.image_frame = s.device_set.image_frame;
  if (!referenceFrame.empty()) s.reference_frame = referenceFrame;
  else if (!s.device_set.reference_frame.empty()) s.reference_frame = s.device_set.reference_frame;
  const MetaImageHeader& h = s.header;

  // The tracked transforms: every per-frame <A>To<B>Transform of the file.
  struct Tracked {
    std::string field, from, to;
  };
  std::vector<Tracked> tracked;
  for (const std::string& name : frameTransformNames(h)) {
    const auto parts = splitTransformName(name);
    if (!parts) continue;  // not a transform name PLUS would chain
    tracked.push_back({name, parts->first, parts->second});
  }
  const std::vector<PlusTransform>& chain = s.device_set.transforms;
  const std::size_t statics = chain.size();

  for (int f = 0; f < h.frames; ++f) {
    if (!frameStatusOk(h, f, "ImageStatus")) {
      ++s.skipped_image;
      continue;
    }
    // Every transform of the frame (`all`), and those whose status is OK (`valid`).
    std::vector<PlusTransform> valid(chain.begin(), chain.begin() + std::ptrdiff_t(statics)), all = valid;
    for (const Tracked& t : tracked) {
      const std::optional<Mat4> m = frameMatrix(h, f, t.field);
      if (!m)
        throw InputError(h.path, frameFieldKey(f, t.field),
                         "missing: the frame has no " + t.field + " while other frames do", -1);
      if ((m->row(3) - Eigen::RowVector4d(0, 0, 0, 1)).cwiseAbs().maxCoeff() > 1e-6 &&
          frameStatusOk(h, f, t.field + "Status"))
        throw InputError(h.path, frameFieldKey(f, t.field), "last row must be 0 0 0 1 (an affine transform)",
                         h.line(frameFieldKey(f, t.field)));
      all.push_back({t.from, t.to, *m});
      if (frameStatusOk(h, f, t.field + "Status")) valid.push_back(all.back());
    }
    // No chain even through the invalid transforms: the inputs cannot place any frame (an error).
    // A chain that needs an invalid one: this frame is skipped (tracking was lost).
    if (!chainTransform(all, s.image_frame, s.reference_frame))
      throw InputError(s.device_set.path, "CoordinateDefinitions",
                       "no chain of transforms from " + s.image_frame + " to " + s.reference_frame +
                           " (input.reference_frame); available: " + transformList(all));
    std::optional<Mat4> pose = chainTransform(valid, s.image_frame, s.reference_frame);
    if (!pose) {
      ++s.skipped_transform;
      continue;
    }
    const Vec3 c0 = pose->block<3, 1>(0, 0), c1 = pose->block<3, 1>(0, 1);
    if (!(c0.norm() > 1e-12 && c1.norm() > 1e-12) || c0.cross(c1).norm() < 1e-9 * c0.norm() * c1.norm())
      throw InputError(h.path, frameFieldKey(f, "ImageToReferenceTransform"),
                       "the chained " + s.image_frame + " to " + s.reference_frame + " transform of frame " +
                           std::to_string(f) + " (" + transformList(valid) +
                           ") has zero or parallel pixel axes (a calibration without the pixel spacing?)");
    s.frames.push_back(f);
    s.image_to_reference.push_back(*pose);
  }
  if (s.frames.empty())
    throw InputError(h.path, "", "no frame has an OK image and OK transforms (" + std::to_string(s.skipped_image) +
                                     " image(s) and " + std::to_string(s.skipped_transform) +
                                     " transform(s) not OK)");
  s.field_of_view = plusFieldOfView(s.device_set, h.width, h.height);
  return s;
}

MetaImageHeader readPlusMasks(const std::string& path, const PlusSequence& s) {
  MetaImageHeader m = readMetaImageHeader(path);
  const MetaImageHeader& h = s.header;
  if (m.width != h.width || m.height != h.height || m.frames != h.frames)
    throw InputError(path, "DimSize",
                     "the masks are " + std::to_string(m.width) + " x " + std::to_string(m.height) + " x " +
                         std::to_string(m.frames) + " while the recording " + h.path + " is " + std::to_string(h.width) +
                         " x " + std::to_string(h.height) + " x " + std::to_string(h.frames) +
                         ": input.plus_masks needs one mask per frame, of the frame's size",
                     m.line("DimSize"));
  for (int f = 0; f < h.frames; ++f) {
    const std::optional<double> a = frameNumber(m, f, "Timestamp"), b = frameNumber(h, f, "Timestamp");
    if (a && b && std::abs(*a - *b) > 1e-3)
      throw InputError(path, frameFieldKey(f, "Timestamp"),
                       "mask frame " + std::to_string(f) + " is at " + std::to_string(*a) + " s, the recording's frame " +
                           std::to_string(f) + " at " + std::to_string(*b) +
                           " s: the masks are not the recording's frames in order",
                       m.line(frameFieldKey(f, "Timestamp")));
  }
  if (m.orientation.empty()) {
    m.flip_columns = h.flip_columns;
    m.flip_rows = h.flip_rows;
  }
  return m;
}

cv::Mat orientedMask(const PlusSequence& s, const cv::Mat& pixels) {
  const bool fc = s.masks->flip_columns, fr = s.masks->flip_rows;
  if (!fc && !fr) return pixels;
  cv::Mat out;
  cv::flip(pixels, out, fc && fr ? -1 : (fc ? 1 : 0));
  return out;
}

cv::Mat orientedFrame(const PlusSequence& s, const cv::Mat& pixels) {
  const bool fc = s.header.flip_columns, fr = s.header.flip_rows;
  if (!fc && !fr) return pixels;
  cv::Mat out;
  cv::flip(pixels, out, fc && fr ? -1 : (fc ? 1 : 0));
  return out;
}

}  // namespace xsect
