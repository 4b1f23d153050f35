#include "rodcore/topology.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <string>

#include "rodcore/error.hpp"
#include "rodcore/message_number.hpp"

namespace rodcore::topology {
namespace {

using V = std::array<double, 3>;
V load(const double* p) { return {p[0], p[1], p[2]}; }
V sub(const V& a, const V& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
V add(const V& a, const V& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
V scale(double s, const V& a) { return {s * a[0], s * a[1], s * a[2]}; }
double dot(const V& a, const V& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
V cross(const V& a, const V& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const V& a) { return std::sqrt(dot(a, a)); }
V unit(const V& a) { return scale(1.0 / norm(a), a); }

// Projection directions for the crossing count: generic (no symmetry of a test curve or
// a box axis lies in them), tried in turn until the over and under counts agree.
constexpr double kDirections[4][3] = {{0.2917, 0.5189, 0.8037},
                                      {-0.6571, 0.2279, 0.7185},
                                      {0.5330, -0.7936, 0.2934},
                                      {0.1187, 0.9251, -0.3607}};
constexpr std::size_t kBlock = 32;

// Segments as start and end points (3 values each).
struct Segments {
  std::vector<V> a, b;
};

Segments closed_segments(const double* x, std::size_t n) {
  Segments s;
  for (std::size_t i = 0; i < n; ++i) {
    s.a.push_back(load(x + 3 * i));
    s.b.push_back(load(x + 3 * ((i + 1) % n)));
  }
  return s;
}

// Signed crossings of segments a and b in the projection along the unit p: (sum over
// crossings with a above b, sum with b above a); the crossing's sign is
// sign((d_upper x d_lower) . p), the right-hand rule.
std::pair<long, long> crossings(const Segments& A, const Segments& B, const V& p) {
  const V e1 = unit(cross(p, std::abs(p[0]) < 0.9 ? V{1.0, 0.0, 0.0} : V{0.0, 1.0, 0.0}));
  const V e2 = cross(p, e1);
  struct P2 {
    double x, y;
  };
  auto project = [&](const std::vector<V>& v) {
    std::vector<P2> out(v.size());
    for (std::size_t i = 0; i < v.size(); ++i) out[i] = {dot(v[i], e1), dot(v[i], e2)};
    return out;
  };
  const auto A1 = project(A.a), A2 = project(A.b), B1 = project(B.a), B2 = project(B.b);
  struct Box {
    double x0, y0, x1, y1;
  };
  auto boxes = [](const std::vector<P2>& P, const std::vector<P2>& Q) {
    std::vector<Box> out;
    for (std::size_t s = 0; s < P.size(); s += kBlock) {
      Box b{P[s].x, P[s].y, P[s].x, P[s].y};
      for (std::size_t i = s; i < std::min(P.size(), s + kBlock); ++i)
        for (const P2& q : {P[i], Q[i]}) {
          b.x0 = std::min(b.x0, q.x), b.y0 = std::min(b.y0, q.y);
          b.x1 = std::max(b.x1, q.x), b.y1 = std::max(b.y1, q.y);
        }
      out.push_back(b);
    }
    return out;
  };
  const auto bA = boxes(A1, A2), bB = boxes(B1, B2);
  long above = 0, below = 0;
  for (std::size_t ia = 0; ia < bA.size(); ++ia)
    for (std::size_t ib = 0; ib < bB.size(); ++ib) {
      const Box &u = bA[ia], &w = bB[ib];
      if (!(u.x0 <= w.x1 && w.x0 <= u.x1 && u.y0 <= w.y1 && w.y0 <= u.y1)) continue;
      for (std::size_t i = ia * kBlock; i < std::min(A1.size(), (ia + 1) * kBlock); ++i)
        for (std::size_t j = ib * kBlock; j < std::min(B1.size(), (ib + 1) * kBlock); ++j) {
          const double rx = A2[i].x - A1[i].x, ry = A2[i].y - A1[i].y;
          const double qx = B2[j].x - B1[j].x, qy = B2[j].y - B1[j].y;
          const double wx = B1[j].x - A1[i].x, wy = B1[j].y - A1[i].y;
          const double den = rx * qy - ry * qx;
          if (den == 0.0) continue;
          const double s = (wx * qy - wy * qx) / den, t = (wx * ry - wy * rx) / den;
          if (!(s >= 0.0 && s < 1.0 && t >= 0.0 && t < 1.0)) continue;
          const double za = dot(add(A.a[i], scale(s, sub(A.b[i], A.a[i]))), p);
          const double zb = dot(add(B.a[j], scale(t, sub(B.b[j], B.a[j]))), p);
          const long sign = den > 0.0 ? 1 : -1;
          if (za > zb) above += sign;
          if (za < zb) below -= sign;
        }
    }
  return {above, below};
}

void check_points(const double* x, std::size_t n, const char* what, std::size_t minimum) {
  if (n < minimum)
    throw InputError(std::string(what) + ": need at least " + std::to_string(minimum) + " points, got " +
                     std::to_string(n));
  for (std::size_t i = 0; i < 3 * n; ++i)
    if (!std::isfinite(x[i]))
      throw InputError(std::string(what) + ": non-finite coordinates at point " + std::to_string(i / 3));
}

}  // namespace

double segment_solid_angle(const double* p1, const double* p2, const double* p3, const double* p4) {
  const V P1 = load(p1), P2 = load(p2), P3 = load(p3), P4 = load(p4);
  const V v1 = sub(P3, P1), v2 = sub(P4, P1), v3 = sub(P4, P2), v4 = sub(P3, P2);
  const double l1 = norm(v1), l2 = norm(v2), l3 = norm(v3), l4 = norm(v4);
  const double d13 = dot(v1, v3);
  const double first =
      std::atan2(dot(v1, cross(v2, v3)), l1 * l2 * l3 + dot(v1, v2) * l3 + d13 * l2 + dot(v2, v3) * l1);
  const double second =
      std::atan2(dot(v1, cross(v3, v4)), l1 * l3 * l4 + d13 * l4 + dot(v1, v4) * l3 + dot(v3, v4) * l1);
  return -2.0 * (first + second);
}

double gauss_linking_integral(const double* A, std::size_t nA, const double* B, std::size_t nB) {
  check_points(A, nA, "gauss_linking_integral: A", 3);
  check_points(B, nB, "gauss_linking_integral: B", 3);
  double sum = 0.0;
  for (std::size_t i = 0; i < nA; ++i)
    for (std::size_t j = 0; j < nB; ++j)
      sum += segment_solid_angle(A + 3 * i, A + 3 * ((i + 1) % nA), B + 3 * j, B + 3 * ((j + 1) % nB));
  return sum / (4.0 * std::numbers::pi);
}

long linking_number(const double* A, std::size_t nA, const double* B, std::size_t nB, const double* period) {
  check_points(A, nA, "linking_number: A", 3);
  check_points(B, nB, "linking_number: B", 3);
  Segments sA, sB;
  V b{0.0, 0.0, 0.0};
  if (!period) {
    sA = closed_segments(A, nA);
    sB = closed_segments(B, nB);
  } else {
    b = load(period);
    if (!(norm(b) > 0.0) || !std::isfinite(norm(b)))
      throw InputError("linking_number: the period must be a nonzero finite 3-vector");
    // One period of A against B over the neighbouring periods: every crossing of the
    // periodic diagram once (by its segment of A).
    for (std::size_t i = 0; i < nA; ++i) {
      sA.a.push_back(load(A + 3 * i));
      sA.b.push_back(i + 1 < nA ? load(A + 3 * (i + 1)) : add(load(A), b));
    }
    for (int m = -1; m <= 1; ++m)
      for (std::size_t j = 0; j < nB; ++j) {
        sB.a.push_back(add(load(B + 3 * j), scale(m, b)));
        sB.b.push_back(j + 1 < nB ? add(load(B + 3 * (j + 1)), scale(m, b)) : add(load(B), scale(m + 1, b)));
      }
  }
  for (const auto& dir : kDirections) {
    V p = unit(load(dir));
    if (period) {  // project along a direction normal to the box axis
      const V bh = unit(b);
      p = unit(sub(p, scale(dot(p, bh), bh)));
    }
    const auto [up, down] = crossings(sA, sB, p);
    if (up == down) return up;
  }
  throw NumericalError(
      "linking_number: the crossings of A over B and of B over A disagree in every projection tried; the "
      "curves touch or nearly intersect");
}

double polygon_writhe(const double* x, std::size_t n) {
  check_points(x, n, "writhe", 4);
  double total = 0.0;
  for (std::size_t i = 0; i + 2 < n; ++i) {
    const double *a1 = x + 3 * i, *a2 = x + 3 * (i + 1);
    const std::size_t jend = i == 0 ? n - 1 : n;  // segment n - 1 is adjacent to segment 0
    for (std::size_t j = i + 2; j < jend; ++j)
      total += segment_solid_angle(a1, a2, x + 3 * j, x + 3 * ((j + 1) % n));
  }
  return 2.0 * total / (4.0 * std::numbers::pi);
}

double writhe(const double* x, std::size_t n, int stride) {
  check_points(x, n, "writhe", 4);
  if (stride <= 1) return polygon_writhe(x, n);
  const std::size_t k = static_cast<std::size_t>(stride);
  std::vector<std::size_t> starts;
  for (std::size_t s = 0; s < n; s += k) starts.push_back(s);
  const std::size_t nb = starts.size();
  if (nb < 4)
    throw InputError("writhe: stride " + std::to_string(k) + " leaves " + std::to_string(nb) + " of " +
                     std::to_string(n) + " points; at least 4 are needed");
  auto end_of = [&](std::size_t blk) { return blk + 1 < nb ? starts[blk + 1] : n; };
  double near = 0.0;
  auto seg = [&](std::size_t i, std::size_t j) {
    return segment_solid_angle(x + 3 * i, x + 3 * ((i + 1) % n), x + 3 * j, x + 3 * ((j + 1) % n));
  };
  for (std::size_t blk = 0; blk < nb; ++blk) {
    const std::size_t nxt = (blk + 1) % nb;
    for (std::size_t i = starts[blk]; i < end_of(blk); ++i) {
      for (std::size_t j = i + 1; j < end_of(blk); ++j) {  // the same block, each pair once
        const std::size_t gap = (j + n - i) % n;
        if (gap >= 2 && gap <= n - 2) near += seg(i, j);
      }
      for (std::size_t j = starts[nxt]; j < end_of(nxt); ++j) {  // the next block
        const std::size_t gap = (j + n - i) % n;
        if (gap >= 2 && gap <= n - 2) near += seg(i, j);
      }
    }
  }
  std::vector<double> coarse;
  for (std::size_t s : starts) coarse.insert(coarse.end(), x + 3 * s, x + 3 * s + 3);
  return polygon_writhe(coarse.data(), nb) + 2.0 * near / (4.0 * std::numbers::pi);
}

double periodic_writhe(const double* x, std::size_t n, const double* period) {
  check_points(x, n, "periodic writhe", 2);
  const V e = unit(load(period));
  std::vector<V> t(n);
  std::vector<double> et(n);
  std::size_t worst = 0;
  for (std::size_t i = 0; i < n; ++i) {
    V edge = sub(i + 1 < n ? load(x + 3 * (i + 1)) : add(load(x), load(period)), load(x + 3 * i));
    t[i] = unit(edge);
    et[i] = dot(t[i], e);
    if (et[i] < et[worst]) worst = i;
  }
  if (et[worst] < -0.9)
    throw InputError("periodic writhe: edge " + std::to_string(worst) +
                     " turns back against the box axis (cosine " + message_number(et[worst]) +
                     "); the writhe relative to the straight axis is defined only while the axis never "
                     "reverses (docs/topology.md)");
  double sum = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    sum += std::atan2(dot(e, cross(t[i], t[j])), 1.0 + et[i] + et[j] + dot(t[i], t[j]));
  }
  return 2.0 * sum / (2.0 * std::numbers::pi);
}

std::vector<double> centred_tangents(const double* x, std::size_t n, const double* period) {
  std::vector<double> t(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    V nxt = load(x + 3 * ((i + 1) % n)), prv = load(x + 3 * ((i + n - 1) % n));
    if (period && i + 1 == n) nxt = add(nxt, load(period));
    if (period && i == 0) prv = sub(prv, load(period));
    const V u = unit(sub(nxt, prv));
    std::copy(u.begin(), u.end(), t.begin() + 3 * i);
  }
  return t;
}

std::vector<double> perpendicular_unit(const double* v, const double* t, std::size_t n) {
  std::vector<double> u(3 * n);
  for (std::size_t i = 0; i < n; ++i) {
    const V vi = load(v + 3 * i), ti = load(t + 3 * i);
    const V w = sub(vi, scale(dot(vi, ti), ti));
    const double nw = norm(w);
    if (!(nw >= 1e-6 * norm(vi)))
      throw NumericalError("ribbon: the ribbon vector is along the tangent at point " + std::to_string(i) +
                           "; its perpendicular part is undefined there");
    for (int c = 0; c < 3; ++c) u[3 * i + c] = w[c] / nw;
  }
  return u;
}

std::vector<double> twist_angles(const double* t, const double* u, std::size_t n) {
  std::vector<double> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::size_t j = (i + 1) % n;
    const V t1 = load(t + 3 * i), t2 = load(t + 3 * j), u1 = load(u + 3 * i), u2 = load(u + 3 * j);
    const double c = dot(t1, t2);
    if (c <= -1.0 + 1e-12)
      throw NumericalError("twist: the tangent reverses between points " + std::to_string(i) +
                           " and the next");
    const V Pu = sub(u1, scale(dot(t2, u1) / (1.0 + c), add(t1, t2)));
    out[i] = std::atan2(dot(cross(Pu, u2), t2), dot(Pu, u2));
  }
  return out;
}

std::vector<double> edge_twist_angles(const double* x, const double* v, std::size_t n) {
  // edge e runs from x_e to x_{e+1}; its tangent is exact for the polygon, and its ribbon
  // vector is v_e + v_{e+1} made perpendicular to it
  std::vector<double> t(3 * n), w(3 * n);
  for (std::size_t e = 0; e < n; ++e) {
    const std::size_t f = (e + 1) % n;
    const V te = unit(sub(load(x + 3 * f), load(x + 3 * e)));
    const V we = add(load(v + 3 * e), load(v + 3 * f));
    std::copy(te.begin(), te.end(), t.begin() + 3 * e);
    std::copy(we.begin(), we.end(), w.begin() + 3 * e);
  }
  const auto u = perpendicular_unit(w.data(), t.data(), n);
  return twist_angles(t.data(), u.data(), n);
}

Ribbon ribbon_topology(const double* x, const double* v, std::size_t n, const double* period,
                       int writhe_stride, bool coarsening) {
  check_points(x, n, "ribbon: centreline", 4);
  const auto t = centred_tangents(x, n, period);
  const auto u = perpendicular_unit(v, t.data(), n);
  std::vector<double> edges(n);
  for (std::size_t i = 0; i < n; ++i) {
    V nxt = load(x + 3 * ((i + 1) % n));
    if (period && i + 1 == n) nxt = add(nxt, load(period));
    edges[i] = norm(sub(nxt, load(x + 3 * i)));
  }
  std::sort(edges.begin(), edges.end());
  const double median = n % 2 ? edges[n / 2] : 0.5 * (edges[n / 2 - 1] + edges[n / 2]);
  // closed: the polygon's own twist (edge tangents), with which Tw + Wr = Lk holds to round-off;
  // box-periodic: the centred tangents' (second order; the periodic writhe is Fuller's)
  const auto angles = period ? twist_angles(t.data(), u.data(), n) : edge_twist_angles(x, v, n);
  std::size_t worst = 0;
  double Tw = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    Tw += angles[i];
    if (std::abs(angles[i]) > std::abs(angles[worst])) worst = i;
  }
  if (std::abs(angles[worst]) > kMaxTwistPerPoint)
    throw NumericalError(
        "ribbon: it turns " +
        std::to_string(static_cast<long>(std::lround(angles[worst] * 180.0 / std::numbers::pi))) +
        " deg between points " + std::to_string(worst) + " and " + std::to_string((worst + 1) % n) +
        "; at most 90 deg per point is resolved (a faster twist aliases to a slower one in "
        "Lk and Tw alike)");
  std::vector<double> ribbon(3 * n);
  const double eps = 0.25 * median;
  for (std::size_t i = 0; i < 3 * n; ++i) ribbon[i] = x[i] + eps * u[i];
  Ribbon r;
  r.Lk = linking_number(x, n, ribbon.data(), n, period);
  r.Tw = Tw / (2.0 * std::numbers::pi);
  if (period) {
    r.Wr = periodic_writhe(x, n, period);
  } else {
    r.Wr = writhe(x, n, writhe_stride);
    if (coarsening && writhe_stride > 1) r.Wr_coarsening = r.Wr - writhe(x, n, 2 * writhe_stride);
  }
  return r;
}

bool is_closed(const double* x, std::size_t n) {
  check_points(x, n, "is_closed", 2);
  double longest = 0.0;
  for (std::size_t i = 0; i + 1 < n; ++i)
    longest = std::max(longest, norm(sub(load(x + 3 * (i + 1)), load(x + 3 * i))));
  return norm(sub(load(x), load(x + 3 * (n - 1)))) <= 2.0 * longest;
}

int writhe_stride(std::size_t n, int writhe_points) {
  if (writhe_points < 8)
    throw InputError("writhe points: " + std::to_string(writhe_points) + "; allowed: at least 8");
  return std::max<int>(1, static_cast<int>((n + static_cast<std::size_t>(writhe_points) - 1) /
                                           static_cast<std::size_t>(writhe_points)));
}

}  // namespace rodcore::topology
