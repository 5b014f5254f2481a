// Hill-climbing ODT smoothing with optimesh's step cap, boundary sliding and Lawson flips.
#include "cleanup/smoothing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cleanup/measures.hpp"
#include "core/predicates.hpp"
#include "geometry/curve_projection.hpp"

namespace pdmesh::cleanup {
namespace {

// A boundary vertex moves at most this fraction of the arc gap to each curve neighbour per move,
// so neighbours never meet or cross (sim/boundary_handling uses 0.45 for the same reason).
constexpr double kArcGapFraction = 0.45;
// Step lengths tried per move: the capped step, then halved this many times (MESH2D relaxes a
// rejected move back towards the old position the same way).
constexpr int kLineSearchSteps = 4;

}  // namespace

Smoother::Smoother(EditableMesh& mesh, const Geometry& geometry, double step_cap)
    : mesh_(mesh), geometry_(geometry), step_cap_(step_cap) {}

Vec2 Smoother::on_curve(int a, Vec2 candidate, double& new_arc) const {
  const double here = mesh_.arc[a];
  const double lo = here - kArcGapFraction * (here - mesh_.neighbour_arc(a, 0));
  const double hi = here + kArcGapFraction * (mesh_.neighbour_arc(a, 1) - here);
  const CurvePoint cp = closest_on_curve_range(geometry_.curves[mesh_.curve[a]], candidate, lo, hi);
  new_arc = cp.arc;
  return cp.p;
}

// The star's triangles with what a move of a leaves as it is: their other two points, the squared
// length of the side opposite a as min_angle_sine computes it and its length as aspect_ratio computes
// it (dist(), the square root of the same number); and each triangle's score, aspect ratio and
// inradius now, as score_of() and aspect_ratio_and_inradius() give them (the same operations).
void Smoother::set_star_edges(int a) {
  const auto& m = mesh_;
  star_edges_.clear();
  for (int t : fan_) {
    const auto& tv = m.v[t];
    StarEdge e;
    e.k = EditableMesh::index_of(tv, a);
    e.sharp = m.sharp_corner_of(t);
    const Vec2 x = m.p[tv[0]], y = m.p[tv[1]], z = m.p[tv[2]];
    e.x = x;
    e.y = y;
    e.z = z;
    const double ab = norm2(y - x), bc = norm2(z - y), ca = norm2(x - z);
    e.twice_area = cross(y - x, z - x);
    e.score =
        e.sharp >= 0 ? min_angle_sine_except(x, y, z, e.sharp) : min_angle_sine_of_squares(ab, bc, ca, e.twice_area);
    const double la = std::sqrt(bc), lb = std::sqrt(ca), lc = std::sqrt(ab);
    const double perimeter = lc + la + lb;
    e.inradius = perimeter > 0.0 ? std::fabs(e.twice_area) / perimeter : 0.0;
    e.aspect = aspect_ratio_of_lengths(la, lb, lc, e.twice_area);
    e.opposite = e.k == 0 ? bc : (e.k == 1 ? ca : ab);
    e.opposite_length = e.k == 0 ? la : (e.k == 1 ? lb : lc);
    star_edges_.push_back(e);
  }
}

// EditableMesh::score_of(t, x, y, z) for star triangle e with a at its corner e.k, and the squared
// lengths of its sides ab, bc, ca (min_angle_sine's names) in `sides`, for the aspect ratio.
inline double Smoother::score_at(const StarEdge& e, Vec2 x, Vec2 y, Vec2 z, double twice_area, double* sides) const {
  sides[0] = e.k == 2 ? e.opposite : norm2(y - x);
  sides[1] = e.k == 0 ? e.opposite : norm2(z - y);
  sides[2] = e.k == 1 ? e.opposite : norm2(x - z);
  if (e.sharp >= 0) return min_angle_sine_except(x, y, z, e.sharp);
  return min_angle_sine_of_squares(sides[0], sides[1], sides[2], twice_area);
}

// aspect_ratio(x, y, z) of star triangle e from score_at()'s sides: the side opposite the vertex is
// the star's length, the other two the square roots of their squares.
inline double Smoother::aspect_at(const StarEdge& e, const double* sides, double twice_area) {
  double la, lb, lc;
  switch (e.k) {
    case 0:
      la = e.opposite_length, lb = std::sqrt(sides[2]), lc = std::sqrt(sides[0]);
      break;
    case 1:
      la = std::sqrt(sides[1]), lb = e.opposite_length, lc = std::sqrt(sides[0]);
      break;
    default:
      la = std::sqrt(sides[1]), lb = std::sqrt(sides[2]), lc = e.opposite_length;
      break;
  }
  return aspect_ratio_of_lengths(la, lb, lc, twice_area);
}

inline double Smoother::score_at(std::size_t j, Vec2 to) const {
  const StarEdge& e = star_edges_[j];
  const Vec2 x = e.k == 0 ? to : e.x, y = e.k == 1 ? to : e.y, z = e.k == 2 ? to : e.z;
  double sides[3];
  return score_at(e, x, y, z, cross(y - x, z - x), sides);
}

// Moves a by `displacement` (projected onto its curve for a boundary vertex), halving the step
// until no adjacent triangle inverts, the adjacent minimum does not drop, the adjacent sum of aspect
// ratios does not rise, and one of the two strictly improves (so sweeps end, and neither the worst
// angle nor the mesh's average aspect ratio can get worse). A lifting move (`lift`) needs only the
// adjacent minimum to rise strictly; its aspect-ratio sum may rise. fan_ holds a's star, and
// star_edges_ its triangles (set_star_edges()).
bool Smoother::try_move(int a, Vec2 displacement, double old_min, double old_sum, bool lift) {
  const auto& m = mesh_;
  const Vec2 from = m.p[a];
  const bool sliding = m.kind[a] == NodeKind::Boundary;
  // Most steps are rejected, mostly because one triangle's score falls below old_min, and a triangle
  // that falls below it at one step mostly does at half that step too. Any triangle below old_min
  // rejects a step, whatever the others are, so that triangle is scored first at the next step, and
  // when it is below old_min again the rest of the star is not looked at: the same verdict.
  std::size_t culprit = star_edges_.size();
  for (int k = 0; k < kLineSearchSteps; ++k, displacement = 0.5 * displacement) {
    double new_arc = m.arc[a];
    const Vec2 to = sliding ? on_curve(a, from + displacement, new_arc) : from + displacement;
    if (to == from) return false;
    if (culprit < star_edges_.size() && score_at(culprit, to) < old_min) continue;
    double new_min = std::numeric_limits<double>::infinity(), new_sum = 0.0;
    bool valid = true;
    for (std::size_t j = 0; j < star_edges_.size(); ++j) {
      const StarEdge& e = star_edges_[j];
      const Vec2 x = e.k == 0 ? to : e.x, y = e.k == 1 ? to : e.y, z = e.k == 2 ? to : e.z;
      if (!(orient2d(x, y, z) > 0.0)) {
        culprit = j;
        valid = false;
        break;
      }
      double sides[3];
      const double twice_area = cross(y - x, z - x);
      const double score = score_at(e, x, y, z, twice_area, sides);
      new_min = std::min(new_min, score);
      // Rejected already (aspect ratios are positive, so the sum only grows): the rest of the star
      // cannot change the verdict below, so the step ends here, before the aspect ratio when the
      // smallest score decides it.
      if (new_min < old_min) {
        culprit = j;
        valid = false;
        break;
      }
      new_sum += aspect_at(e, sides, twice_area);
      if (!lift && new_sum > old_sum) {
        valid = false;
        break;
      }
    }
    if (!valid || new_min < old_min || (!lift && new_sum > old_sum)) continue;
    // The move must gain something: outside a trial at least the sweep gains (a settled lattice
    // otherwise keeps taking moves that change the mean aspect ratio in the sixth digit, docs/cleanup.md);
    // a trial's relaxation takes any gain (0: strict improvement).
    const bool sweep = !mesh_.in_transaction();
    const double min_gain = sweep ? min_rise_ : 0.0,
                 aspect_gain = sweep ? aspect_drop_ * static_cast<double>(fan_.size()) : 0.0;
    // A step that is valid and harms nothing but gains too little ends the search: a shorter one
    // would gain less still, and trying the halvings is what a rejected move costs.
    if (!(new_min - old_min > min_gain || old_sum - new_sum > aspect_gain)) {
      if (sweep && (min_gain > 0.0 || aspect_gain > 0.0)) return false;
      continue;
    }
    // Lawson flips follow the move. They never lower the smallest angle of the quadrilateral they
    // flip, but may change its aspect ratios, so outside a topology trial (which measures itself)
    // the move and its flips are measured together and undone if the aspect-ratio sum grew.
    const bool own = !mesh_.in_transaction();
    last_gain_ = {new_min - old_min, old_sum - new_sum, static_cast<int>(fan_.size())};
    // Most moves of a settled lattice flip nothing. Then the move is all there is: no Lawson pass, and
    // outside a trial no journal either, since the flips were the only thing it could have undone
    // (the measured sums would be exactly new_sum <= old_sum); move() marks the star dirty as a commit would.
    if (!flips_needed(a, to)) {
      mesh_.move(a, to, new_arc, fan_);  // in a trial it journals the star; outside one it marks it dirty
      return true;
    }
    if (defer_flips_) {
      deferred_ = true;
      return false;
    }
    if (own) mesh_.begin();
    mesh_.move(a, to, new_arc, fan_);
    edges_.clear();
    for (int t : fan_) {
      const auto& tv = m.v[t];
      for (int i = 0; i < 3; ++i) edges_.push_back({tv[next3(i)], tv[prev3(i)], t});
    }
    mesh_.legalize(edges_);
    if (own) {
      int n_before = 0, n_after = 0;
      if (!lift && mesh_.touched_aspect_after(n_after) > mesh_.touched_aspect_before(n_before)) {
        mesh_.rollback();
        continue;
      }
      mesh_.commit();
    }
    return true;
  }
  return false;
}

// Whether legalize() would flip any edge of a's star once a is at `to`: the edges it starts from are
// the three edges of each star triangle, so with none of them illegal it flips nothing. Each edge is
// tested from the star triangle whose local index it is opposite to (the link edge and the spoke shared
// with the next star triangle; the first one's other spoke is shared with the last triangle, or is a
// boundary edge of an open star); the exact incircle test gives the same sign from either side.
bool Smoother::flips_needed(int a, Vec2 to) const {
  const auto& m = mesh_;
  auto at = [&](int x) { return x == a ? to : m.p[x]; };
  for (int t : fan_) {
    const auto& tv = m.v[t];
    const int k = EditableMesh::index_of(tv, a);
    for (const int i : {k, next3(k)}) {
      const int u = m.n[t][i];
      if (u < 0) continue;
      const int q = m.v[u][EditableMesh::index_of(m.n[u], t)];
      if (incircle(at(tv[i]), at(tv[next3(i)]), at(tv[prev3(i)]), at(q)) > 0.0) return true;
    }
  }
  return false;
}

bool Smoother::relax(int a) { return relax(a, false); }

bool Smoother::relax(int a, bool star_known) {
  auto& m = mesh_;
  deferred_ = false;
  if (m.removed(a) || !m.movable(a)) return false;
  if (m.kind[a] == NodeKind::Boundary && m.curve[a] < 0) return false;
  if (!star_known) m.star(a, fan_);
  double old_min = std::numeric_limits<double>::infinity(), old_sum = 0.0, area_sum = 0.0;
  double r_min = std::numeric_limits<double>::infinity();
  Vec2 weighted{};
  set_star_edges(a);
  for (const StarEdge& e : star_edges_) {
    old_min = std::min(old_min, e.score);
    old_sum += e.aspect;
    const double area = 0.5 * e.twice_area;
    weighted = weighted + area * circumcentre(e.x, e.y, e.z);
    area_sum += area;
    r_min = std::min(r_min, e.inradius);
  }
  if (!(area_sum > 0.0)) return false;
  Vec2 d = (1.0 / area_sum) * weighted - m.p[a];
  const double length = norm(d), cap = step_cap_ * r_min;
  if (!(length > 0.0)) return false;
  if (length > cap) d = (cap / length) * d;
  return try_move(a, d, old_min, old_sum);
}

// The gradient of triangle t's score in the position of its vertex a (central differences, probe h).
Vec2 Smoother::score_gradient(int t, int a, double h) const {
  const auto& m = mesh_;
  const auto& tv = m.v[t];
  const int k = EditableMesh::index_of(tv, a);
  const Vec2 y = m.p[tv[next3(k)]], z = m.p[tv[prev3(k)]], x = m.p[a];
  const int skip = m.sharp_corner_of(t);
  auto score_at = [&](Vec2 at) {
    if (skip < 0) return min_angle_sine(at, y, z);
    std::array<Vec2, 3> q{m.p[tv[0]], m.p[tv[1]], m.p[tv[2]]};
    q[static_cast<std::size_t>(k)] = at;
    return min_angle_sine_except(q[0], q[1], q[2], skip);
  };
  return {score_at(x + Vec2{h, 0}) - score_at(x - Vec2{h, 0}), score_at(x + Vec2{0, h}) - score_at(x - Vec2{0, h})};
}

bool Smoother::climb(int a) { return climb(a, false); }

bool Smoother::climb(int a, bool star_known) {
  auto& m = mesh_;
  deferred_ = false;
  if (m.removed(a) || !m.movable(a)) return false;
  if (m.kind[a] == NodeKind::Boundary && m.curve[a] < 0) return false;
  if (!star_known) m.star(a, fan_);
  double old_min = std::numeric_limits<double>::infinity(), second_min = old_min, old_sum = 0.0;
  double r_min = std::numeric_limits<double>::infinity();
  int worst = -1, second = -1;
  set_star_edges(a);
  for (std::size_t j = 0; j < star_edges_.size(); ++j) {
    const StarEdge& e = star_edges_[j];
    const int t = fan_[j];
    const double q = e.score;
    if (q < old_min) {
      second_min = old_min;
      second = worst;
      old_min = q;
      worst = t;
    } else if (q < second_min) {
      second_min = q;
      second = t;
    }
    old_sum += e.aspect;
    r_min = std::min(r_min, e.inradius);
  }
  if (worst < 0 || !(r_min > 0.0)) return false;
  const double h = 1e-3 * r_min;
  const Vec2 g = score_gradient(worst, a, h);
  const double length = norm(g);
  if (!(length > 0.0)) return false;
  const bool lift = old_min < lift_below_ && stuck_ && stuck_(worst);
  if (try_move(a, (step_cap_ * r_min / length) * g, old_min, old_sum, lift)) return true;
  if (!lift || second < 0) return false;
  // A lifting climb that stalls where the worst triangle's rise is the second worst's fall (two
  // triangles at nearly the same smallest angle, the kink of the star's smallest angle) steps along
  // the bisector of their two gradients, which raises both.
  const Vec2 g2 = score_gradient(second, a, h);
  const double length2 = norm(g2);
  if (!(length2 > 0.0)) return false;
  const Vec2 b = (1.0 / length) * g + (1.0 / length2) * g2;
  const double length_b = norm(b);
  if (!(length_b > 0.0)) return false;
  return try_move(a, (step_cap_ * r_min / length_b) * b, old_min, old_sum, true);
}

}  // namespace pdmesh::cleanup
