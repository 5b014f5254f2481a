// Robust orient2d / incircle after Shewchuk (1997): a floating-point filter with his error bounds,
// falling back to exact expansion arithmetic; plus exact segment tests built on orient2d.
#include "core/predicates.hpp"

#include <algorithm>
#include <cmath>

namespace pdmesh {
namespace {

// Expansion arithmetic. An expansion is an array of doubles, ordered by increasing magnitude,
// whose components do not overlap; its value is their exact sum. Zero components are dropped,
// so an empty expansion (length 0) is zero and the last component carries the sign.
// Exactness needs IEEE round-to-nearest-even and no overflow/underflow in the products.

constexpr double kEps = 0x1p-53;  // half an ulp of 1: the unit roundoff
// Shewchuk's bounds on the error of the plain floating-point evaluation (relative to the permanent).
constexpr double kOrientBound = (3.0 + 16.0 * kEps) * kEps;
constexpr double kIncircleBound = (10.0 + 96.0 * kEps) * kEps;

// x + y == a + b exactly, with x = fl(a + b).
inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double b_virtual = x - a;
  const double a_virtual = x - b_virtual;
  y = (a - a_virtual) + (b - b_virtual);
}

inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double b_virtual = a - x;
  const double a_virtual = x + b_virtual;
  y = (a - a_virtual) + (b_virtual - b);
}

// x + y == a * b exactly. With hardware FMA the error term is one fused operation; without it,
// Dekker's split into 26-bit halves gives the same result (std::fma in software would be slow).
inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
#if defined(__FMA__) || defined(__ARM_FEATURE_FMA)
  y = std::fma(a, b, -x);
#else
  constexpr double kSplitter = 134217729.0;  // 2^27 + 1
  const double ca = kSplitter * a, cb = kSplitter * b;
  const double a_hi = ca - (ca - a), a_lo = a - a_hi;
  const double b_hi = cb - (cb - b), b_lo = b - b_hi;
  y = a_lo * b_lo - (((x - a_hi * b_hi) - a_lo * b_hi) - a_hi * b_lo);
#endif
}

