// Shape-function traits: partition of unity, zero gradient sum, and the uGIMP weights and
// gradient weights against numerical quadrature of the particle characteristic function.
#include <Teuchos_UnitTestHarness.hpp>

#include <random>

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
