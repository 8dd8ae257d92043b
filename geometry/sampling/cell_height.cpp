// Chebyshev ball of a cell by linear programming with constraint generation (see cell_height.h).
// CGAL's QP headers stay in this file.
#include "geometry/sampling/cell_height.h"

#include <CGAL/Gmpzf.h>
#include <CGAL/QP_functions.h>
#include <CGAL/QP_models.h>

#include <cmath>
#include <stdexcept>

namespace xsect {

namespace {

/// The Chebyshev ball of the cell within [lo, hi] (bounding_planes and open left empty); height 0
/// and `feasible` false when the cell does not meet the box.
CellHeight chebyshevBall(const std::vector<Plane>& planes, const std::vector<int>& sides, const Vec3& lo,
                         const Vec3& hi, const std::vector<int>& first, bool* feasible) {
  using Program = CGAL::Quadratic_program<double>;
  using Solution = CGAL::Quadratic_program_solution<CGAL::Gmpzf>;
  // Variables x, y, z (0-2) and r (3); rows A v <= b. Maximise r: minimise -r, with r >= 0.
  Program lp(CGAL::SMALLER, false, 0, false, 0);
  lp.set_l(3, true, 0.0);
  lp.set_c(3, -1.0);
  int rows = 0;
  const auto addRow = [&](const Vec3& a, double b) {
    for (int k = 0; k < 3; ++k) lp.set_a(k, rows, a[k]);
    lp.set_a(3, rows, 1.0);
    lp.set_b(rows, b);
    ++rows;
  };
  for (int k = 0; k < 3; ++k) {  // lo_k + r <= x_k and x_k + r <= hi_k
    addRow(-Vec3::Unit(k), -lo[k]);
    addRow(Vec3::Unit(k), hi[k]);
  }
  std::vector<char> used(planes.size(), 0);
  const auto addPlane = [&](std::size_t j) {
    used[j] = 1;
    const Plane& P = planes[j];
    addRow(-double(sides[j]) * P.normal, -double(sides[j]) * P.normal.dot(P.origin));
  };
  for (const int j : first)
    if (j >= 0 && std::size_t(j) < planes.size() && !used[std::size_t(j)]) addPlane(std::size_t(j));
  CellHeight out;
  const double scale = (hi - lo).norm();
  for (;;) {
    const Solution s = CGAL::solve_linear_program(lp, CGAL::Gmpzf());
    *feasible = s.is_optimal();  // the box bounds the program: not optimal means infeasible
    if (!*feasible) return CellHeight{};
    auto v = s.variable_values_begin();
    for (int k = 0; k < 3; ++k, ++v) out.centre[k] = CGAL::to_double(*v);
    out.height = CGAL::to_double(*v);
    // The plane the ball crosses most deeply, if any (a tolerance of 1e-12 of the box for the
    // rounding of the centre to doubles); as a row: r <= σ_j (n_j · x − d_j).
    std::size_t worst = planes.size();
    double deepest = 1e-12 * scale;
    for (std::size_t j = 0; j < planes.size(); ++j) {
      if (used[j]) continue;
      const double depth = out.height - double(sides[j]) * planes[j].signedDistance(out.centre);
      if (depth > deepest) deepest = depth, worst = j;
    }
    if (worst == planes.size()) return out;
    addPlane(worst);
  }
}

}  // namespace

CellHeight cellHeight(const std::vector<Plane>& planes, const std::vector<int>& sides, const Vec3& lo,
                      const Vec3& hi, bool check_open, const std::vector<int>& first) {
  if (sides.size() != planes.size()) throw std::invalid_argument("cellHeight: one side per plane");
  if (!(lo.array() < hi.array()).all()) throw std::invalid_argument("cellHeight: empty box");
  for (const Plane& p : planes)
    if (std::abs(p.normal.norm() - 1) > 1e-9) throw std::invalid_argument("cellHeight: plane normals must be unit");
  bool feasible = false;
  CellHeight out = chebyshevBall(planes, sides, lo, hi, first, &feasible);
  const double scale = (hi - lo).norm();
  if (!feasible) {  // the cell does not meet the box: nothing is shown for it
    out.open = true;
    return out;
  }
  // Open: the box, not the planes, limits the height (the same cell in a box grown by its
  // diagonal each way has a larger ball). Unlike "the ball touches the box", this does not depend
  // on which of several largest balls the solver returns.
  if (check_open) {
    bool grown = false;
    const Vec3 d = Vec3::Constant(scale);
    out.open = chebyshevBall(planes, sides, lo - d, hi + d, first, &grown).height > out.height + 1e-9 * scale;
  }
  const double touch = 1e-9 * scale;
  for (std::size_t j = 0; j < planes.size(); ++j)
    if (std::abs(double(sides[j]) * planes[j].signedDistance(out.centre) - out.height) < touch)
      out.bounding_planes.push_back(int(j));
  return out;
}

}  // namespace xsect