// h = e * b. h needs room for 2 * elen components. Returns the length of h.
int scale_expansion(const double* e, int elen, double b, double* h) {
  if (elen == 0 || b == 0.0) return 0;
  int hn = 0;
  double q, hh;
  two_product(e[0], b, q, hh);
  if (hh != 0.0) h[hn++] = hh;
  for (int i = 1; i < elen; ++i) {
    double p1, p0, sum;
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, sum, hh);
    if (hh != 0.0) h[hn++] = hh;
    two_sum(p1, sum, q, hh);
    if (hh != 0.0) h[hn++] = hh;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

// h = e + f (Shewchuk's fast expansion sum: merge by magnitude, then one pass of two_sum).
// h needs room for elen + flen components and must not alias e or f.
int sum_expansions(const double* e, int elen, const double* f, int flen, double* h) {
  if (elen == 0) return static_cast<int>(std::copy(f, f + flen, h) - h);
  if (flen == 0) return static_cast<int>(std::copy(e, e + elen, h) - h);
  // Merge into h first, then sum in place: the write index never overtakes the read index.
  std::merge(e, e + elen, f, f + flen, h, [](double u, double v) { return std::fabs(u) < std::fabs(v); });
  const int n = elen + flen;
  int hn = 0;
  double q = h[0];
  for (int i = 1; i < n; ++i) {
    double qnew, hh;
    two_sum(q, h[i], qnew, hh);
    if (hh != 0.0) h[hn++] = hh;
    q = qnew;
  }
  if (q != 0.0) h[hn++] = q;
  return hn;
}

int negate(double* e, int elen) {
  for (int i = 0; i < elen; ++i) e[i] = -e[i];
  return elen;
}

// The exact difference a - b as an expansion of at most two components.
int exact_diff(double a, double b, double* h) {
  double x, y;
  two_diff(a, b, x, y);
  int n = 0;
  if (y != 0.0) h[n++] = y;
  if (x != 0.0) h[n++] = x;
  return n;
}

// Capacities: a difference has 2 components, a product of differences 8, a 2x2 minor 16,
// a lifted square sum 16, a term lift*minor 2*16*16 = 512, the determinant 3*512.
constexpr int kTermCap = 512;

// h = e * f; h needs room for 2 * elen * flen components. scratch likewise.
int multiply(const double* e, int elen, const double* f, int flen, double* h, double* scratch) {
  int hn = 0;
  double part[2 * 16];  // e has at most 16 components in all our uses
  for (int i = 0; i < flen; ++i) {
    const int pn = scale_expansion(e, elen, f[i], part);
    const int sn = sum_expansions(h, hn, part, pn, scratch);
    std::copy(scratch, scratch + sn, h);
    hn = sn;
  }
  return hn;
}

double estimate_sign_value(const double* e, int n) { return n == 0 ? 0.0 : e[n - 1]; }

// u*v - w*z with u, v, w, z expansions of at most two components; h needs 16.
int minor2(const double* u, int un, const double* v, int vn, const double* w, int wn, const double* z, int zn,
           double* h) {
  double p[8], q[8], s[16];
  const int pn = multiply(u, un, v, vn, p, s);
  const int qn = negate(q, multiply(w, wn, z, zn, q, s));
  return sum_expansions(p, pn, q, qn, h);
}

double orient2d_exact(Vec2 a, Vec2 b, Vec2 c) {
  double acx[2], acy[2], bcx[2], bcy[2];
  const int acxn = exact_diff(a.x, c.x, acx), acyn = exact_diff(a.y, c.y, acy);
  const int bcxn = exact_diff(b.x, c.x, bcx), bcyn = exact_diff(b.y, c.y, bcy);
  double det[16];
  const int n = minor2(acx, acxn, bcy, bcyn, acy, acyn, bcx, bcxn, det);
  return estimate_sign_value(det, n);
}

// lift * minor for one row of the incircle determinant.
int incircle_term(const double* dx, int dxn, const double* dy, int dyn, const double* minor, int minorn, double* h) {
  double sx[8], sy[8], lift[16], s[kTermCap];
  const int sxn = multiply(dx, dxn, dx, dxn, sx, s);
  const int syn = multiply(dy, dyn, dy, dyn, sy, s);
  const int liftn = sum_expansions(sx, sxn, sy, syn, lift);
  return multiply(lift, liftn, minor, minorn, h, s);
}

double incircle_exact(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  double adx[2], ady[2], bdx[2], bdy[2], cdx[2], cdy[2];
  const int adxn = exact_diff(a.x, d.x, adx), adyn = exact_diff(a.y, d.y, ady);
  const int bdxn = exact_diff(b.x, d.x, bdx), bdyn = exact_diff(b.y, d.y, bdy);
  const int cdxn = exact_diff(c.x, d.x, cdx), cdyn = exact_diff(c.y, d.y, cdy);
  double bc[16], ca[16], ab[16];
  const int bcn = minor2(bdx, bdxn, cdy, cdyn, cdx, cdxn, bdy, bdyn, bc);
  const int can = minor2(cdx, cdxn, ady, adyn, adx, adxn, cdy, cdyn, ca);
  const int abn = minor2(adx, adxn, bdy, bdyn, bdx, bdxn, ady, adyn, ab);
  double ta[kTermCap], tb[kTermCap], tc[kTermCap], tab[2 * kTermCap], det[3 * kTermCap];
  const int ta_n = incircle_term(adx, adxn, ady, adyn, bc, bcn, ta);
  const int tb_n = incircle_term(bdx, bdxn, bdy, bdyn, ca, can, tb);
  const int tc_n = incircle_term(cdx, cdxn, cdy, cdyn, ab, abn, tc);
  const int tabn = sum_expansions(ta, ta_n, tb, tb_n, tab);
  const int n = sum_expansions(tab, tabn, tc, tc_n, det);
  return estimate_sign_value(det, n);
}

int sign_of(double v) { return (v > 0.0) - (v < 0.0); }

// Closed-segment overlap of collinear segments: compare along the lexicographic (x, then y) order,
// which is monotone along any line.
bool lex_less(Vec2 p, Vec2 q) { return p.x < q.x || (p.x == q.x && p.y < q.y); }

bool collinear_overlap(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  if (lex_less(b, a)) std::swap(a, b);
  if (lex_less(d, c)) std::swap(c, d);
  const Vec2 lo = lex_less(a, c) ? c : a;  // later start
  const Vec2 hi = lex_less(b, d) ? b : d;  // earlier end
  return !lex_less(hi, lo);
}

}  // namespace

double orient2d(Vec2 a, Vec2 b, Vec2 c) {
  const double left = (a.x - c.x) * (b.y - c.y);
  const double right = (a.y - c.y) * (b.x - c.x);
  const double det = left - right;
  double permanent;
  if (left > 0.0) {
    if (right <= 0.0) return det;  // no cancellation: the sign is right
    permanent = left + right;
  } else if (left < 0.0) {
    if (right >= 0.0) return det;
    permanent = -left - right;
  } else {
    return det;  // left is exactly zero, so det = -right with one rounding: the sign is right
  }
  const double bound = kOrientBound * permanent;
  if (det >= bound || -det >= bound) return det;
  return orient2d_exact(a, b, c);
}

double incircle(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
  const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double det = alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy) + clift * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  const double bound = kIncircleBound * permanent;
  if (det > bound || -det > bound) return det;
  return incircle_exact(a, b, c, d);
}

bool segments_intersect(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = sign_of(orient2d(a, b, c)), o2 = sign_of(orient2d(a, b, d));
  if (o1 * o2 > 0) return false;  // c and d strictly on one side of line ab
  const int o3 = sign_of(orient2d(c, d, a)), o4 = sign_of(orient2d(c, d, b));
  if (o3 * o4 > 0) return false;
  if (o1 == 0 && o2 == 0 && o3 == 0 && o4 == 0) return collinear_overlap(a, b, c, d);
  return true;
}

bool segments_cross_properly(Vec2 a, Vec2 b, Vec2 c, Vec2 d) {
  const int o1 = sign_of(orient2d(a, b, c)), o2 = sign_of(orient2d(a, b, d));
  if (o1 * o2 >= 0) return false;
  const int o3 = sign_of(orient2d(c, d, a)), o4 = sign_of(orient2d(c, d, b));
  return o3 * o4 < 0;
}

}  // namespace pdmesh
