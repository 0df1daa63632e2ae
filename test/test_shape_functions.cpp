// Shape-function traits: partition of unity, zero gradient sum, and the uGIMP weights and
// gradient weights against numerical quadrature of the particle characteristic function;
// quadratic and cubic B-splines up to the grid edge (partition of unity, linear completeness,
// C1 and C2).
#include <Teuchos_UnitTestHarness.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <type_traits>
#include <vector>

#include "core/ParticleStencil.hpp"

namespace {

using impm::CubicBSpline;
using impm::LinearMpm;
using impm::ParticleStencil;
using impm::QuadraticBSpline;
using impm::StructuredGrid;
using impm::UniformGimp;

StructuredGrid testGrid() {
  StructuredGrid g;
  g.x0 = -0.3;
  g.y0 = 0.1;
  g.hx = 0.5;
  g.hy = 0.25;
  g.nx = 12;
  g.ny = 9;
  return g;
}

template <class Shape>
void checkPartitionOfUnity(Teuchos::FancyOStream& out, bool& success) {
  const StructuredGrid g = testGrid();
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> ux(g.x0 + g.hx, g.xMax() - g.hx), uy(g.y0 + g.hy, g.yMax() - g.hy);
  std::uniform_real_distribution<double> frac(0.05, 0.5);
  for (int k = 0; k < 2000; ++k) {
    const double x = ux(rng), y = uy(rng), lx = frac(rng) * g.hx, ly = frac(rng) * g.hy;
    const ParticleStencil<Shape> st(g, x, y, lx, ly);
    double sum = 0, gxs = 0, gys = 0, firstMomentX = 0;
    for (int a = 0; a < st.count[0]; ++a)
      for (int b = 0; b < st.count[1]; ++b) {
        sum += st.weight(a, b);
        gxs += st.gradX(a, b);
        gys += st.gradY(a, b);
        firstMomentX += st.weight(a, b) * g.nodeX(st.first[0] + a);
      }
    TEST_FLOATING_EQUALITY(sum, 1.0, 1e-13);
    TEST_COMPARE(std::abs(gxs), <, 1e-12 / g.hx);
    TEST_COMPARE(std::abs(gys), <, 1e-12 / g.hy);
    // Linear completeness: sum S_ip x_i reproduces x_p.
    TEST_FLOATING_EQUALITY(firstMomentX, x, 1e-12);
  }
}

TEUCHOS_UNIT_TEST(ShapeFunctions, LinearMpmPartitionOfUnity) { checkPartitionOfUnity<LinearMpm>(out, success); }
TEUCHOS_UNIT_TEST(ShapeFunctions, UniformGimpPartitionOfUnity) { checkPartitionOfUnity<UniformGimp>(out, success); }

// The same in 3D through forEachNode/forEachOffset (the kernels' loops): sum S = 1, sum grad S = 0,
// and linear completeness in every direction, sum S x_i = x_p and sum grad_j S x_i,k = delta_jk
// (a linear field and its gradient are reproduced exactly). For the quadratic element (Hex27)
// also sum S x_i^2 = x_p^2 (quadratic completeness). wholeGrid: positions over the whole grid,
// edge cells included, a fifth of them on the edge lines or half a cell from them (B-splines);
// otherwise one cell away from the edges.
template <class Shape>
void checkPartitionOfUnity3d(Teuchos::FancyOStream& out, bool& success, bool wholeGrid = false) {
  StructuredGrid g = testGrid();
  g.dim = 3;
  g.z0 = 0.2;
  g.hz = 0.4;
  g.nz = 8;
  if (std::is_same<Shape, impm::QuadraticLagrange>::value) g.ny = 10;  // even cell counts
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> frac(0.05, 0.5);
  const auto ix = impm::LocalNodeIndexer::wholeGrid(g);
  double worst = 0;
  for (int k = 0; k < 1000; ++k) {
    double xc[3], l[3];
    for (int d = 0; d < 3; ++d) {
      const double margin = wholeGrid ? 0.0 : 1.0;
      std::uniform_real_distribution<double> u(g.origin(d) + margin * g.spacing(d),
                                               g.origin(d) + (g.cells(d) - margin) * g.spacing(d));
      xc[d] = u(rng);
      if (wholeGrid && k % 5 == 0) {
        const double offset[6] = {0.0, 0.25, 0.5, g.cells(d) - 0.5, g.cells(d) - 0.25, 1.0 * g.cells(d)};
        xc[d] = g.origin(d) + offset[(k / 5 + d) % 6] * g.spacing(d);
      }
      l[d] = frac(rng) * g.spacing(d);
    }
    const ParticleStencil<Shape, 3> st(g, xc, l);
    double sum = 0, grad[3] = {0, 0, 0}, moment[3] = {0, 0, 0}, dmoment[3][3] = {}, second = 0;
    st.forEachOffset([&](const int* off, double w, const double* gr) {
      double xn[3];
      for (int d = 0; d < 3; ++d) xn[d] = g.origin(d) + (st.first[d] + off[d]) * g.spacing(d);
      sum += w;
      second += w * xn[0] * xn[0];
      for (int d = 0; d < 3; ++d) {
        grad[d] += gr[d];
        moment[d] += w * xn[d];
        for (int e = 0; e < 3; ++e) dmoment[d][e] += gr[d] * xn[e];
      }
    });
    // forEachNode visits the same nodes with the same weights, by grid index.
    double sumByIndex = 0;
    st.forEachNode(ix, [&](int n, double w, const double*) {
      TEST_ASSERT(n >= 0 && n < ix.size());
      sumByIndex += w;
    });
    worst = std::max(worst, std::abs(sum - 1.0));
    TEST_FLOATING_EQUALITY(sum, 1.0, 1e-13);
    TEST_FLOATING_EQUALITY(sumByIndex, sum, 1e-14);
    for (int d = 0; d < 3; ++d) {
      TEST_COMPARE(std::abs(grad[d]), <, 1e-12 / g.spacing(d));
      TEST_FLOATING_EQUALITY(moment[d], xc[d], 1e-12);
      for (int e = 0; e < 3; ++e) TEST_COMPARE(std::abs(dmoment[d][e] - (d == e ? 1.0 : 0.0)), <, 1e-11);
    }
    if (std::is_same<Shape, impm::QuadraticLagrange>::value) TEST_FLOATING_EQUALITY(second, xc[0] * xc[0], 1e-12);
  }
  out << Shape::name << " 3D: max |sum S - 1| = " << worst << "\n";
}

TEUCHOS_UNIT_TEST(ShapeFunctions, LinearMpm3dCompleteness) { checkPartitionOfUnity3d<LinearMpm>(out, success); }
TEUCHOS_UNIT_TEST(ShapeFunctions, UniformGimp3dCompleteness) { checkPartitionOfUnity3d<UniformGimp>(out, success); }
TEUCHOS_UNIT_TEST(ShapeFunctions, Hex27Completeness) { checkPartitionOfUnity3d<impm::QuadraticLagrange>(out, success); }
TEUCHOS_UNIT_TEST(ShapeFunctions, BSpline3dCompletenessUpToTheEdge) {
  checkPartitionOfUnity3d<QuadraticBSpline>(out, success, true);
}

// B-splines in 2D at positions sweeping the whole grid in x (edge cells, grid lines and half-cell
// lines included) at y on the edges, their half-cell lines and inside: N x N nodes (3 quadratic,
// 4 cubic) inside the grid, non-negative weights, sum S = 1, sum grad S = 0, sum S x_i = x_p,
// sum S y_i = y_p and sum grad_j S x_i,k = delta_jk.
template <class Shape>
void checkSplineCompletenessUpToTheEdge(Teuchos::FancyOStream& out, bool& success) {
  constexpr int N = Shape::max_nodes_1d;
  const StructuredGrid g = testGrid();
  const int perCell = 40;
  int visited = 0;
  for (int ix = 0; ix <= perCell * g.nx; ++ix)
    for (double fy : {0.0, 0.2, 0.5, 1.0, 4.37, g.ny - 1.0, g.ny - 0.5, g.ny - 0.1, 1.0 * g.ny}) {
      const double x = g.x0 + ix * g.hx / perCell, y = g.y0 + fy * g.hy;
      const ParticleStencil<Shape> st(g, x, y, 0.0, 0.0);
      TEST_EQUALITY_CONST(st.countX(), N);
      TEST_EQUALITY_CONST(st.countY(), N);
      TEST_ASSERT(st.first[0] >= 0 && st.first[0] + N - 1 <= g.nx && st.first[1] >= 0 && st.first[1] + N - 1 <= g.ny);
      double sum = 0, gx = 0, gy = 0, mx = 0, my = 0, dxx = 0, dxy = 0, dyx = 0, dyy = 0;
      for (int a = 0; a < N; ++a)
        for (int b = 0; b < N; ++b) {
          const double xi = g.nodeX(st.first[0] + a), yi = g.y0 + (st.first[1] + b) * g.hy;
          TEST_COMPARE(st.weight(a, b), >=, 0.0);
          sum += st.weight(a, b);
          gx += st.gradX(a, b);
          gy += st.gradY(a, b);
          mx += st.weight(a, b) * xi;
          my += st.weight(a, b) * yi;
          dxx += st.gradX(a, b) * xi;
          dxy += st.gradX(a, b) * yi;
          dyx += st.gradY(a, b) * xi;
          dyy += st.gradY(a, b) * yi;
        }
      TEST_FLOATING_EQUALITY(sum, 1.0, 1e-13);
      TEST_COMPARE(std::abs(gx), <, 1e-12 / g.hx);
      TEST_COMPARE(std::abs(gy), <, 1e-12 / g.hy);
      TEST_COMPARE(std::abs(mx - x), <, 1e-13 * (1 + std::abs(x)));
      TEST_COMPARE(std::abs(my - y), <, 1e-13 * (1 + std::abs(y)));
      TEST_FLOATING_EQUALITY(dxx, 1.0, 1e-12);
      TEST_FLOATING_EQUALITY(dyy, 1.0, 1e-12);
      TEST_COMPARE(std::abs(dxy), <, 1e-12);
      TEST_COMPARE(std::abs(dyx), <, 1e-12);
      ++visited;
    }
  TEST_EQUALITY(visited, (perCell * g.nx + 1) * 9);
}

TEUCHOS_UNIT_TEST(ShapeFunctions, BSplineCompletenessUpToTheEdge) {
  checkSplineCompletenessUpToTheEdge<QuadraticBSpline>(out, success);
}
TEUCHOS_UNIT_TEST(ShapeFunctions, CubicBSplineCompletenessUpToTheEdge) {
  checkSplineCompletenessUpToTheEdge<CubicBSpline>(out, success);
}
TEUCHOS_UNIT_TEST(ShapeFunctions, CubicBSpline3dCompletenessUpToTheEdge) {
  checkPartitionOfUnity3d<CubicBSpline>(out, success, true);
}

// Jumps of a B-spline's 1D weights over the whole grid at every cell line, half-cell line and
// quarter-cell line: in the weight, in h x its gradient weight and in h^2 x the gradient
// weight's one-sided derivatives (left and right of the line, over 1e-5 h); and how far the gradient weight
// is from the finite difference of the weight.
struct SplineJumps {
  double value = 0, gradient = 0, curvature = 0, derivative = 0;
};
template <class Shape>
SplineJumps splineJumps(const StructuredGrid& g) {
  constexpr int N = Shape::max_nodes_1d;
  const double h = g.hx, eps = 1e-7 * h, step = 1e-5 * h, y = g.y0 + 3.3 * g.hy;
  // Weight and gradient weight of grid node i for a particle at x (0 off the stencil).
  auto weightOf = [&](int i, double x, double& w, double& gr) {
    const ParticleStencil<Shape> st(g, x, y, 0.0, 0.0);
    w = gr = 0;
    const int a = i - st.first[0];
    if (a < 0 || a >= N) return;
    double wy = 0;  // 1 (partition of unity in y)
    for (int b = 0; b < N; ++b) wy += st.w[1][b];
    w = st.w[0][a] * wy;
    gr = st.g[0][a] * wy;
  };
  SplineJumps j;
  for (int i = 0; i <= g.nx; ++i)
    for (int q = 1; q < 40 * g.nx; ++q) {
      const double x = g.x0 + q * h / 40;  // hits every cell line and half-cell line
      double wm, gm, wp, gp, w, gr, wmm, gmm, wpp, gpp;
      weightOf(i, x - eps, wm, gm);
      weightOf(i, x + eps, wp, gp);
      weightOf(i, x, w, gr);
      weightOf(i, x - step, wmm, gmm);
      weightOf(i, x + step, wpp, gpp);
      j.value = std::max(j.value, std::abs(wp - wm));
      j.gradient = std::max(j.gradient, std::abs(gp - gm) * h);
      j.curvature = std::max(j.curvature, std::abs((gpp - gr) / step - (gr - gmm) / step) * h * h);
      j.derivative = std::max(j.derivative, std::abs((wp - wm) / (2 * eps) - gr) * h);
    }
  return j;
}

// The 1D quadratic B-spline weights of every node are C1 in the particle position over the whole
// grid (no jump in weight or gradient at cell lines, half-cell lines or where the edge tents
// join), the gradient weight is the derivative of the weight, and inside the grid a particle on
// a node gives it 3/4 and each neighbour 1/8; on the edge node it takes all the weight. They are
// not C2: the second derivative jumps by 3/h^2 where pieces meet (the curvature check sees it).
TEUCHOS_UNIT_TEST(ShapeFunctions, BSplineIsC1UpToTheEdge) {
  const StructuredGrid g = testGrid();
  const SplineJumps j = splineJumps<QuadraticBSpline>(g);
  out << "B-spline: max jump over 2e-7 h: " << std::max(j.value, j.gradient)
      << " (w, h grad w); max |FD - grad| h: " << j.derivative << "; max jump of h^2 w'': " << j.curvature << "\n";
  TEST_COMPARE(j.value, <, 1e-6);
  TEST_COMPARE(j.gradient, <, 1e-6);
  TEST_COMPARE(j.derivative, <, 1e-6);
  TEST_COMPARE(j.curvature, >, 1.0);
  auto weight = [&](int i, double x) {
    const ParticleStencil<QuadraticBSpline> st(g, x, g.y0 + 3.3 * g.hy, 0.0, 0.0);
    return st.w[0][i - st.first[0]];
  };
  TEST_FLOATING_EQUALITY(weight(5, g.nodeX(5)), 0.75, 1e-14);
  TEST_FLOATING_EQUALITY(weight(4, g.nodeX(5)), 0.125, 1e-14);
  TEST_FLOATING_EQUALITY(weight(6, g.nodeX(5)), 0.125, 1e-14);
  TEST_FLOATING_EQUALITY(weight(0, g.x0), 1.0, 1e-14);
  TEST_FLOATING_EQUALITY(weight(g.nx, g.xMax()), 1.0, 1e-14);
}

// Cubic B-splines are C2 over the whole grid, edge cells included (the folded edge functions
// join the uniform ones with matching second derivatives one cell from the edge): the one-sided
// second derivatives, by differences over 1e-4 h, agree to O(1e-4) where the quadratic ones jump
// by 3. A particle on an inner node gives it 2/3 and each neighbour 1/6; on the edge node it
// gives that node all its weight (the spline interpolates there), and a third of the way into
// the edge cell the edge node has the paper's 1 - t + t^3/6. Inside, sum S x_i^2 = x_p^2 + h^2/3
// (quadratics are not reproduced).
TEUCHOS_UNIT_TEST(ShapeFunctions, CubicBSplineIsC2UpToTheEdge) {
  const StructuredGrid g = testGrid();
  const SplineJumps j = splineJumps<CubicBSpline>(g);
  out << "cubic B-spline: max jump over 2e-7 h: " << std::max(j.value, j.gradient)
      << " (w, h grad w); max |FD - grad| h: " << j.derivative << "; max jump of h^2 w'': " << j.curvature << "\n";
  TEST_COMPARE(j.value, <, 1e-6);
  TEST_COMPARE(j.gradient, <, 1e-6);
  TEST_COMPARE(j.derivative, <, 1e-6);
  TEST_COMPARE(j.curvature, <, 1e-3);
  auto weight = [&](int i, double x) {
    const ParticleStencil<CubicBSpline> st(g, x, g.y0 + 3.3 * g.hy, 0.0, 0.0);
    const int a = i - st.first[0];
    return a >= 0 && a < 4 ? st.w[0][a] : 0.0;
  };
  TEST_FLOATING_EQUALITY(weight(5, g.nodeX(5)), 2.0 / 3.0, 1e-14);
  TEST_FLOATING_EQUALITY(weight(4, g.nodeX(5)), 1.0 / 6.0, 1e-14);
  TEST_FLOATING_EQUALITY(weight(6, g.nodeX(5)), 1.0 / 6.0, 1e-14);
  for (int i : {0, g.nx}) {
    const double edge = g.nodeX(i), inward = i == 0 ? 1.0 : -1.0;
    TEST_FLOATING_EQUALITY(weight(i, edge), 1.0, 1e-14);
    TEST_COMPARE(std::abs(weight(i + (int)inward, edge)), <, 1e-15);
    const double t = 1.0 / 3.0;
    TEST_FLOATING_EQUALITY(weight(i, edge + inward * t * g.hx), 1.0 - t + t * t * t / 6.0, 1e-13);
  }
  for (double fx : {3.0, 4.25, 6.5, 7.9}) {
    const double x = g.x0 + fx * g.hx;
    const ParticleStencil<CubicBSpline> st(g, x, g.y0 + 3.3 * g.hy, 0.0, 0.0);
    double second = 0;
    for (int a = 0; a < 4; ++a) second += st.w[0][a] * g.nodeX(st.first[0] + a) * g.nodeX(st.first[0] + a);
    TEST_FLOATING_EQUALITY(second, x * x + g.hx * g.hx / 3.0, 1e-12);
  }
}

// S_ip = (1/2l) int_{x_p-l}^{x_p+l} N_i(x) dx and G_ip = (1/2l) int dN_i/dx dx, by a fine
// midpoint rule. The tent's kinks make the rule O(h_q^2) accurate: 1e5 points give ~1e-9.
TEUCHOS_UNIT_TEST(ShapeFunctions, UniformGimpMatchesQuadrature) {
  const double h = 0.7;
  auto tent = [&](double r) { return std::max(0.0, 1.0 - std::abs(r) / h); };
  auto tentSlope = [&](double r) { return std::abs(r) < h ? (r > 0 ? -1.0 : 1.0) / h : 0.0; };
  const int nq = 100000;
  for (double l : {0.05 * h, 0.2 * h, 0.37 * h, 0.5 * h}) {
    for (double r = -1.6 * h; r <= 1.6 * h; r += 0.0731 * h) {
      // r = x_p - x_i; integrate over x - x_i in [r - l, r + l].
      double s = 0, gq = 0;
      for (int q = 0; q < nq; ++q) {
        const double xq = r - l + (q + 0.5) * (2 * l / nq);
        s += tent(xq);
        gq += tentSlope(xq);
      }
      s /= nq;
      gq /= nq;
      TEST_COMPARE(std::abs(UniformGimp::value(r, h, l) - s), <, 1e-8);
      TEST_COMPARE(std::abs(UniformGimp::gradient(r, h, l) - gq), <, 1e-4 / h);
    }
  }
}

// The gradient weight is the derivative of the weight with respect to the particle position.
TEUCHOS_UNIT_TEST(ShapeFunctions, GradientIsDerivativeOfWeight) {
  const double h = 1.3, l = 0.3, eps = 1e-7;
  for (double r = -1.55; r <= 1.55; r += 0.0377) {
    const double fdG = (UniformGimp::value(r + eps, h, l) - UniformGimp::value(r - eps, h, l)) / (2 * eps);
    TEST_COMPARE(std::abs(UniformGimp::gradient(r, h, l) - fdG), <, 1e-6);
  }
}

// Every node outside a stencil has zero weight: the stencil is complete.
TEUCHOS_UNIT_TEST(ShapeFunctions, GimpStencilIsComplete) {
  const StructuredGrid g = testGrid();
  for (double x = g.x0 + 0.3 * g.hx; x < g.xMax() - 0.3 * g.hx; x += 0.0913 * g.hx) {
    const double l = 0.25 * g.hx;
    const ParticleStencil<UniformGimp> st(g, x, g.y0 + 2.5 * g.hy, l, 0.1 * g.hy);
    for (int i = 0; i <= g.nx; ++i) {
      if (i >= st.first[0] && i < st.first[0] + st.count[0]) continue;
      TEST_EQUALITY_CONST(UniformGimp::value(x - g.nodeX(i), g.hx, l), 0.0);
    }
  }
}

// LinearMpm's interior fast path (interiorStencil, taken by the stencil for points strictly
// inside a cell) gives the per-node value() and gradient() to round-off, and declines on cell
// lines, at the grid edge and outside, where the general path's clamping applies.
TEUCHOS_UNIT_TEST(ShapeFunctions, LinearMpmInteriorStencilMatchesTheTraits) {
  const StructuredGrid g = testGrid();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> ux(g.x0, g.xMax());
  for (int k = 0; k < 5000; ++k) {
    const double x = ux(rng);
    int first = -1;
    double w[2], gr[2];
    TEST_ASSERT(LinearMpm::interiorStencil((x - g.x0) / g.hx, 1.0 / g.hx, g.nx, first, w, gr));
    TEST_EQUALITY(first, (int)std::floor((x - g.x0) / g.hx));
    for (int a = 0; a < 2; ++a) {
      const double r = x - g.nodeX(first + a);
      TEST_COMPARE(std::abs(w[a] - LinearMpm::value(r, g.hx, 0.0)), <, 1e-14);
      TEST_COMPARE(std::abs(gr[a] - LinearMpm::gradient(r, g.hx, 0.0)), <, 1e-14 / g.hx);
    }
  }
  int first = -1;
  double w[2], gr[2];
  for (double xi : {0.0, 3.0, double(g.nx), -0.5, g.nx + 0.25})
    TEST_ASSERT(!LinearMpm::interiorStencil(xi, 1.0 / g.hx, g.nx, first, w, gr));
  TEST_EQUALITY_CONST(first, -1);
  // On the last grid line the stencil keeps the last cell (general path): weight 1 at the end node.
  const ParticleStencil<LinearMpm> st(g, g.xMax(), g.y0 + 2.5 * g.hy, 0.0, 0.0);
  TEST_EQUALITY(st.first[0], g.nx - 1);
  TEST_FLOATING_EQUALITY(st.w[0][1], 1.0, 1e-14);
}

// The fast paths of GIMP and the B-splines (domainStencil, taken by the stencil wherever the
// domain or point is off the grid's edge functions) give the per-node value() and gradient() to
// round-off, on the same nodes (a node either path leaves out has zero weight in the other), and
// decline where the general path's clipping or edge functions apply. Points: random ones and the
// 5-per-cell lattice, whose GIMP domains end on cell lines.
template <class Shape>
void checkDomainStencil(const std::vector<double>& halfSizes, Teuchos::FancyOStream& out, bool& success) {
  const StructuredGrid g = testGrid();
  const double invh = 1.0 / g.hx;
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> ux(g.x0, g.xMax());
  std::vector<double> points;
  for (int k = 0; k < 4000; ++k) points.push_back(ux(rng));
  for (int c = 0; c < g.nx; ++c)
    for (int k = 0; k < 5; ++k) points.push_back(g.nodeX(c) + (k + 0.5) * g.hx / 5);
  int taken = 0, declined = 0;
  for (double l : halfSizes)
    for (double x : points) {
      int first = -1, count = 0;
      double w[Shape::max_nodes_1d], gr[Shape::max_nodes_1d];
      if (!Shape::domainStencil((x - g.x0) * invh, l * invh, invh, g.nx, first, count, w, gr)) {
        ++declined;
        TEST_EQUALITY_CONST(first, -1);
        continue;
      }
      ++taken;
      TEST_ASSERT(first >= 0 && first + count - 1 <= g.nx);
      double sumW = 0, sumG = 0;
      for (int i = std::max(0, first - 2); i <= std::min(g.nx, first + count + 1); ++i) {
        const int a = i - first;
        const bool inStencil = a >= 0 && a < count;
        const double r = x - g.nodeX(i);
        const double value = Shape::value(r, g.hx, l, i, g.nx), grad = Shape::gradient(r, g.hx, l, i, g.nx);
        TEST_COMPARE(std::abs((inStencil ? w[a] : 0.0) - value), <, 1e-13);
        TEST_COMPARE(std::abs((inStencil ? gr[a] : 0.0) - grad), <, 1e-13 * invh);
        if (inStencil) {
          sumW += w[a];
          sumG += gr[a];
        }
      }
      TEST_COMPARE(std::abs(sumW - 1.0), <, 1e-14);
      TEST_COMPARE(std::abs(sumG), <, 1e-13 * invh);
    }
  out << Shape::name << ": fast path taken for " << taken << " points, declined for " << declined << "\n";
  TEST_COMPARE(taken, >, 2 * declined);  // declined only in the edge cells (2 of 12)
  TEST_COMPARE(declined, >, 0);
  int first = -1, count = 0;
  double w[Shape::max_nodes_1d], gr[Shape::max_nodes_1d];
  // At and across the grid's edges the general path's clipping or edge functions apply.
  for (double xi : {0.05, g.nx - 0.05, g.nx + 0.25, -0.5})
    TEST_ASSERT(!Shape::domainStencil(xi, 0.1, invh, g.nx, first, count, w, gr));
  TEST_EQUALITY_CONST(first, -1);
}

TEUCHOS_UNIT_TEST(ShapeFunctions, GimpDomainStencilMatchesTheTraits) {
  checkDomainStencil<UniformGimp>({0.05, 0.1, 0.125, 0.2, 0.25}, out, success);
  int first = -1, count = 0;
  double w[3], gr[3];
  // A domain wider than a cell (l > h/2) is the general path's.
  TEST_ASSERT(!UniformGimp::domainStencil(4.5, 0.6, 2.0, 12, first, count, w, gr));
}
TEUCHOS_UNIT_TEST(ShapeFunctions, QuadraticBSplineDomainStencilMatchesTheTraits) {
  checkDomainStencil<QuadraticBSpline>({0.0}, out, success);
}
TEUCHOS_UNIT_TEST(ShapeFunctions, CubicBSplineDomainStencilMatchesTheTraits) {
  checkDomainStencil<CubicBSpline>({0.0}, out, success);
}

}  // namespace
