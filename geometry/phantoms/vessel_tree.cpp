// Growth of the vessel-tree phantom, its blended signed distance, nearest boundary points and
// reach bounds (see vessel_tree.h).
#include "geometry/phantoms/vessel_tree.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "geometry/core/random_streams.h"
#include "geometry/phantoms/implicit_surface.h"

namespace xsect {
namespace {

using Tube = PhantomShape::Tube;
using Junction = PhantomShape::Junction;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr double kPhi0 = 3.0 / 16.0;  // phi(0): the largest drop of one smooth minimum, / k

double blendOf(const PhantomShape& s) {
  const auto it = s.params.find("blend_mm");
  return it == s.params.end() ? 0.0 : it->second;
}

/// phi(t) = (1 - t)^3 (3 + t) / 16 on [0, 1]: phi(1) = phi'(1) = phi''(1) = 0, phi'(0) = -1/2.
double phi(double t) {
  const double u = 1.0 - t;
  return u * u * u * (3.0 + t) / 16.0;
}

double pointSegment(const Vec3& p, const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  const double l2 = d.squaredNorm();
  const double s = l2 > 0 ? std::clamp((p - a).dot(d) / l2, 0.0, 1.0) : 0.0;
  return (a + s * d - p).norm();
}

double capsuleValue(const Tube& t, const Vec3& q) { return pointSegment(q, t.a, t.b) - t.radius; }

/// A unit vector orthogonal to d (d non-zero).
Vec3 anyOrthogonal(const Vec3& d) {
  const Vec3 o = std::abs(d.x()) < 0.9 * d.norm() ? Vec3::UnitX() : Vec3::UnitY();
  return d.cross(o).normalized();
}

/// Capsule signed distance with its exact gradient and Hessian: with p the nearest axis point,
/// rho = |q - p| and n = (q - p) / rho, grad = n and H = (I - n n^T - [e e^T]) / rho, the
/// bracket (axis direction e) only beside the segment (on the caps the level sets are spheres).
SdfJet capsuleJet(const Tube& t, const Vec3& q, bool hessian) {
  const Vec3 d = t.b - t.a;
  const double l2 = d.squaredNorm();
  const double raw = l2 > 0 ? (q - t.a).dot(d) / l2 : 0.0;
  const double s = std::clamp(raw, 0.0, 1.0);
  const Vec3 w = q - (t.a + s * d);
  const double rho = w.norm();
  SdfJet j;
  j.value = rho - t.radius;
  if (rho < 1e-12) {  // on the axis: deep inside, any direction
    j.gradient = l2 > 0 ? anyOrthogonal(d) : Vec3::UnitX();
    return j;
  }
  const Vec3 n = w / rho;
  j.gradient = n;
  if (hessian) {
    j.hessian = (Eigen::Matrix3d::Identity() - n * n.transpose()) / rho;
    if (raw > 0 && raw < 1) {
      const Vec3 e = d / std::sqrt(l2);
      j.hessian -= e * e.transpose() / rho;
    }
  }
  return j;
}

/// S_k of two jets: S = (a + b)/2 - g(b - a), g(s) = |s|/2 + k phi(|s|/k), so
/// dS/da = 1/2 + g'(s), dS/db = 1/2 - g'(s) and the Hessian gains -g''(s) (grad a - grad b)^2.
SdfJet smoothMinJet(const SdfJet& a, const SdfJet& b, double k, bool hessian) {
  const double s = b.value - a.value;
  if (k <= 0 || std::abs(s) >= k) return s >= 0 ? a : b;
  const double t = std::abs(s) / k;
  const double gp = (s >= 0 ? 1.0 : -1.0) * 0.75 * (t - t * t * t / 3.0);
  const double wa = 0.5 + gp, wb = 0.5 - gp;
  SdfJet r;
  r.value = std::min(a.value, b.value) - k * phi(t);
  r.gradient = wa * a.gradient + wb * b.gradient;
  if (hessian) {
    const double gpp = 0.75 / k * (1.0 - t * t);
    const Vec3 dg = a.gradient - b.gradient;
    r.hessian = wa * a.hessian + wb * b.hessian - gpp * dg * dg.transpose();
  }
  return r;
}

double junctionOffset(const Junction& J, double k) { return double(J.children.size()) * kPhi0 * k; }

/// f restricted to a subset of the junctions (exact wherever the others are positive: every
/// junction value is >= the distance to its nearest capsule minus its offset).
class TreeField {
 public:
  /// Every junction (no allocation: evaluated once per pixel when rendering).
  explicit TreeField(const PhantomShape& s) : s_(s), k_(blendOf(s)), all_(true) {}
  TreeField(const PhantomShape& s, std::vector<int> use)
      : s_(s), k_(blendOf(s)), all_(false), use_(std::move(use)) {}
  std::size_t size() const { return all_ ? s_.junctions.size() : use_.size(); }
  const Junction& junction(std::size_t i) const { return s_.junctions[all_ ? i : use_[i]]; }

