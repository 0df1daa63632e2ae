// CPDI1 (core/CpdiStencil.hpp): partition of unity and linear completeness for stretched,
// sheared and rotated domains in 2D and 3D; with F = I the weights are the corner averages of the
// tent (a tensor product) and the gradient weights uGIMP's difference quotient times the other
// directions' corner averages, equal to uGIMP when the box stays inside one cell; the node box
// and its cap; corners clipped at the grid edge.
#include <Teuchos_UnitTestHarness.hpp>

#include <cmath>
#include <random>

#include "core/CpdiDomainCheck.hpp"
#include "core/ParticleStencil.hpp"

namespace {

using impm::Cpdi;
using impm::LinearMpm;
using impm::ParticleStencil;
using impm::StructuredGrid;
using impm::UniformGimp;

StructuredGrid grid3d(int dim) {
  StructuredGrid g;
  g.x0 = -0.3;
  g.y0 = 0.1;
  g.hx = 0.5;
  g.hy = 0.25;
  g.nx = 12;
  g.ny = 9;
  if (dim == 3) {
    g.dim = 3;
    g.z0 = 0.2;
    g.hz = 0.4;
    g.nz = 8;
  }
  return g;
}

// A random F = rotation x (stretch + shear) with det > 0, and half sizes (the corners may need
// more than 4 nodes in some direction: callers skip those capped stencils).
template <int Dim>
void randomDomain(std::mt19937& rng, const StructuredGrid& g, double (&F)[Dim * Dim], double (&l)[Dim]) {
  std::uniform_real_distribution<double> stretch(0.5, 2.0), shear(-0.8, 0.8), angle(-3.1, 3.1), frac(0.15, 0.5);
  double A[3][3] = {};
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) A[i][j] = i == j ? stretch(rng) : j > i ? shear(rng) : 0.0;
  double Q[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  const double a = angle(rng), c = std::cos(a), s = std::sin(a);
  Q[0][0] = c;
  Q[0][1] = -s;
  Q[1][0] = s;
  Q[1][1] = c;
  if (Dim == 3) {  // and a rotation about x
    const double b = angle(rng), cb = std::cos(b), sb = std::sin(b);
    const double R[3][3] = {{1, 0, 0}, {0, cb, -sb}, {0, sb, cb}};
    double QR[3][3] = {};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        for (int k = 0; k < 3; ++k) QR[i][j] += Q[i][k] * R[k][j];
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Q[i][j] = QR[i][j];
  }
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) {
      double v = 0;
      for (int k = 0; k < Dim; ++k) v += Q[i][k] * A[k][j];
      F[Dim * i + j] = v;
    }
  for (int d = 0; d < Dim; ++d) l[d] = frac(rng) * g.spacing(d);
}

template <int Dim>
void checkCompleteness(Teuchos::FancyOStream& out, bool& success) {
  const StructuredGrid g = grid3d(Dim);
  std::mt19937 rng(11 + Dim);
  const auto ix = impm::LocalNodeIndexer::wholeGrid(g);
  double worst = 0;
  int capped = 0, spread = 0;
  for (int k = 0; k < 1000; ++k) {
    double F[Dim * Dim], l[Dim], xc[Dim];
    randomDomain<Dim>(rng, g, F, l);
    for (int d = 0; d < Dim; ++d) {  // 2 cells from the edges: no corner is clipped
      std::uniform_real_distribution<double> u(g.origin(d) + 2 * g.spacing(d),
                                               g.origin(d) + (g.cells(d) - 2) * g.spacing(d));
      xc[d] = u(rng);
    }
    const ParticleStencil<Cpdi, Dim> st(g, xc, l, F);
    if (st.capped) {
      ++capped;
      continue;
    }
    double sum = 0, grad[Dim] = {}, moment[Dim] = {}, dmoment[Dim][Dim] = {};
    st.forEachOffset([&](const int* off, double w, const double* gr) {
      for (int d = 0; d < Dim; ++d) {
        const double xn = g.origin(d) + (st.first[d] + off[d]) * g.spacing(d);
        moment[d] += w * xn;
        grad[d] += gr[d];
        for (int e = 0; e < Dim; ++e) dmoment[e][d] += gr[e] * xn;
      }
      sum += w;
    });
    bool four = false;
    for (int d = 0; d < Dim; ++d) four = four || st.count[d] == 4;
    spread += four;
    double byIndex = 0;
    st.forEachNode(ix, [&](int n, double w, const double*) {
      TEST_ASSERT(n >= 0 && n < ix.size());
      byIndex += w;
    });
    TEST_FLOATING_EQUALITY(byIndex, sum, 1e-14);
    worst = std::max(worst, std::abs(sum - 1.0));
    for (int d = 0; d < Dim; ++d) {
      worst = std::max(worst, std::abs(grad[d]) * g.spacing(d));
      worst = std::max(worst, std::abs(moment[d] - xc[d]) / g.spacing(d));
      for (int e = 0; e < Dim; ++e) worst = std::max(worst, std::abs(dmoment[e][d] - (d == e ? 1.0 : 0.0)));
    }
  }
  out << Dim << "D CPDI, 1000 random domains (" << capped << " capped, skipped; " << spread
      << " with 4 nodes in some direction): worst deviation " << worst
      << " from sum S = 1, sum grad S = 0, sum S x = x_p, sum grad S x^T = I\n";
  TEST_COMPARE(worst, <, 1e-12);
  TEST_COMPARE(spread, >, 100);  // the non-tensor 4-node boxes were exercised
  TEST_COMPARE(capped, <, 300);
}

