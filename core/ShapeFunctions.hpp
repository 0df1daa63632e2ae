// Grid shape functions as small traits: each gives the 1D weight and gradient weight of a
// node for a particle, and the range of nodes with non-zero weight. 2D weights are tensor
// products (see ParticleStencil). All traits are usable by the same kernels. `node` is the
// node's index along the direction and `cells` the grid's cell count along it (only the
// quadratic element and the B-spline's edge functions need them).
#pragma once

#include <Kokkos_Core.hpp>

#include <type_traits>
#include <utility>

namespace impm {

// floor(x) as an int, usable inside kernels (Kokkos 3.4 keeps floor in Experimental).
KOKKOS_INLINE_FUNCTION int floorToInt(double x) {
  const int i = static_cast<int>(x);
  return x < i ? i - 1 : i;
}

// Linear MPM ("tent"): the particle is a point; S_ip = N_i(x_p).
// r = x_p - x_i, h = cell size. The half domain size l is ignored.
struct LinearMpm {
  static constexpr int max_nodes_1d = 2;
  static constexpr bool fixed_count = true;  // always 2 nodes per direction inside the grid
  static constexpr const char* name = "MPM";

  KOKKOS_INLINE_FUNCTION static double value(double r, double h, double /*l*/, int /*node*/ = 0, int /*cells*/ = 0) {
    const double a = r < 0 ? -r : r;
    return a < h ? 1.0 - a / h : 0.0;
  }
  KOKKOS_INLINE_FUNCTION static double gradient(double r, double h, double /*l*/, int /*node*/ = 0, int /*cells*/ = 0) {
    const double a = r < 0 ? -r : r;
    if (a >= h) return 0.0;
    return r < 0 ? 1.0 / h : -1.0 / h;
  }
  // First node index (relative to the grid origin) of the stencil and its length.
  KOKKOS_INLINE_FUNCTION static void range(double xi, double /*l_over_h*/, int& first, int& count) {
    first = floorToInt(xi);
    count = 2;
  }
  // The whole 1D stencil of a point strictly inside a cell, from its grid coordinate
  // xi = (x - origin) / h: node floor(xi) with weight 1 - f and node floor(xi) + 1 with f,
  // f = xi - floor(xi), gradients -+1/h. What value() and gradient() give there, without their
  // per-node branches and divisions (the explicit kernels build two stencils per particle and
  // step). False, and nothing set, on a cell line or outside the grid's cells: the caller then
  // takes the general path.
  KOKKOS_INLINE_FUNCTION static bool interiorStencil(double xi, double invh, int ncells, int& first, double* w,
                                                     double* gr) {
    const int i = floorToInt(xi);
    const double f = xi - i;
    if (i < 0 || i >= ncells || !(f > 0.0)) return false;
    first = i;
    w[0] = 1.0 - f;
    w[1] = f;
    gr[0] = -invh;
    gr[1] = invh;
    return true;
  }
};

// Whether a shape has LinearMpm's interiorStencil.
template <class Shape, class = void>
struct HasInteriorStencil : std::false_type {};
template <class Shape>
struct HasInteriorStencil<Shape,
                          decltype(void(Shape::interiorStencil(0.0, 0.0, 0, std::declval<int&>(), nullptr, nullptr)))>
    : std::true_type {};

// Whether a shape has UniformGimp's domainStencil.
template <class Shape, class = void>
struct HasDomainStencil : std::false_type {};
template <class Shape>
struct HasDomainStencil<Shape, decltype(void(Shape::domainStencil(0.0, 0.0, 0.0, 0, std::declval<int&>(),
                                                                  std::declval<int&>(), nullptr, nullptr)))>
    : std::true_type {};

// Uniform GIMP (Bardenhagen & Kober 2004): the particle is a box of half size l (l <= h/2)
// with characteristic function chi_p; S_ip = (1/V_p) int chi_p N_i dx, and the gradient
// weight is (1/V_p) int chi_p dN_i/dx dx = dS_ip/dx_p. Closed forms per 1D interval.
struct UniformGimp {
  static constexpr int max_nodes_1d = 3;
  static constexpr bool fixed_count = false;  // 2 or 3 nodes per direction
  static constexpr const char* name = "GIMP";

