// A body that fills its grid: GIMP particle domains that reach past the grid's edge are clipped
// to it, so the weights keep the partition of unity there; with the nodes beyond the edge dropped
// instead, a GIMP cantilever on a grid it fills vibrates 13% to 229% too fast. Checked on the
// stencil itself and on the cantilever, filled against padded.
#include <Teuchos_UnitTestHarness.hpp>
#include <Teuchos_LAPACK.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
#include <vector>

#include "core/InputDeck.hpp"
#include "core/ParticleStencil.hpp"
#include "solvers/Simulation.hpp"
#include "test/RunHistory.hpp"

namespace {

using Teuchos::ParameterList;

// Sum of the weights and of the gradient weights of a GIMP particle of half size l at (x, y),
// for centres from inside the grid to beyond its edges (the domain then partly outside).
TEUCHOS_UNIT_TEST(GridEdge, GimpStencilKeepsPartitionOfUnityPastTheEdge) {
  impm::StructuredGrid g;
  g.nx = 4;
  g.ny = 3;
  g.hx = 0.5;
  g.hy = 0.25;
  g.x0 = -1.0;
  g.y0 = 2.0;
  const double lx = 0.125, ly = 0.0625;
  double worstSum = 0, worstGrad = 0;
  for (int k = -20; k <= 20; ++k) {
    // Centres within 0.9 l of each edge, outside and inside, and near the corner.
    const double s = 0.045 * k * lx / 0.9 / 1.0;
    const double xs[2] = {g.x0 + s, g.xMax() + s};
    const double ys[2] = {g.y0 + s * ly / lx, g.yMax() + s * ly / lx};
    for (double x : xs)
      for (double y : ys) {
        if (x < g.x0 || x > g.xMax() || y < g.y0 || y > g.yMax()) continue;  // centres stay in the grid
        const impm::ParticleStencil<impm::UniformGimp> st(g, x, y, lx, ly);
        double sum = 0, gx = 0, gy = 0;
        for (int a = 0; a < st.countX(); ++a)
          for (int b = 0; b < st.countY(); ++b) {
            sum += st.weight(a, b);
            gx += st.gradX(a, b);
            gy += st.gradY(a, b);
          }
        worstSum = std::max(worstSum, std::abs(sum - 1.0));
        worstGrad = std::max(worstGrad, std::abs(gx) * g.hx + std::abs(gy) * g.hy);
      }
  }
  out << "max |sum w - 1| = " << worstSum << ", max |sum grad w| h = " << worstGrad << "\n";
  TEST_COMPARE(worstSum, <, 1e-14);
  TEST_COMPARE(worstGrad, <, 1e-14);
}

// Plane-stress cantilever, L = 1 m, h = 0.1 m, E = 1e6 Pa, nu = 0.3, rho = 1000 kg/m^3, clamped
// at x = 0 (the x- face), a step force of 0.1 N at the tip's mid-height node: the tip oscillates
// about its static deflection with the first natural period. Grid: 0.025 m cells, either
// exactly the body (40 x 4 cells, as the seed's decks) or with two empty cells around it.
ParameterList cantileverDeck(const std::string& shape, const std::string& integrator, bool padded,
                             const std::string& outdir) {
  ParameterList d("impm");
  d.sublist("Problem").set("Name", "cantilever").set("Output Directory", outdir);
  const int pad = padded ? 2 : 0;
  d.sublist("Grid")
      .set("Cells X", 40 + 2 * pad)
      .set("Cells Y", 4 + 2 * pad)
      .set("Cell Size X", 0.025)
      .set("Cell Size Y", 0.025)
      .set("Origin X", -0.025 * pad)
      .set("Origin Y", -0.025 * pad)
      .set("Plane Condition", "Plane Stress")
      .set("Thickness", 1.0);
  d.sublist("Materials").sublist("soft").set("Young Modulus", 1e6).set("Poisson Ratio", 0.3).set("Density", 1000.0);
  d.sublist("Bodies")
      .sublist("beam")
      .set("Shape", "Rectangle")
      .set("Material", "soft")
      .set("X Min", 0.0)
      .set("X Max", 1.0)
      .set("Y Min", 0.0)
      .set("Y Max", 0.1)
      .set("Particles Per Cell X", 2)
      .set("Particles Per Cell Y", 2);
  d.sublist("Method").set("Shape Function", shape);
  const bool implicitRun = integrator == "Implicit";
  d.sublist("Integrator")
      .set("Type", integrator)
      .set("Time Step", implicitRun ? 0.01 : 2e-4)
      .set("Number of Steps", implicitRun ? 400 : 20000);
  if (implicitRun) d.sublist("Integrator").sublist("Implicit").set("GIMP Stiffness", "Consistent");
  d.sublist("Constraints").sublist("clamp").set("Where", "Face").set("Face", "x-").set("Components", "xy");
  d.sublist("Loads").sublist("tip").set("Type", "Node Force").set("X", 1.0).set("Y", 0.05).set("Force Y", -0.1);
  d.sublist("Monitors").sublist("tip").set("Quantity", "Displacement Y").set("X", 1.0).set("Y", 0.05);
  d.sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0).set("History Interval", 1);
  return d;
}