TEUCHOS_UNIT_TEST(Cpdi, PartitionOfUnityAndLinearCompleteness2d) { checkCompleteness<2>(out, success); }
TEUCHOS_UNIT_TEST(Cpdi, PartitionOfUnityAndLinearCompleteness3d) { checkCompleteness<3>(out, success); }

// F = I: the corner average of the tent factorises, S = prod_d (N(x_d - l_d) + N(x_d + l_d)) / 2,
// and the gradient along x is (N(x + l) - N(x - l)) / (2 l), which is uGIMP's gradient weight
// (the domain average of N'), times the corner averages of the other directions. When the box
// lies inside one cell the tent is linear over it, corner average = domain average, and CPDI1 is
// uGIMP exactly.
TEUCHOS_UNIT_TEST(Cpdi, IdentityIsTheCornerAverageAndUGimpInsideACell) {
  const StructuredGrid g = grid3d(2);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> ux(g.x0 + g.hx, g.xMax() - g.hx), uy(g.y0 + g.hy, g.yMax() - g.hy),
      frac(0.05, 0.5);
  const double I[4] = {1, 0, 0, 1};
  int insideOneCell = 0;
  for (int k = 0; k < 500; ++k) {
    const double xc[2] = {ux(rng), uy(rng)}, l[2] = {frac(rng) * g.hx, frac(rng) * g.hy};
    const ParticleStencil<Cpdi, 2> st(g, xc, l, I);
    const ParticleStencil<UniformGimp, 2> gimp(g, xc[0], xc[1], l[0], l[1]);
    const bool oneCell = std::floor((xc[0] - l[0] - g.x0) / g.hx) == std::floor((xc[0] + l[0] - g.x0) / g.hx) &&
                         std::floor((xc[1] - l[1] - g.y0) / g.hy) == std::floor((xc[1] + l[1] - g.y0) / g.hy);
    insideOneCell += oneCell;
    for (int a = 0; a < st.countX(); ++a)
      for (int b = 0; b < st.countY(); ++b) {
        const double rx = xc[0] - g.nodeX(st.first[0] + a), ry = xc[1] - g.nodeY(st.first[1] + b);
        const double avgX = 0.5 * (LinearMpm::value(rx - l[0], g.hx, 0) + LinearMpm::value(rx + l[0], g.hx, 0));
        const double avgY = 0.5 * (LinearMpm::value(ry - l[1], g.hy, 0) + LinearMpm::value(ry + l[1], g.hy, 0));
        TEST_FLOATING_EQUALITY(st.weight(a, b) + 1.0, avgX * avgY + 1.0, 1e-13);
        TEST_FLOATING_EQUALITY(st.gradX(a, b) * g.hx + 1.0, UniformGimp::gradient(rx, g.hx, l[0]) * avgY * g.hx + 1.0,
                               1e-12);
        TEST_FLOATING_EQUALITY(st.gradY(a, b) * g.hy + 1.0, avgX * UniformGimp::gradient(ry, g.hy, l[1]) * g.hy + 1.0,
                               1e-12);
        if (oneCell) {
          // uGIMP's stencil (2 nodes per direction here) at the same node.
          const int ga = st.first[0] + a - gimp.first[0], gb = st.first[1] + b - gimp.first[1];
          const bool inGimp = ga >= 0 && ga < gimp.countX() && gb >= 0 && gb < gimp.countY();
          const double w = inGimp ? gimp.weight(ga, gb) : 0.0, gx = inGimp ? gimp.gradX(ga, gb) : 0.0;
          TEST_FLOATING_EQUALITY(st.weight(a, b) + 1.0, w + 1.0, 1e-13);
          TEST_FLOATING_EQUALITY(st.gradX(a, b) * g.hx + 1.0, gx * g.hx + 1.0, 1e-12);
        }
      }
  }
  out << insideOneCell << " of 500 boxes inside one cell\n";
  TEST_COMPARE(insideOneCell, >, 20);
}

