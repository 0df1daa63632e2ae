// Shape-function traits: partition of unity, zero gradient sum, and the uGIMP weights and
// gradient weights against numerical quadrature of the particle characteristic function.
#include <Teuchos_UnitTestHarness.hpp>

#include <algorithm>
#include <cmath>
#include <random>
#include <type_traits>

#include "core/ParticleStencil.hpp"

namespace {

using impm::LinearMpm;
using impm::ParticleStencil;
using impm::StructuredGrid;
using impm::UniformGimp;

StructuredGrid testGrid() {
  StructuredGrid g;
  g.x0 = -0.3; g.y0 = 0.1; g.hx = 0.5; g.hy = 0.25; g.nx = 12; g.ny = 9;
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
// also sum S x_i^2 = x_p^2 (quadratic completeness).
template <class Shape>
void checkPartitionOfUnity3d(Teuchos::FancyOStream& out, bool& success) {
  StructuredGrid g = testGrid();
  g.dim = 3; g.z0 = 0.2; g.hz = 0.4; g.nz = 8;
  if (std::is_same<Shape, impm::QuadraticLagrange>::value) g.ny = 10;  // even cell counts
  std::mt19937 rng(17);
  std::uniform_real_distribution<double> frac(0.05, 0.5);
  impm::LocalNodeIndexer ix{0, g.nx + 1, g.ny + 1, g.nz + 1};
  double worst = 0;
  for (int k = 0; k < 1000; ++k) {
    double xc[3], l[3];
    for (int d = 0; d < 3; ++d) {
      std::uniform_real_distribution<double> u(g.origin(d) + g.spacing(d), g.origin(d) + (g.cells(d) - 1) * g.spacing(d));
      xc[d] = u(rng);
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

}  // namespace