struct TipResponse {
  double period = 0, peak = 0;
};

// Period from the crossings of the mid level (max + min) / 2 (half a period apart); peak = the
// largest downward deflection (twice the static one for an undamped step response).
TipResponse runCantilever(const std::string& shape, const std::string& integrator, bool padded,
                          Teuchos::FancyOStream& out) {
  std::string tag = shape + "_" + integrator + (padded ? "_padded" : "_filled");
  ParameterList d = cantileverDeck(shape, integrator, padded, "test_output/cantilever_" + tag);
  const impm_test::History h = impm_test::runDeck(d);
  const std::vector<double>& t = h.at("time");
  const std::vector<double>& w = h.at("tip");
  TipResponse r;
  if (w.size() < 3) return r;
  const double lo = *std::min_element(w.begin(), w.end()), hi = *std::max_element(w.begin(), w.end());
  const double mid = 0.5 * (lo + hi);
  std::vector<double> crossings;
  for (size_t k = 1; k < w.size(); ++k)
    if ((w[k - 1] - mid) * (w[k] - mid) < 0)
      crossings.push_back(t[k - 1] + (t[k] - t[k - 1]) * (mid - w[k - 1]) / (w[k] - w[k - 1]));
  if (crossings.size() >= 2) r.period = 2.0 * (crossings.back() - crossings.front()) / (crossings.size() - 1);
  r.peak = -lo;
  out << tag << ": period " << r.period << " s, peak tip deflection " << r.peak << " m (" << crossings.size()
      << " mid-level crossings)\n";
  return r;
}

// An independent reference for the FE Q9 run (which shares impm's grid and assembly with the
// methods it checks): the first period of the same cantilever as a Timoshenko beam (shear
// coefficient of a rectangle in plane stress, Cowper 1966: 10 (1 + nu) / (12 + 11 nu)), from
// 400 two-node elements (linear w and theta, one-point shear integration, consistent mass with
// rotary inertia) and LAPACK's generalized symmetric eigensolver. The discretisation error of
// 400 elements is below 1e-4 of the period.
double timoshenkoCantileverPeriod(double L, double h, double E, double nu, double rho) {
  const int elements = 400, n = 2 * elements;  // w and theta at nodes 1..elements (node 0 clamped)
  const double le = L / elements, A = h, I = h * h * h / 12, G = E / (2 * (1 + nu));
  const double kappa = 10 * (1 + nu) / (12 + 11 * nu);
  std::vector<double> K(n * n, 0.0), M(n * n, 0.0);
  for (int e = 0; e < elements; ++e) {
    const int dof[4] = {2 * e - 2, 2 * e - 1, 2 * e, 2 * e + 1};  // w_a, theta_a, w_b, theta_b (-2, -1: clamped)
    const double shearB[4] = {-1 / le, -0.5, 1 / le, -0.5};       // gamma = w' - theta at the midpoint
    double k[4][4] = {}, m[4][4] = {};
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j) k[i][j] = kappa * G * A * le * shearB[i] * shearB[j];
    k[1][1] += E * I / le;
    k[3][3] += E * I / le;
    k[1][3] -= E * I / le;
    k[3][1] -= E * I / le;
    for (int a = 0; a < 2; ++a)
      for (int b = 0; b < 2; ++b) {
        const double shape = (a == b ? 2.0 : 1.0) * le / 6;
        m[2 * a][2 * b] = rho * A * shape;
        m[2 * a + 1][2 * b + 1] = rho * I * shape;
      }
    for (int i = 0; i < 4; ++i)
      for (int j = 0; j < 4; ++j)
        if (dof[i] >= 0 && dof[j] >= 0) {
          K[dof[i] * n + dof[j]] += k[i][j];
          M[dof[i] * n + dof[j]] += m[i][j];
        }
  }
  std::vector<double> eigenvalues(n), work(1);
  Teuchos::LAPACK<int, double> lapack;
  int info = 0;
  lapack.SYGV(1, 'N', 'U', n, K.data(), n, M.data(), n, eigenvalues.data(), work.data(), -1, &info);
  work.resize(static_cast<size_t>(work[0]));
  lapack.SYGV(1, 'N', 'U', n, K.data(), n, M.data(), n, eigenvalues.data(), work.data(), (int)work.size(), &info);
  return info == 0 ? 2 * M_PI / std::sqrt(eigenvalues[0]) : NAN;
}