// The node box: corners in 3 cells per direction take 4 nodes; in 4 cells the box is capped at
// 4 nodes and flagged (the run loop stops such a run).
TEUCHOS_UNIT_TEST(Cpdi, NodeBoxAndCap) {
  const StructuredGrid g = grid3d(2);
  const double xc[2] = {g.x0 + 5.5 * g.hx, g.y0 + 4.5 * g.hy};
  const double l[2] = {0.25 * g.hx, 0.25 * g.hy};
  const double stretched[4] = {5.0, 0, 0, 1};  // corners at +-1.25 cells: cells 4..6, 4 nodes
  const ParticleStencil<Cpdi, 2> three(g, xc, l, stretched);
  TEST_EQUALITY(three.countX(), 4);
  TEST_EQUALITY(three.first[0], 4);
  TEST_EQUALITY(three.countY(), 2);
  TEST_ASSERT(!three.capped);
  const double tooLong[4] = {7.0, 0, 0, 1};  // +-1.75 cells: cells 3..7, 6 nodes
  const ParticleStencil<Cpdi, 2> capped(g, xc, l, tooLong);
  TEST_ASSERT(capped.capped);
  TEST_EQUALITY(capped.countX(), 4);
  // A shear: r_1 = l_x (1, 1.8) reaches 0.9 cell (hy = hx / 2) up and down, r_2 = (0, l_y) a
  // quarter cell more: corners in rows 3..5, 4 nodes in y, 2 in x.
  const double sheared[4] = {1.0, 0.0, 1.8, 1.0};
  const ParticleStencil<Cpdi, 2> shear(g, xc, l, sheared);
  TEST_EQUALITY(shear.countY(), 4);
  TEST_EQUALITY(shear.countX(), 2);
}

// Grid edge: the corners are clipped to the grid; the weights still sum to 1 and the gradient
// weights to 0, and every node is a grid node.
TEUCHOS_UNIT_TEST(Cpdi, CornersClippedAtTheGridEdge) {
  const StructuredGrid g = grid3d(3);
  std::mt19937 rng(3);
  double worst = 0;
  int used = 0;
  for (int k = 0; k < 500; ++k) {
    double F[9], l[3], xc[3];
    randomDomain<3>(rng, g, F, l);
    for (int d = 0; d < 3; ++d) {  // within a cell of an edge, some on the edge itself
      std::uniform_real_distribution<double> u(0.0, 1.0);
      const double t = k % 7 == 0 ? 0.0 : u(rng);
      xc[d] = (k + d) % 2 ? g.origin(d) + t * g.spacing(d) : g.origin(d) + (g.cells(d) - t) * g.spacing(d);
    }
    const ParticleStencil<Cpdi, 3> st(g, xc, l, F);
    if (st.capped) continue;
    ++used;
    double sum = 0, grad[3] = {};
    st.forEachOffset([&](const int* off, double w, const double* gr) {
      for (int d = 0; d < 3; ++d) {
        const int node = st.first[d] + off[d];
        TEST_ASSERT(node >= 0 && node <= g.cells(d));
        grad[d] += gr[d];
      }
      sum += w;
    });
    worst = std::max(worst, std::abs(sum - 1.0));
    for (int d = 0; d < 3; ++d) worst = std::max(worst, std::abs(grad[d]) * g.spacing(d));
  }
  TEST_COMPARE(worst, <, 1e-12);
  TEST_COMPARE(used, >, 250);
}

// The run loop's check (core/CpdiDomainCheck.hpp): the particles whose domain needs more than 4
// nodes in a direction, or reaches beyond the rank's node columns, with the lowest global id.
TEUCHOS_UNIT_TEST(Cpdi, DomainCheckNamesTheParticle) {
  const StructuredGrid g = grid3d(2);
  impm::ParticleSet ps(4, 2);
  auto x = Kokkos::create_mirror_view(ps.x);
  auto hs = Kokkos::create_mirror_view(ps.halfSize);
  auto F = Kokkos::create_mirror_view(ps.F);
  auto id = Kokkos::create_mirror_view(ps.id);
  Kokkos::deep_copy(F, ps.F);
  const double stretch[4] = {1.0, 7.0, 5.0, 1.0};  // particles 1 (capped, +-1.75 cells) and 2 (4 nodes)
  for (int p = 0; p < 4; ++p) {
    x(p, 0) = g.x0 + (2.5 + 2 * p) * g.hx;
    x(p, 1) = g.y0 + 4.5 * g.hy;
    hs(p, 0) = 0.25 * g.hx;
    hs(p, 1) = 0.25 * g.hy;
    F(p, 0, 0) = stretch[p];
    id(p) = 100 + p;
  }
  Kokkos::deep_copy(ps.x, x);
  Kokkos::deep_copy(ps.halfSize, hs);
  Kokkos::deep_copy(ps.F, F);
  Kokkos::deep_copy(ps.id, id);
  const auto all = impm::LocalNodeIndexer::wholeGrid(g);
  const auto r = impm::checkCpdiDomains<impm::ExecutionSpace, 2>(g, all, ps);
  TEST_EQUALITY(r.tooLarge, 1);
  TEST_EQUALITY(r.outOfReach, 0);
  TEST_EQUALITY(r.firstId, 101LL);
  // A rank that maps node columns 0..6 only: particle 2 (corners in cells 5..7, nodes up to 8)
  // and particle 3 (x in cell 8) are out of its reach.
  const auto slab = impm::LocalNodeIndexer::box(0, 7, 0, g.ny + 1);
  const auto s = impm::checkCpdiDomains<impm::ExecutionSpace, 2>(g, slab, ps);
  TEST_EQUALITY(s.outOfReach, 2);
  TEST_EQUALITY(s.firstId, 101LL);
}

}  // namespace
