// The data of report.html's 3D view (issue 21; drawn by report/page/report_page.js): the mesh,
// decimated for the browser, with the sampling verdict of the cell (thesis ch. 1 §4.4-4.5, ch. 2
// §3; report.json sampling.cells) and the material label at each vertex; the
// slices' observed rectangles (the flagged ones marked) and their sections' contours, in world mm.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>

#include "pipeline/run_outputs.h"

namespace xsect {

/// What the view may hold, so that the page stays light whatever the run's size.
struct ViewBudget {
  std::size_t triangles = 150000;        ///< the mesh is decimated above this (a 1 M-triangle mesh: ~5 MB page)
  std::size_t slices = 300;              ///< evenly chosen among the planes above this
  std::size_t contour_points = 60000;    ///< contour vertices drawn, over all slices drawn (~2 MB)
};

/// The view's JSON (report_page.js reads it): typed arrays as little-endian base64.
nlohmann::ordered_json viewDataJson(const RunResults& r, const ViewBudget& budget = {});

}  // namespace xsect