// The reference: FE Q9 on the same grid (40 x 4 cells, 20 x 2 elements; it is within 0.78% of
// Timoshenko on the seed's beam), measured T = 1.99 s, peak 7.77e-4 m (Euler-Bernoulli: 1.958 s,
// 8.0e-4 m; shear flexibility at h / L = 0.1 lengthens both). Each method on the grid its body
// fills must be within 1% in period and 2% in peak (measured: MPM and GIMP 0.0-0.2% and 0.8%;
// with the nodes beyond the edge dropped, GIMP is 13% to 229% off in period).
// Padded, GIMP measures 2.0% and 2.6-3.3% longer and larger (its particle domains at the
// top and bottom spread into the empty rows, a softer surface), MPM is unchanged: bounds 3%, 4%.
const TipResponse& feQ9Reference(Teuchos::FancyOStream& out) {
  static const TipResponse reference = runCantilever("FE Q9", "Implicit", false, out);
  return reference;
}

// FE Q9 against the Timoshenko beam: measured 0.95% longer (Euler-Bernoulli 1.958 s, Timoshenko
// 1.973 s, FE Q9 1.992 s). The continuum on 2 elements through the depth differs from the beam
// by its clamped face (no warping), the tip force at one node (local compliance), and the
// period read from four mid-level crossings of a response that holds higher modes; Newmark's
// elongation at dt = 0.01 s is 8e-5. Bound 2%: about twice the measured, and less than half of
// what a 10% error in the modulus or the density does to the period (5%).
const double kFeQ9OffTimoshenko = 0.02;

TEUCHOS_UNIT_TEST(GridEdge, FeQ9CantileverPeriodMatchesTimoshenko) {
  const double timoshenko = timoshenkoCantileverPeriod(1.0, 0.1, 1e6, 0.3, 1000.0);
  const double eulerBernoulli = 2 * M_PI / (1.8751040687 * 1.8751040687) * std::sqrt(1000.0 * 0.1 / (1e6 * 1e-3 / 12));
  const TipResponse& ref = feQ9Reference(out);
  out << std::setprecision(4) << "first period: Euler-Bernoulli " << eulerBernoulli << " s, Timoshenko " << timoshenko
      << " s, FE Q9 " << ref.period << " s (" << ref.period / timoshenko - 1 << " off Timoshenko)\n";
  TEST_COMPARE(timoshenko, >, eulerBernoulli);  // shear and rotary inertia lengthen the period
  TEST_COMPARE(std::abs(ref.period / timoshenko - 1.0), <, kFeQ9OffTimoshenko);
}

void compareWithReference(const std::string& shape, const std::string& integrator, Teuchos::FancyOStream& out,
                          bool& success) {
  const TipResponse& ref = feQ9Reference(out);
  const TipResponse filled = runCantilever(shape, integrator, false, out);
  const TipResponse padded = runCantilever(shape, integrator, true, out);
  TEST_COMPARE(std::abs(filled.period / ref.period - 1.0), <, 0.01);
  TEST_COMPARE(std::abs(filled.peak / ref.peak - 1.0), <, 0.02);
  TEST_COMPARE(std::abs(padded.period / ref.period - 1.0), <, 0.03);
  TEST_COMPARE(std::abs(padded.peak / ref.peak - 1.0), <, 0.04);
}

TEUCHOS_UNIT_TEST(GridEdge, GimpExplicitCantileverFillingTheGrid) {
  compareWithReference("GIMP", "Explicit", out, success);
}
TEUCHOS_UNIT_TEST(GridEdge, GimpImplicitCantileverFillingTheGrid) {
  compareWithReference("GIMP", "Implicit", out, success);
}
TEUCHOS_UNIT_TEST(GridEdge, MpmExplicitCantileverFillingTheGrid) {
  compareWithReference("MPM", "Explicit", out, success);
}

}  // namespace