  KOKKOS_INLINE_FUNCTION static double value(double r, double h, double l, int /*node*/ = 0, int /*cells*/ = 0) {
    const double a = r < 0 ? -r : r;
    if (a < l) return 1.0 - (r * r + l * l) / (2.0 * h * l);
    if (a < h - l) return 1.0 - a / h;
    if (a < h + l) {
      const double s = h + l - a;
      return s * s / (4.0 * h * l);
    }
    return 0.0;
  }
  KOKKOS_INLINE_FUNCTION static double gradient(double r, double h, double l, int /*node*/ = 0, int /*cells*/ = 0) {
    const double a = r < 0 ? -r : r;
    const double sign = r < 0 ? -1.0 : 1.0;
    if (a < l) return -r / (h * l);
    if (a < h - l) return -sign / h;
    if (a < h + l) return -sign * (h + l - a) / (2.0 * h * l);
    return 0.0;
  }
  KOKKOS_INLINE_FUNCTION static void range(double xi, double l_over_h, int& first, int& count) {
    first = floorToInt(xi - l_over_h);
    const int last = floorToInt(xi + l_over_h) + 1;
    count = last - first + 1;
    if (count > max_nodes_1d) count = max_nodes_1d;
  }
  // The whole 1D stencil of a domain inside the grid, from its grid coordinate xi = (x - origin) / h
  // and half size lh = l / h <= 1/2: value() and gradient() in cell units, with one division per
  // particle instead of one or two per node. With i = floor(xi) and f = xi - i, a domain within
  // cell i (lh <= f <= 1 - lh) has the tent's two weights 1 - f and f; one across node i (f < lh)
  // has three, node i's 1 - (f^2 + lh^2) / (2 lh) and its neighbours' (lh -+ f)^2 / (4 lh); one
  // across node i + 1 the mirror image. Equal to value() and gradient() up to rounding (a few ulps;
  // test_shape_functions). False, and nothing set, for a domain wider than a cell or one that
  // reaches the grid's edge: the caller then takes the general path, which clips it.
  KOKKOS_INLINE_FUNCTION static bool domainStencil(double xi, double lh, double invh, int ncells, int& first,
                                                   int& count, double* w, double* gr) {
    const int i = floorToInt(xi);
    const double f = xi - i;
    if (!(lh <= 0.5) || !(lh > 0.0)) return false;
    if (f < lh) {  // across node i: nodes i - 1, i, i + 1
      if (i < 1 || i + 1 > ncells) return false;
      const double q = 0.25 / lh, a = lh - f, b = lh + f;
      first = i - 1;
      count = 3;
      w[0] = a * a * q;
      w[1] = 1.0 - (f * f + lh * lh) * (2.0 * q);
      w[2] = b * b * q;
      gr[0] = -a * (2.0 * q) * invh;
      gr[1] = -f * (4.0 * q) * invh;
      gr[2] = b * (2.0 * q) * invh;
      return true;
    }
    if (f > 1.0 - lh) {  // across node i + 1: nodes i, i + 1, i + 2
      if (i < 0 || i + 2 > ncells) return false;
      const double q = 0.25 / lh, g = 1.0 - f, a = lh - g, b = lh + g;
      first = i;
      count = 3;
      w[0] = b * b * q;
      w[1] = 1.0 - (g * g + lh * lh) * (2.0 * q);
      w[2] = a * a * q;
      gr[0] = -b * (2.0 * q) * invh;
      gr[1] = g * (4.0 * q) * invh;
      gr[2] = a * (2.0 * q) * invh;
      return true;
    }
    if (i < 0 || i + 1 > ncells) return false;  // within cell i: the tent
    first = i;
    count = 2;
    w[0] = 1.0 - f;
    w[1] = f;
    gr[0] = -invh;
    gr[1] = invh;
    return true;
  }
};

// Convected-particle GIMP (cpGIMP; Sadeghirad, Brannon & Burghardt 2011 call it the
// axis-aligned variant; Wallstedt & Guilkey 2008): the uGIMP functions, with the particle
// domain carried by the deformation. The domain stays an axis-aligned box whose half size in
// direction d is l0_d F_dd (updated as l_d <- l_d F_dd^new / F_dd^old with the stress, while
// both are positive), capped at half a cell so that the uGIMP closed forms (l <= h/2) and the
// 3-node stencil still hold. Under compression the domains shrink with the material instead
// of overlapping, which is what a compacting body needs.
struct ConvectedGimp : UniformGimp {
  static constexpr const char* name = "cpGIMP";
};

// CPDI1 (Sadeghirad, Brannon & Burghardt 2011, IJNME 86): the particle domain is the
// parallelogram (2D) / parallelepiped (3D) spanned by r_i = F l0_i e_i about x_p, l0 the initial
// half size (halfSize, which CPDI never changes). The weights average the linear tent over the
// domain's 2^Dim corners; the stencil is not a tensor product, see CpdiStencil.hpp (the
// ParticleStencil<Cpdi, Dim> specialisation). Only the trait's constants are used.
struct Cpdi {
  static constexpr int max_nodes_1d = 4;  // a domain whose corners lie in at most 3 cells per direction
  static constexpr bool fixed_count = false;
  static constexpr const char* name = "CPDI";
};

// Whether a shape's particle domains follow the deformation (read by the particle update).
template <class Shape>
struct ConvectsDomain {
  static constexpr bool value = false;
};
template <>
struct ConvectsDomain<ConvectedGimp> {
  static constexpr bool value = true;
};

// Quadratic Lagrange (the 1D factor of the Q9 element) for the finite-element reference mode:
// an element spans two grid cells per direction, with nodes at its ends (even grid indices)
// and its middle (odd). With s = |r| / h, an end node's function is (1 - s)(1 - s/2) for
// s < 2 (it reaches across the element to the far end node), a middle node's 1 - s^2 for
// s < 1. Cells X and Cells Y must be even.
struct QuadraticLagrange {
  static constexpr int max_nodes_1d = 3;
  static constexpr bool fixed_count = true;  // always the element's 3 nodes per direction
  static constexpr const char* name = "FE Q9";