  double value(const Vec3& q) const {
    if (s_.junctions.empty()) {  // not linked (a shape built by hand): the union of capsules
      double d = kInf;
      for (const auto& t : s_.tubes) d = std::min(d, capsuleValue(t, q));
      return d;
    }
    double f = kInf;
    for (std::size_t ji = 0; ji < size(); ++ji) {
      const Junction& J = junction(ji);
      double b = capsuleValue(s_.tubes[J.parent], q);
      if (!J.children.empty()) {
        double c = capsuleValue(s_.tubes[J.children[0]], q);
        for (std::size_t i = 1; i < J.children.size(); ++i)
          c = smoothMin(c, capsuleValue(s_.tubes[J.children[i]], q), k_);
        b = smoothMin(b, c, k_);
      }
      f = std::min(f, b);
    }
    return f;
  }

  SdfJet jet(const Vec3& q, bool hessian) const {
    SdfJet best;
    best.value = kInf;
    if (s_.junctions.empty()) {
      for (const auto& t : s_.tubes) {
        const SdfJet j = capsuleJet(t, q, hessian);
        if (j.value < best.value) best = j;
      }
      return best;
    }
    for (std::size_t ji = 0; ji < size(); ++ji) {
      const Junction& J = junction(ji);
      SdfJet b = capsuleJet(s_.tubes[J.parent], q, hessian);
      if (!J.children.empty()) {
        SdfJet c = capsuleJet(s_.tubes[J.children[0]], q, hessian);
        for (std::size_t i = 1; i < J.children.size(); ++i)
          c = smoothMinJet(c, capsuleJet(s_.tubes[J.children[i]], q, hessian), k_, hessian);
        b = smoothMinJet(b, c, k_, hessian);
      }
      if (b.value < best.value) best = b;
    }
    return best;
  }

 private:
  const PhantomShape& s_;
  double k_;
  bool all_;
  std::vector<int> use_;
};

/// The tree's field as geometry/phantoms/implicit_surface.h reads it: one jet per point, kept for
/// the gradient that follows the value (a fresh one per call: the field is shared across threads).
class TreeSurface {
 public:
  explicit TreeSurface(const TreeField& F) : F_(F) {}
  double value(const Vec3& x) const { return jetAt(x).value; }
  Vec3 gradient(const Vec3& x) const { return jetAt(x).gradient; }
  double check(const Vec3& x) const { return F_.value(x); }

