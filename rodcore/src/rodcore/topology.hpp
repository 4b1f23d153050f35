// Linking number, twist and writhe of polygons, closed and box-periodic: the one home
// of these algorithms (docs/topology.md). rodsim writes them per frame for closed rods;
// the Python functions of mdbridge/geometry/topology.py call these through the rodcore
// module (rodcore.topology).
//
// Points are n x 3, row-major; a closed polygon joins its last point to its first; a
// box-periodic one continues as x_{i+n} = x_i + P (`period` non-null, 3 values).
//
//   linking_number   the Gauss linking integral of two disjoint polygons, an exact
//                    integer: the signed crossings of A over B in a projection (each
//                    crossing of two straight segments exact), counted again as B over A,
//                    which must agree (else the next of four projection directions).
//                    Segments are tested in blocks of 32 whose projected bounding boxes
//                    overlap: O(N) for a curve not tangled in projection. Box-periodic:
//                    one period of A against B over the neighbouring periods, projected
//                    along a direction normal to P (the box axis closed into a circle far
//                    larger than the box, without twist).
//   writhe           Klenin & Langowski (Biopolymers 54:307, 2000): the Gauss integral
//                    over two straight segments is the solid angle of the quadrilateral
//                    they span (two triangles by Van Oosterom & Strackee, IEEE Trans
//                    Biomed Eng 30:125, 1983), exact for the polygon, O(n^2). Coarsened
//                    (stride k > 1): segments in blocks of k, pairs in the same or
//                    neighbouring blocks exact, every other pair of blocks by its chords.
//   twist_angles     the angle from u_i, parallel-transported along the minimal rotation
//                    from t_i to t_{i+1}, to u_{i+1}: Tw = sum / 2 pi, second order.
//   edge_twist_angles the twist angles of a closed polygon framed on its edges (tangent the
//                    edge's direction, ribbon vector the mean of its ends' made perpendicular),
//                    at its vertices: Tw = sum / 2 pi is the polygon's own, and Tw + Wr = Lk
//                    to round-off with the exact polygon writhe (Fuller's theorem for polygons:
//                    the parallel transport around the tantrix turns by its area, and Wr = area
//                    / 2 pi - 1 mod 2; Cimasoni, J Knot Theory Ramif 10:387, 2001).
//   periodic_writhe  Fuller's one-integral writhe relative to the straight box axis, on
//                    the polygon's tantrix (spherical triangles (e, t_i, t_{i+1})).
#pragma once
#include <cstddef>
#include <utility>
#include <vector>

namespace rodcore::topology {

// A ribbon turning by more than this between neighbouring points is not resolved: a
// turn of 270 deg reads as -90 deg in the twist and in the ribbon polygon's linking
// alike, so Lk = Tw + Wr would still hold and could not flag it.
inline constexpr double kMaxTwistPerPoint = 1.5707963267948966;  // pi / 2

// 4 pi times the Gauss integral over the segments p1 -> p2 and p3 -> p4, exactly
// (segments that touch give 0). Over the segment pairs of two closed polygons the sum
// / 4 pi is their linking number; over the ordered pairs i != j of one, its writhe.
double segment_solid_angle(const double* p1, const double* p2, const double* p3, const double* p4);

// (1/4 pi) sum of the segment solid angles of two closed polygons: their linking
// number as a real number, O(nA nB), for checks.
double gauss_linking_integral(const double* A, std::size_t nA, const double* B, std::size_t nB);

// Throws NumericalError when no projection gives agreeing counts (the curves touch).
long linking_number(const double* A, std::size_t nA, const double* B, std::size_t nB,
                    const double* period = nullptr);

// Exact writhe of a closed polygon (n >= 4), and the coarsened one (stride k; at least 4
// blocks, else InputError).
double polygon_writhe(const double* x, std::size_t n);
double writhe(const double* x, std::size_t n, int stride);

// Writhe per period of a box-periodic polygon; InputError when an edge turns back
// against the box axis (cosine < -0.9).
double periodic_writhe(const double* x, std::size_t n, const double* period);

// Unit tangents x_{i+1} - x_{i-1} (second order), closed or box-periodic.
std::vector<double> centred_tangents(const double* x, std::size_t n, const double* period = nullptr);
// v made perpendicular to the unit tangents t and normalised; NumericalError where v is
// (nearly) along t.
std::vector<double> perpendicular_unit(const double* v, const double* t, std::size_t n);
// Per point, cyclic; NumericalError where the tangent reverses between two points.
std::vector<double> twist_angles(const double* t, const double* u, std::size_t n);

// Per vertex of a closed polygon x framed by v (n x 3), cyclic: the angle at vertex e + 1.
std::vector<double> edge_twist_angles(const double* x, const double* v, std::size_t n);

struct Ribbon {
  long Lk = 0;
  double Tw = 0.0, Wr = 0.0;
  double Wr_coarsening = 0.0;  // Wr(stride) - Wr(2 stride); 0 for stride 1 or box-periodic
};
// Lk, Tw, Wr of the curve x framed by v (n x 3) made perpendicular to the centred
// tangent: Lk of x and x + eps u (eps a quarter of the median spacing), Tw (closed: the
// polygon's, edge_twist_angles; box-periodic: of u about the centred tangent), Wr
// coarsened with `writhe_stride` (closed) or per period. coarsening: also compute
// Wr_coarsening. NumericalError when the ribbon turns by more than kMaxTwistPerPoint
// between two points.
Ribbon ribbon_topology(const double* x, const double* v, std::size_t n, const double* period,
                       int writhe_stride, bool coarsening = true);

// A ring: the edge from the last point back to the first no longer than twice the
// longest of the others (a box-periodic rod's is about its length).
bool is_closed(const double* x, std::size_t n);
// Stride of the coarsened writhe of a closed rod: at most `writhe_points` blocks
// (InputError if writhe_points < 8). Default: 1000 blocks, 0.02 CPU s at 10.5 kbp,
// within 0.04 of the exact writhe (bench/topology.py).
inline constexpr int kWrithePoints = 1000;
int writhe_stride(std::size_t n, int writhe_points = kWrithePoints);

}  // namespace rodcore::topology