  KOKKOS_INLINE_FUNCTION static double value(double r, double h, double /*l*/, int node, int /*cells*/ = 0) {
    const double s = (r < 0 ? -r : r) / h;
    if (node % 2 == 0) return s < 2.0 ? (1.0 - s) * (1.0 - 0.5 * s) : 0.0;
    return s < 1.0 ? 1.0 - s * s : 0.0;
  }
  KOKKOS_INLINE_FUNCTION static double gradient(double r, double h, double /*l*/, int node, int /*cells*/ = 0) {
    const double s = (r < 0 ? -r : r) / h;
    const double sign = r < 0 ? -1.0 : 1.0;
    if (node % 2 == 0) return s < 2.0 ? sign * (s - 1.5) / h : 0.0;
    return s < 1.0 ? -2.0 * r / (h * h) : 0.0;
  }
  // The element containing xi (in cells): its first node is even.
  KOKKOS_INLINE_FUNCTION static void range(double xi, double /*l_over_h*/, int& first, int& count) {
    first = 2 * floorToInt(0.5 * xi);
    count = 3;
  }
};

// Quadratic B-spline MPM (Steffen, Kirby & Berzins 2008, IJNME 76): the particle is a point and
// node i's function is the uniform C1 quadratic B-spline with knots at the cell midpoints,
// support |r| < 1.5 h: with s = |r| / h, 3/4 - s^2 for s < 1/2, (3/2 - s)^2 / 2 for s < 3/2.
// Always 3 nodes per direction: the node nearest the particle and its two neighbours.
// Grid edge (the paper's modified boundary splines): node -1 (or n + 1) is missing, so on the
// edge half cells [0, h/2] and [(n - 1/2) h, n h] the edge node and its neighbour take the
// linear tent 1 - s instead, which joins their B-spline pieces C1 at h/2 from the edge. This is
// the spline space of the open knot vector {0, 0, 0, 1/2, 3/2, ...} (in cells) cut down to one
// function per grid node, the ones linear on the edge half cells.
// What holds, on the whole grid [0, n h] including the edge cells: sum_i S_i = 1,
// sum_i dS_i = 0, sum_i S_i x_i = x_p and sum_i dS_i x_i = 1; every S_i is C1 (no jump in the
// gradient when a particle crosses a cell line). Quadratics are not reproduced (inside,
// sum_i S_i x_i^2 = x_p^2 + h^2/4). Needs at least 2 cells per direction (3 nodes).
struct QuadraticBSpline {
  static constexpr int max_nodes_1d = 3;
  static constexpr bool fixed_count = true;
  static constexpr const char* name = "B-Spline Quadratic";