 private:
  const SdfJet& jetAt(const Vec3& x) const {
    if (!has_ || x != at_) {
      jet_ = F_.jet(x, false);
      at_ = x;
      has_ = true;
    }
    return jet_;
  }
  const TreeField& F_;
  mutable SdfJet jet_;
  mutable Vec3 at_ = Vec3::Zero();
  mutable bool has_ = false;
};

constexpr ImplicitSurfaceSteps kTreeSteps{1e-12, 1e-9, 300, 1e-14};

/// Newton steps x <- x - f grad f / |grad f|^2 onto f = 0. False when it does not converge.
bool projectToSurface(const TreeField& F, const Vec3& x, Vec3* out) {
  return projectOntoSurface(TreeSurface(F), x, kTreeSteps, out);
}

/// From p on the surface, a local minimum of |x - q| over the surface (implicit_surface.h).
Vec3 descendOnTree(const TreeField& F, const Vec3& q, const Vec3& p) {
  return descendToNearest(TreeSurface(F), q, p, kTreeSteps);
}

/// Nearest point of a capsule's surface to q.
Vec3 capsuleSurfacePoint(const Tube& t, const Vec3& q) {
  const Vec3 d = t.b - t.a;
  const double l2 = d.squaredNorm();
  const double s = l2 > 0 ? std::clamp((q - t.a).dot(d) / l2, 0.0, 1.0) : 0.0;
  const Vec3 p = t.a + s * d;
  Vec3 w = q - p;
  if (w.norm() < 1e-12) w = l2 > 0 ? anyOrthogonal(d) : Vec3::UnitX();
  return p + t.radius * w.normalized();
}

/// Principal curvatures (convex positive) of the level set through a jet's point.
void principalCurvatures(const SdfJet& j, double* k1, double* k2) {
  const double gn = j.gradient.norm();
  const Vec3 n = j.gradient / gn;
  const Vec3 t1 = anyOrthogonal(n), t2 = n.cross(t1);
  const double a = t1.dot(j.hessian * t1) / gn, b = t1.dot(j.hessian * t2) / gn,
               d = t2.dot(j.hessian * t2) / gn;
  const double m = 0.5 * (a + d), r = std::hypot(0.5 * (a - d), b);
  *k1 = m - r;
  *k2 = m + r;
}

struct CurvatureMax {
  double convex = 0.0, concave = 0.0;
};

/// Convex (side 0) or concave (side 1) curvature of the boundary at p (on it); inf where the
/// gradient vanishes (a singular point).
double sideCurvature(const TreeField& F, const Vec3& p, int side) {
  const SdfJet j = F.jet(p, true);
  if (!(j.gradient.norm() > 1e-9)) return kInf;
  double k1, k2;
  principalCurvatures(j, &k1, &k2);
  return side == 0 ? std::max(0.0, k2) : std::max(0.0, -k1);
}

/// Local maximum of one side's curvature over the boundary near p: pattern search along eight
/// tangent directions with steps from h down to h / 128.
double refineCurvatureMax(const TreeField& F, Vec3 p, int side, double h, const Vec3& c,
                          double R) {
  double best = sideCurvature(F, p, side);
  for (double step = h; step > h / 128 && std::isfinite(best);) {
    const SdfJet j = F.jet(p, false);
    const Vec3 n = j.gradient.normalized(), t1 = anyOrthogonal(n), t2 = n.cross(t1);
    bool moved = false;
    for (int d = 0; d < 8 && !moved; ++d) {
      const double a = M_PI / 4 * d;
      Vec3 q;
      if (!projectToSurface(F, p + step * (std::cos(a) * t1 + std::sin(a) * t2), &q) ||
          (q - c).norm() > R)
        continue;
      const double k = sideCurvature(F, q, side);
      if (k > best) {
        best = k;
        p = q;
        moved = true;
      }
    }
    if (!moved) step *= 0.5;
  }
  return best;
}

/// A tube meeting at a junction point c: its direction away from c, its length from c, its
/// radius, and how far along it the blends can act (sampleJunctionCurvature).
struct JunctionMember {
  int tube;
  Vec3 e;
  double length, radius, extent;
};

/// Where the junction's surface is sampled from: rings around each member up to its extent, on
/// its tube and dJ beyond, a step h apart, and a sphere of radius rmax + dJ / 2 around c
/// (Fibonacci lattice).
std::vector<Vec3> junctionSampleStarts(const std::vector<JunctionMember>& members, const Vec3& c, double dJ,
                                       double rmax, double h) {
  std::vector<Vec3> starts;
  for (const auto& u : members) {
    const Vec3 f1 = anyOrthogonal(u.e), f2 = u.e.cross(f1);
    const int nTheta = std::max(16, int(std::ceil(2 * M_PI * (u.radius + dJ) / h)));
    for (double sa = 0.0; sa <= u.extent + 1e-12; sa += h)
      for (int a = 0; a < nTheta; ++a) {
        const double th = 2 * M_PI * a / nTheta;
        const Vec3 radial = std::cos(th) * f1 + std::sin(th) * f2;
        for (const double o : {0.0, dJ}) starts.push_back(c + sa * u.e + (u.radius + o) * radial);
      }
  }
  const double rs = rmax + 0.5 * dJ;
  const int nSphere = std::max(64, int(std::ceil(4 * M_PI * rs * rs / (h * h))));
  const double golden = M_PI * (3.0 - std::sqrt(5.0));
  for (int i = 0; i < nSphere; ++i) {
    const double z = 1.0 - 2.0 * (i + 0.5) / nSphere, rr = std::sqrt(1.0 - z * z);
    starts.push_back(c + rs * Vec3(rr * std::cos(golden * i), rr * std::sin(golden * i), z));
  }
  return starts;
}

/// The largest convex and concave principal curvatures of the boundary around junction ji:
/// a coarse pass over the projections onto f = 0 of start points (rings around every member
/// tube, and offset outwards by the blend offset, along the stretch where a blend can be active;
/// a sphere around the junction point) at spacing h, then a local maximisation from the 12
/// largest values of each side.
/// The start points are bounded: h grows past the requested spacing when the sampled area would
/// need more than `budget` of them (vesselTreeReach's share of kTreeStartBudget; a fillet much
/// thinner than the tubes, e.g. blend_mm = 0.001 on 0.6 mm tubes, asked for 10^8 starts and 28 s),
/// and the scan for where the blends stop uses at most 1024 steps per tube. Above that bound the
/// coarse pass may land farther from a curvature peak; the local maximisation
/// (refineCurvatureMax, down to h / 128) still climbs to it from the best starts.
CurvatureMax sampleJunctionCurvature(const PhantomShape& s, int ji, double h, double budget) {
  const double k = blendOf(s);
  const Junction& J = s.junctions[ji];
  const Vec3 c = s.tubes[J.parent].b;
  const double dJ = junctionOffset(J, k);
  std::vector<JunctionMember> members;
  auto addMember = [&](int ti, const Vec3& far) {
    const Tube& t = s.tubes[ti];
    const double L = (far - c).norm();
    members.push_back({ti, L > 0 ? Vec3((far - c) / L) : Vec3::UnitZ(), L, t.radius, L});
  };
  addMember(J.parent, s.tubes[J.parent].a);
  for (const int ci : J.children) addMember(ci, s.tubes[ci].b);
  // Along each member, the blends are inactive beyond the point from which its capsule keeps a
  // gap >= k + 2 dJ to every other member: sample up to there, plus k.
  double rmax = 0.0;
  for (auto& u : members) {
    rmax = std::max(rmax, u.radius);
    double clearFrom = u.length;
    const double scanStep = std::max(h, u.length / 1024);
    for (double sa = 0.0; sa <= u.length; sa += scanStep) {
      bool clear = true;
      for (const auto& v : members) {
        if (v.tube == u.tube) continue;
        const Tube& tv = s.tubes[v.tube];
        if (segmentDistance(c + sa * u.e, c + u.length * u.e, tv.a, tv.b) - u.radius - v.radius <
            k + 2 * dJ) {
          clear = false;
          break;
        }
      }
      if (clear) {
        clearFrom = sa;
        break;
      }
    }
    u.extent = std::min(u.length, clearFrom + k);
  }
  double area = 4 * M_PI * (rmax + 0.5 * dJ) * (rmax + 0.5 * dJ);
  for (const auto& u : members) area += 2 * u.extent * 2 * M_PI * (u.radius + dJ);
  h = std::max(h, std::sqrt(area / budget));
  double R = 0.0;
  for (const auto& u : members) R = std::max(R, std::hypot(u.extent, u.radius + dJ));
  R += dJ + h;
  // Junctions that can matter within R of c (the others are > 0 there).
  std::vector<int> use;
  for (std::size_t gi = 0; gi < s.junctions.size(); ++gi) {
    const Junction& G = s.junctions[gi];
    double near = pointSegment(c, s.tubes[G.parent].a, s.tubes[G.parent].b) -
                  s.tubes[G.parent].radius;
    for (const int ci : G.children)
      near = std::min(near, pointSegment(c, s.tubes[ci].a, s.tubes[ci].b) - s.tubes[ci].radius);
    if (near <= R + junctionOffset(G, k) + 1e-3) use.push_back(int(gi));
  }
  const TreeField F(s, use);

  const std::vector<Vec3> starts = junctionSampleStarts(members, c, dJ, rmax, h);
  std::vector<Vec3> points(starts.size());
  std::vector<char> ok(starts.size(), 0);
  std::vector<double> curv[2] = {std::vector<double>(starts.size(), -1.0),
                                 std::vector<double>(starts.size(), -1.0)};
  tbb::parallel_for(std::size_t(0), starts.size(), [&](std::size_t i) {
    Vec3 p;
    if (!projectToSurface(F, starts[i], &p) || (p - c).norm() > R) return;
    ok[i] = 1;
    points[i] = p;
    curv[0][i] = sideCurvature(F, p, 0);
    curv[1][i] = sideCurvature(F, p, 1);
  });
  CurvatureMax out;
  double* result[2] = {&out.convex, &out.concave};
  for (int side = 0; side < 2; ++side) {
    std::vector<std::size_t> order;
    for (std::size_t i = 0; i < starts.size(); ++i)
      if (ok[i]) order.push_back(i);
    const std::size_t top = std::min<std::size_t>(12, order.size());
    std::partial_sort(order.begin(), order.begin() + top, order.end(),
                      [&](std::size_t a, std::size_t b) {
                        const double ca = curv[side][a], cb = curv[side][b];
                        return ca > cb || (ca == cb && a < b);
                      });
    std::vector<double> refined(top, 0.0);
    tbb::parallel_for(std::size_t(0), top, [&](std::size_t t) {
      refined[t] = refineCurvatureMax(F, points[order[t]], side, h, c, R);
    });
    for (std::size_t t = 0; t < top; ++t)
      *result[side] = std::max({*result[side], curv[side][order[t]], refined[t]});
  }
  return out;
}

}  // namespace

double segmentDistance(const Vec3& a0, const Vec3& a1, const Vec3& b0, const Vec3& b1) {
  // Minimise |a0 + s da - b0 - t db| over [0,1]^2: the minimum is either interior (solve the 2x2
  // normal equations) or on one of the four edges (point-to-segment distances).
  const Vec3 da = a1 - a0, db = b1 - b0, r = a0 - b0;
  double best = std::min({pointSegment(a0, b0, b1), pointSegment(a1, b0, b1),
                          pointSegment(b0, a0, a1), pointSegment(b1, a0, a1)});
  const double a = da.squaredNorm(), b = da.dot(db), c = db.squaredNorm();
  const double d = da.dot(r), e = db.dot(r);
  const double den = a * c - b * b;
  if (den > 1e-12 * a * c) {
    const double s = (b * e - c * d) / den, t = (a * e - b * d) / den;
    if (s > 0 && s < 1 && t > 0 && t < 1) best = std::min(best, (r + s * da - t * db).norm());
  }
  return best;
}

std::vector<PhantomShape::Tube> growVesselTree(const VesselTreeParams& p) {
  struct Node {
    PhantomShape::Tube tube;
    int parent;
    double length;
  };
  std::vector<Node> nodes{{{Vec3::Zero(), Vec3(0, 0, p.length), p.radius}, -1, p.length}};
  const double alpha = p.branch_angle_deg * M_PI / 180.0;
  std::mt19937_64 rng = makeStream(p.seed, 0x7472656555ULL /* "treeU" */, 0);
  std::vector<int> tips{0};
  auto adjacent = [&](int i, int j) {
    return nodes[i].parent == j || nodes[j].parent == i ||
           (nodes[i].parent >= 0 && nodes[i].parent == nodes[j].parent);
  };
  auto clear = [&](int i) {
    for (int j = 0; j < int(nodes.size()); ++j) {
      if (j == i || adjacent(i, j)) continue;
      const auto& a = nodes[i].tube;
      const auto& b = nodes[j].tube;
      const double need =
          a.radius + b.radius + std::max(0.5 * std::min(a.radius, b.radius), 3.0 * p.blend_mm);
      if (segmentDistance(a.a, a.b, b.a, b.b) <= need) return false;
    }
    return true;
  };
  for (int level = 0; level < p.levels; ++level) {
    std::vector<int> next;
    for (const int tip : tips) {
      const Node parent = nodes[tip];
      bool placed = false;
      for (int attempt = 0; attempt < 256 && !placed; ++attempt) {
        const double phi = uniform(rng, 0.0, 2.0 * M_PI);
        const double len = parent.length * p.length_ratio;
        const double rad = parent.tube.radius * p.radius_ratio;
        const std::size_t first = nodes.size();
        for (int side = 0; side < 2; ++side) {
          const double az = phi + side * M_PI;
          const Vec3 dir(std::sin(alpha) * std::cos(az), std::sin(alpha) * std::sin(az),
                         std::cos(alpha));
          nodes.push_back({{parent.tube.b, parent.tube.b + len * dir, rad}, tip, len});
        }
        placed = clear(int(first)) && clear(int(first) + 1);
        if (!placed) {
          nodes.resize(first);
        } else {
          next.push_back(int(first));
          next.push_back(int(first) + 1);
        }
      }
      if (!placed)
        throw std::runtime_error(
            "vessel_tree: cannot grow branches without contact; reduce levels, radius or "
            "blend_mm, or increase length or branch_angle_deg");
    }
    tips = next;
  }
  std::vector<PhantomShape::Tube> out;
  out.reserve(nodes.size());
  for (const auto& n : nodes) out.push_back(n.tube);
  return out;
}

std::vector<PhantomShape::Junction> linkVesselJunctions(
    const std::vector<PhantomShape::Tube>& tubes) {
  const int n = int(tubes.size());
  std::vector<std::vector<int>> children(n);
  std::vector<char> isChild(n, 0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (i != j && tubes[j].a == tubes[i].b) {
        children[i].push_back(j);
        isChild[j] = 1;
        break;  // one parent per tube
      }
  std::vector<Junction> out;
  for (int i = 0; i < n; ++i)
    if (!children[i].empty() || !isChild[i]) out.push_back({i, children[i]});
  return out;
}

double smoothMin(double a, double b, double k) {
  const double s = std::abs(a - b);
  if (k <= 0 || s >= k) return std::min(a, b);
  return std::min(a, b) - k * phi(s / k);
}

double vesselBlendOffset(const PhantomShape& shape) {
  const double k = blendOf(shape);
  double d = 0.0;
  for (const auto& J : shape.junctions) d = std::max(d, junctionOffset(J, k));
  return d;
}

double vesselTreeSdf(const PhantomShape& shape, const Vec3& q) { return TreeField(shape).value(q); }

SdfJet vesselTreeJet(const PhantomShape& shape, const Vec3& q) {
  return TreeField(shape).jet(q, true);
}

Vec3 vesselTreeClosestPoint(const PhantomShape& shape, const Vec3& q) {
  const TreeField all(shape);
  const double delta = vesselBlendOffset(shape);
  std::vector<Vec3> starts;
  double best = kInf;
  Vec3 p;
  if (projectToSurface(all, q, &p)) {
    starts.push_back(p);
    best = (q - p).norm();
  }
  // The nearest boundary point lies within delta of some capsule i, which then has
  // d_i(q) <= best + delta: start from the nearest surface point of each such capsule.
  const double bound = best + delta;
  std::vector<double> d(shape.tubes.size());
  for (std::size_t i = 0; i < shape.tubes.size(); ++i) d[i] = capsuleValue(shape.tubes[i], q);
  for (std::size_t i = 0; i < shape.tubes.size(); ++i)
    if (d[i] <= bound && projectToSurface(all, capsuleSurfacePoint(shape.tubes[i], q), &p)) {
      starts.push_back(p);
      best = std::min(best, (q - p).norm());
    }
  if (starts.empty()) return q;
  // Within the ball of radius best + delta around q only junctions with a capsule closer than
  // best + 2 delta matter (the others are positive there).
  std::vector<int> use;
  for (std::size_t ji = 0; ji < shape.junctions.size(); ++ji) {
    const auto& J = shape.junctions[ji];
    bool near = d[J.parent] <= best + 2 * delta + 1e-6;
    for (const int ci : J.children) near = near || d[ci] <= best + 2 * delta + 1e-6;
    if (near) use.push_back(int(ji));
  }
  const TreeField local = shape.junctions.empty() ? all : TreeField(shape, use);
  Vec3 out = starts.front();
  double outDist = kInf;
  for (const Vec3& s : starts) {
    const Vec3 c = descendOnTree(local, q, s);
    const double dc = (q - c).norm();
    if (dc < outDist) {
      outDist = dc;
      out = c;
    }
  }
  return out;
}

// Reach bounds. reach_i (inner medial axis) and reach_e (outer) of a C^{1,1} boundary are each the
// smaller of (a) the radius of its largest principal curvature of that side (convex for reach_i,
// concave for reach_e) and (b) half its shortest bottleneck on that side (a segment through the
// inside, resp. the outside, normal to the boundary at both ends; Aamari et al. 2019, "Estimating
// the reach of a manifold", Thm 3.4, applied to each side). Here:
//  - Tubes: convex curvature 1/r, inner bottlenecks 2r (diameters): reach_i <= r_min, the
//    thinnest tube (exact at the tips' caps). Tubes have no concave curvature.
//  - Outer bottlenecks join tubes that share no junction (between tubes of one junction the axes
//    are coplanar and meet at the junction, which leaves no segment normal to both surfaces);
//    since the boundary lies within delta of the capsules, they are >= g_min - 2 delta, g_min the
//    smallest surface gap between such capsules: reach_e <= (g_min - 2 delta) / 2.
//  - Fillets (k > 0): their largest curvatures are found numerically (sampleJunctionCurvature:
//    exact Hessians on a coarse sampling at spacing min(r_min, k) / 6, then a local maximisation
//    from the largest samples) and their radii taken with a 10% margin for what the search may
//    miss. k = 0: the junctions are concave creases, reach_e = 0.
// The test PhantomShapes.BlendedVesselTreeReachBoundsHold checks both bounds by nearest points.
VesselReach vesselTreeReach(const PhantomShape& shape) {
  VesselReach r;
  double rmin = kInf;
  for (const auto& t : shape.tubes) rmin = std::min(rmin, t.radius);
  r.interior = std::isfinite(rmin) ? rmin : 0.0;
  r.exterior = kInf;
  const double k = blendOf(shape), delta = vesselBlendOffset(shape);
  const int n = int(shape.tubes.size());
  std::vector<char> adjacent(std::size_t(n) * n, 0);
  bool junctionWithChildren = false;
  for (const auto& J : shape.junctions) {
    std::vector<int> m{J.parent};
    m.insert(m.end(), J.children.begin(), J.children.end());
    junctionWithChildren = junctionWithChildren || !J.children.empty();
    for (const int a : m)
      for (const int b : m) adjacent[std::size_t(a) * n + b] = 1;
  }
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      if (adjacent[std::size_t(i) * n + j]) continue;
      const auto& a = shape.tubes[i];
      const auto& b = shape.tubes[j];
      const double g = segmentDistance(a.a, a.b, b.a, b.b) - a.radius - b.radius;
      r.exterior = std::min(r.exterior, std::max(0.0, 0.5 * (g - 2 * delta)));
    }
  if (!junctionWithChildren) return r;
  if (k <= 0) {
    r.exterior = 0.0;
    return r;
  }
  const double h = std::min(rmin, k) / 6.0;
  constexpr double kMargin = 0.9;
  // The curvature search's start points, for the whole tree: 60,000 a junction at most, 120,000 in
  // all (a junction of the project's phantoms asks for 14,000-22,000 at h, the blend-6 tree's one
  // junction 182,000; a blended tree of five levels, 31 junctions, took 24 s under the fuzzer's
  // sanitizers before the tree's bound).
  constexpr double kJunctionStartBudget = 60000, kTreeStartBudget = 120000;
  int branching = 0;
  for (const auto& J : shape.junctions) branching += !J.children.empty();
  const double budget = std::min(kJunctionStartBudget, kTreeStartBudget / std::max(branching, 1));
  for (std::size_t ji = 0; ji < shape.junctions.size(); ++ji) {
    if (shape.junctions[ji].children.empty()) continue;
    const CurvatureMax c = sampleJunctionCurvature(shape, int(ji), h, budget);
    if (c.convex > 0) r.interior = std::min(r.interior, kMargin / c.convex);
    if (c.concave > 0) r.exterior = std::min(r.exterior, kMargin / c.concave);
  }
  return r;
}

}  // namespace xsect
