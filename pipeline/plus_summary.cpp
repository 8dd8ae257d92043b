// PLUS recording summary (see plus_summary.h).
#include "pipeline/plus_summary.h"

#include "geometry/core/plane_of_pose.h"
#include "pipeline/json_values.h"

namespace xsect {

nlohmann::ordered_json plusSequenceJson(const PlusSequence& s) {
  Vec2 spacing = Vec2::Zero();
  if (!s.image_to_reference.empty()) planeOfPose(s.image_to_reference.front(), &spacing);
  Vec3 lo = Vec3::Constant(1e300), hi = -lo;
  const double w = s.header.width - 1, h = s.header.height - 1;
  for (const Mat4& m : s.image_to_reference)
    for (const Eigen::Vector4d& corner : {Eigen::Vector4d(0, 0, 0, 1), Eigen::Vector4d(w, 0, 0, 1),
                                         Eigen::Vector4d(0, h, 0, 1), Eigen::Vector4d(w, h, 0, 1)}) {
      const Vec3 p = (m * corner).head<3>();
      lo = lo.cwiseMin(p);
      hi = hi.cwiseMax(p);
    }
  nlohmann::ordered_json j;
  j["frames"] = s.header.frames;
  j["frames_used"] = s.frames.size();
  j["skipped_image_not_ok"] = s.skipped_image;
  j["skipped_transform_not_ok"] = s.skipped_transform;
  j["image_frame"] = s.image_frame;
  j["reference_frame"] = s.reference_frame;
  j["orientation"] = s.header.orientation;
  j["image_size_px"] = {s.header.width, s.header.height};
  j["pixel_spacing_mm"] = {spacing.x(), spacing.y()};
  j["field_of_view"] = !s.field_of_view.empty();
  if (!s.image_to_reference.empty()) j["extent_mm"] = {vecJson(lo), vecJson(hi)};
  return j;
}

}  // namespace xsect