  // On an edge half cell (r = x_p - x_node), the edge node's and its neighbour's tent slope in
  // units of 1/h: -1 or +1 (one-sided, into the grid, also on the edge line itself); 0 elsewhere.
  KOKKOS_INLINE_FUNCTION static int edgeTentSlope(double r, double h, int node, int cells) {
    if (node == 0 && r < 0.5 * h) return -1;
    if (node == 1 && r < -0.5 * h) return 1;
    if (node == cells && r > -0.5 * h) return 1;
    if (node == cells - 1 && r > 0.5 * h) return -1;
    return 0;
  }
  KOKKOS_INLINE_FUNCTION static double value(double r, double h, double /*l*/, int node, int cells) {
    const double s = (r < 0 ? -r : r) / h;
    if (edgeTentSlope(r, h, node, cells) != 0) return s < 1.0 ? 1.0 - s : 0.0;
    if (s < 0.5) return 0.75 - s * s;
    if (s < 1.5) return 0.5 * (1.5 - s) * (1.5 - s);
    return 0.0;
  }
  KOKKOS_INLINE_FUNCTION static double gradient(double r, double h, double /*l*/, int node, int cells) {
    const double s = (r < 0 ? -r : r) / h;
    const double sign = r < 0 ? -1.0 : 1.0;
    const int tent = edgeTentSlope(r, h, node, cells);
    if (tent != 0) return tent / h;
    if (s < 0.5) return -2.0 * r / (h * h);
    if (s < 1.5) return -sign * (1.5 - s) / h;
    return 0.0;
  }
  // The node nearest xi and its two neighbours (ParticleStencil keeps them inside the grid).
  KOKKOS_INLINE_FUNCTION static void range(double xi, double /*l_over_h*/, int& first, int& count) {
    first = floorToInt(xi + 0.5) - 1;
    count = 3;
  }
  // The whole stencil of a point off the edge half cells (nearest node i from 1 to cells - 1, where
  // no edge tent applies), from xi = (x - origin) / h: with d = xi - i in [-1/2, 1/2),
  // (1/2 - d)^2 / 2, 3/4 - d^2, (1/2 + d)^2 / 2 and their slopes. value() and gradient() without
  // their divisions and branches, equal up to rounding (test_shape_functions). False, and nothing
  // set, on an edge half cell: the caller then takes the general path.
  KOKKOS_INLINE_FUNCTION static bool domainStencil(double xi, double /*lh*/, double invh, int ncells, int& first,
                                                   int& count, double* w, double* gr) {
    const int i = floorToInt(xi + 0.5);
    if (i < 1 || i > ncells - 1) return false;
    const double d = xi - i, a = 0.5 - d, b = 0.5 + d;
    first = i - 1;
    count = 3;
    w[0] = 0.5 * a * a;
    w[1] = 0.75 - d * d;
    w[2] = 0.5 * b * b;
    gr[0] = -a * invh;
    gr[1] = -2.0 * d * invh;
    gr[2] = b * invh;
    return true;
  }
};

// Cubic B-spline MPM (Steffen, Kirby & Berzins 2008, IJNME 76; de Vaucorbeil, Nguyen, Sinaie & Wu
// 2020, Adv. Appl. Mech. 53, their "modified cubic B-splines"): the particle is a point and node
// i's function is the uniform C2 cubic B-spline with knots at the grid nodes, support |r| < 2 h:
// with s = |r| / h, 2/3 - s^2 + s^3/2 for s < 1, (2 - s)^3 / 6 for s < 2. Always 4 nodes per
// direction: the particle's cell's two nodes and one more either side.
// Grid edge: nodes -1 and n + 1 are missing. Their B-splines are folded into the two nodes next
// to the edge so that constants and linears stay in the space, B_0 + 2 B_-1 and B_1 - B_-1 (at
// the far edge B_n + 2 B_n+1 and B_n-1 - B_n+1), which changes the edge cell only: there, with
// t = x / h from the edge, the edge node's function is 1 - t + t^3/6 and its neighbour's
// 2/3 - (1 - t)^2 + (1 - t)^3/3 (the paper's boundary functions). This is the natural spline
// space (second derivative zero on the grid's edge lines: the control points' second difference
// vanishes there), chosen over an open knot vector because it keeps one function per grid node
// (an open knot vector has n + 3), keeps C2 everywhere, and every function stays non-negative;
// it interpolates at the edge nodes (only the edge node is non-zero on the edge line), so a
// support or load there acts at the point, and a free or simply supported edge has no moment
// (w'' = 0) anyway.
// What holds on the whole grid [0, n h], edge cells included: sum_i S_i = 1, sum_i dS_i = 0,
// sum_i S_i x_i = x_p and sum_i dS_i x_i = 1; every S_i is C2 (no jump in the gradient or in its
// derivative when a particle crosses a cell line). Quadratics are not reproduced (inside,
// sum_i S_i x_i^2 = x_p^2 + h^2/3). Needs at least 3 cells per direction (4 nodes).
struct CubicBSpline {
  static constexpr int max_nodes_1d = 4;
  static constexpr bool fixed_count = true;
  static constexpr const char* name = "B-Spline Cubic";

  // The uniform cubic B-spline and its derivative in r.
  KOKKOS_INLINE_FUNCTION static double uniform(double r, double h) {
    const double s = (r < 0 ? -r : r) / h;
    if (s < 1.0) return 2.0 / 3.0 - s * s + 0.5 * s * s * s;
    if (s < 2.0) return (2.0 - s) * (2.0 - s) * (2.0 - s) / 6.0;
    return 0.0;
  }
  KOKKOS_INLINE_FUNCTION static double uniformGradient(double r, double h) {
    const double s = (r < 0 ? -r : r) / h;
    const double sign = r < 0 ? -1.0 : 1.0;
    if (s < 1.0) return sign * (1.5 * s - 2.0) * s / h;
    if (s < 2.0) return -sign * 0.5 * (2.0 - s) * (2.0 - s) / h;
    return 0.0;
  }
  // The missing node's spline that node `node` takes in (weight 2 for the edge node, -1 for its
  // neighbour), as an offset in cells from `node` to the missing node; 0: none.
  KOKKOS_INLINE_FUNCTION static int edgeFold(int node, int cells, double& factor) {
    factor = node == 0 || node == cells ? 2.0 : -1.0;
    if (node == 0) return -1;
    if (node == 1) return -2;
    if (node == cells) return 1;
    if (node == cells - 1) return 2;
    return 0;
  }
  KOKKOS_INLINE_FUNCTION static double value(double r, double h, double /*l*/, int node, int cells) {
    double factor;
    const int fold = edgeFold(node, cells, factor);
    return fold == 0 ? uniform(r, h) : uniform(r, h) + factor * uniform(r - fold * h, h);
  }
  KOKKOS_INLINE_FUNCTION static double gradient(double r, double h, double /*l*/, int node, int cells) {
    double factor;
    const int fold = edgeFold(node, cells, factor);
    return fold == 0 ? uniformGradient(r, h) : uniformGradient(r, h) + factor * uniformGradient(r - fold * h, h);
  }
  // The nodes of the cell holding xi and one more either side (ParticleStencil keeps them
  // inside the grid; the extra node there has weight 0).
  KOKKOS_INLINE_FUNCTION static void range(double xi, double /*l_over_h*/, int& first, int& count) {
    first = floorToInt(xi) - 1;
    count = 4;
  }
  // The whole stencil of a point off the edge cells (cell i from 1 to cells - 2: the folded-in
  // splines of the missing nodes reach the edge cells only), from xi = (x - origin) / h: with
  // f = xi - i, the uniform spline's four pieces (1 - f)^3 / 6, 2/3 - f^2 + f^3 / 2,
  // 2/3 - g^2 + g^3 / 2 and f^3 / 6 (g = 1 - f) and their slopes. value() and gradient() without
  // their divisions and branches, equal up to rounding (test_shape_functions). False, and nothing
  // set, in an edge cell: the caller then takes the general path.
  KOKKOS_INLINE_FUNCTION static bool domainStencil(double xi, double /*lh*/, double invh, int ncells, int& first,
                                                   int& count, double* w, double* gr) {
    const int i = floorToInt(xi);
    if (i < 1 || i > ncells - 2) return false;
    const double f = xi - i, g = 1.0 - f;
    first = i - 1;
    count = 4;
    w[0] = g * g * g * (1.0 / 6.0);
    w[1] = 2.0 / 3.0 - f * f + 0.5 * f * f * f;
    w[2] = 2.0 / 3.0 - g * g + 0.5 * g * g * g;
    w[3] = f * f * f * (1.0 / 6.0);
    gr[0] = -0.5 * g * g * invh;
    gr[1] = (1.5 * f - 2.0) * f * invh;
    gr[2] = -(1.5 * g - 2.0) * g * invh;
    gr[3] = 0.5 * f * f * invh;
    return true;
  }
};

}  // namespace impm
