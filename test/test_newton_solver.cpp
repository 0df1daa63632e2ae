// NewtonSolver (solvers/newton/NewtonSolver.hpp) on a toy implicit Newmark step of a 1D bar:
//   R(u) = (4/dt^2) M u + K u + c u^3 - f
// with lumped mass M, the stiffness K = E/h tridiag(-1, 2, -1) of fixed-fixed linear elements,
// a cubic spring c u^3 per node (c = 0: linear) and uniform nodal loads f. P = 4/dt^2 M + K + 3 c diag(u^2)
// is the exact Jacobian here. Scales: unit bar, rho = 1, E from 1 to 100, dt = 0.01, load 40 per length,
// so u ~ 1e-3 (displacement-like), ||R(0)|| ~ 1, and with c = kCubic the cubic term's stiffness 3 c u^2 is
// comparable to the inertia term 4/dt^2 m.
// Runs at np = 1 and np = 2.
#include "solvers/newton/NewtonSolver.hpp"

#include <Teuchos_CommandLineProcessor.hpp>
#include <Teuchos_UnitTestHarness.hpp>
#include <Teuchos_UnitTestRepository.hpp>
#include <Tpetra_Core.hpp>
#include <Tpetra_CrsMatrix.hpp>

#include <cmath>
#include <iomanip>
#include <map>
#include <string>
#include <vector>

namespace {

using impm::CrsMatrix;
using impm::GO;
using impm::LO;
using impm::Map;
using impm::NewtonResult;
using impm::NewtonSolver;
using impm::Scalar;
using impm::Vector;
using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

constexpr double kCubic = 1e7;

class NewmarkBar : public impm::ResidualModel {
 public:
  // n free nodes of a unit bar; c: cubic spring coefficient; newMatrixEachCall: jacobianMatrix returns
  // a new matrix object every time (otherwise one static-graph matrix refilled in place); dt: time
  // step; massDecades > 0: nodal masses spread over that many decades (nearly empty MPM cells).
  NewmarkBar(GO n, double c, bool newMatrixEachCall = false, double dt = 0.01, double massDecades = 0)
      : c_(c), newMatrixEachCall_(newMatrixEachCall) {
    map_ = rcp(new Map(n, 0, Tpetra::getDefaultComm()));
    const double h = 1.0 / (n + 1), rho = 1.0, q = 40.0;
    load_ = q * h;
    // Element e joins nodes e-1 and e (nodes -1 and n are the fixed ends). Young's modulus grows
    // from 1 to 100 along the bar and the lumped nodal masses vary by +-50 % (partly filled cells).
    auto E = [&](GO e) { return std::pow(10.0, 2.0 * (e + 0.5) / (n + 1)); };
    auto mass = [&](GO g) {
      const double fill = massDecades > 0 ? std::pow(10.0, -massDecades * std::fmod(0.6180339887 * g, 1.0))
                                          : 1.0 + 0.5 * std::cos(37.0 * g);
      return 4.0 / (dt * dt) * rho * h * fill;
    };
    const LO nLocal = static_cast<LO>(map_->getNodeNumElements());
    cols_.resize(nLocal);
    vals_.resize(nLocal);
    diag_.resize(nLocal);
    A_ = rcp(new CrsMatrix(map_, 3));
    for (LO i = 0; i < nLocal; ++i) {
      const GO g = map_->getGlobalElement(i);
      const double kl = E(g) / h, kr = E(g + 1) / h;
      if (g > 0) cols_[i].push_back(g - 1), vals_[i].push_back(-kl);
      diag_[i] = vals_[i].size();
      cols_[i].push_back(g), vals_[i].push_back(kl + kr + mass(g));
      if (g < n - 1) cols_[i].push_back(g + 1), vals_[i].push_back(-kr);
      A_->insertGlobalValues(g, Teuchos::ArrayView<const GO>(cols_[i]), Teuchos::ArrayView<const Scalar>(vals_[i]));
    }
    A_->fillComplete();
    J_ = rcp(new CrsMatrix(A_->getCrsGraph()));
    J_->fillComplete();
  }

  RCP<const Map> unknownMap() const override {
    // A new Map object over the same indices (a shallow copy), as a model that rebuilds an unchanged map
    // would hand out.
    if (freshMapObject) return rcp(new Map(*map_));
    return map_;
  }

  // Scales the nodal loads: the next "time step" of the same model, a different residual function on
  // the same map.
  void scaleLoad(double factor) { load_ *= factor; }
  bool freshMapObject = false;
  bool nanInMatrix = false;  // P with a NaN: the preconditioned linear solve breaks down

  void residual(const Vector& u, Vector& R) override {
    if (offset != 0.0) {
      // R = A (u + w) - A w: the same function, but each evaluation rounds off about eps |A| |u + w|.
      Vector shifted(u, Teuchos::Copy), Aw(map_);
      Vector w(map_);
      w.putScalar(offset);
      shifted.update(1.0, w, 1.0);
      A_->apply(shifted, R);
      A_->apply(w, Aw);
      R.update(-1.0, Aw, 1.0);
    } else {
      A_->apply(u, R);
    }
    {
      auto uh = u.getLocalViewHost(Tpetra::Access::ReadOnly);
      auto Rh = R.getLocalViewHost(Tpetra::Access::ReadWrite);
      for (size_t i = 0; i < uh.extent(0); ++i) Rh(i, 0) += c_ * uh(i, 0) * uh(i, 0) * uh(i, 0) - load_;
    }
    residualNorms.push_back(R.norm2());
  }

  RCP<const CrsMatrix> jacobianMatrix(const Vector& u) override {
    ++jacobianCalls;
    if (c_ == 0 && !newMatrixEachCall_) return A_;
    RCP<CrsMatrix> J = J_;
    if (newMatrixEachCall_)
      J = rcp(new CrsMatrix(A_->getCrsGraph()));
    else
      J->resumeFill();
    auto uh = u.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (LO i = 0; i < static_cast<LO>(cols_.size()); ++i) {
      std::vector<Scalar> vals = vals_[i];
      vals[diag_[i]] += 3 * c_ * uh(i, 0) * uh(i, 0);
      if (nanInMatrix && i == 0) vals[diag_[i]] = std::nan("");
      J->replaceGlobalValues(map_->getGlobalElement(i), Teuchos::ArrayView<const GO>(cols_[i]),
                             Teuchos::ArrayView<const Scalar>(vals));
    }
    J->fillComplete();
    return J;
  }

  // || |A| (|u + w| + |w|) + |c u^3| + |f| ||: the size of the terms R is summed from (reported when
  // reportsMagnitude; otherwise unknown, as the default ResidualModel says).
  double residualMagnitude(const Vector& u) override {
    if (!reportsMagnitude) return -1.0;
    if (absA_.is_null()) {
      absA_ = rcp(new CrsMatrix(*A_, Teuchos::Copy));
      absA_->resumeFill();
      auto values = absA_->getLocalMatrixHost().values;
      for (size_t k = 0; k < values.extent(0); ++k) values(k) = std::fabs(values(k));
      absA_->fillComplete();
    }
    Vector magnitudes(map_), sum(map_);
    {
      auto uh = u.getLocalViewHost(Tpetra::Access::ReadOnly);
      auto mh = magnitudes.getLocalViewHost(Tpetra::Access::OverwriteAll);
      for (size_t i = 0; i < uh.extent(0); ++i) mh(i, 0) = std::fabs(uh(i, 0) + offset) + std::fabs(offset);
    }
    absA_->apply(magnitudes, sum);
    {
      auto uh = u.getLocalViewHost(Tpetra::Access::ReadOnly);
      auto sh = sum.getLocalViewHost(Tpetra::Access::ReadWrite);
      for (size_t i = 0; i < uh.extent(0); ++i)
        sh(i, 0) += std::fabs(c_ * uh(i, 0) * uh(i, 0) * uh(i, 0)) + std::fabs(load_);
    }
    return sum.norm2();
  }

  std::vector<double> residualNorms;  // ||R|| of every residual() call
  int jacobianCalls = 0;
  double offset = 0.0;            // w: a rigid offset carried through every residual evaluation
  bool reportsMagnitude = false;  // whether residualMagnitude() answers

 private:
  double c_;
  bool newMatrixEachCall_;
  double load_ = 0;
  RCP<const Map> map_;
  RCP<CrsMatrix> A_, J_, absA_;
  std::vector<std::vector<GO>> cols_;  // rows of A (global columns) ...
  std::vector<std::vector<Scalar>> vals_;
  std::vector<size_t> diag_;  // ... and where the diagonal sits in each
};

RCP<ParameterList> params(const std::string& jacobian, const std::string& prec = "RILUK") {
  auto pl = rcp(new ParameterList("Implicit Solver"));
  pl->set("Jacobian", jacobian);
  pl->set("Preconditioner", prec);
  return pl;
}

double relDiff(const Vector& a, const Vector& b) {
  Vector d(a, Teuchos::Copy);
  d.update(-1.0, b, 1.0);
  return d.norm2() / b.norm2();
}

std::string summarize(const NewtonResult& r) {
  std::ostringstream os;
  os << r.reason << "; Krylov per Newton step:";
  for (int k : r.krylovIterations) os << " " << k;
  return os.str();
}

// Expects `f` to throw std::invalid_argument whose message contains every string in `parts`.
template <class F>
bool throwsNaming(F f, const std::vector<std::string>& parts, std::ostream& out) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    out << "  message: " << e.what() << "\n";
    for (const auto& p : parts)
      if (std::string(e.what()).find(p) == std::string::npos) return false;
    return true;
  }
  out << "  no std::invalid_argument thrown\n";
  return false;
}

// Largest problem of SetupIsBuiltOnceAndReused; --newton-max-size=100000 for the full measurement.
int maxSetupSize = 10000;

}  // namespace

TEUCHOS_STATIC_SETUP() {
  Teuchos::UnitTestRepository::getCLP().setOption(
      "newton-max-size", &maxSetupSize, "largest number of unknowns in NewtonSolver.SetupIsBuiltOnceAndReused");
}

TEUCHOS_UNIT_TEST(NewtonSolver, ValidParametersAreDocumentedWithDefaults) {
  auto valid = NewtonSolver::validParameters();
  for (const char* key : {"Jacobian", "Assembled Linear Solver", "Preconditioner", "Displacement Tolerance",
                          "Energy Tolerance", "Residual Tolerance", "Maximum Newton Iterations", "Linear Tolerance",
                          "Maximum Krylov Iterations", "Ifpack2", "NOX", "Stratimikos", "Jacobian-Free Operator"}) {
    TEST_ASSERT(valid->isParameter(key));
    if (valid->isParameter(key)) TEST_ASSERT(!valid->getEntry(key).docString().empty());
  }
  NewtonSolver solver(Teuchos::null);
  const ParameterList& pl = solver.parameters();
  TEST_EQUALITY(pl.get<std::string>("Jacobian"), "Jacobian-Free");
  TEST_EQUALITY(pl.get<std::string>("Preconditioner"), "RILUK");
  TEST_EQUALITY(pl.get<double>("Displacement Tolerance"), 1e-10);
  TEST_EQUALITY(pl.get<double>("Linear Tolerance"), 1e-4);
  TEST_EQUALITY(pl.get<int>("Maximum Krylov Iterations"), 200);
  TEST_EQUALITY(pl.get<int>("Maximum Newton Iterations"), 20);

  // Integers are accepted for real-valued keys (YAML writes 1 for 1.0) and stored as double.
  auto ints = rcp(new ParameterList("Implicit Solver"));
  ints->set("Residual Tolerance", 0);
  NewtonSolver fromInts(ints);
  TEST_EQUALITY(ints->get<double>("Residual Tolerance"), 0.0);
  // The deck's list gets the defaults; pass-through sublists stay as written.
  TEST_ASSERT(ints->isParameter("Energy Tolerance"));
  TEST_EQUALITY(ints->sublist("NOX").numParams(), 0);
}

TEUCHOS_UNIT_TEST(NewtonSolver, BadParametersThrowNamingTheKey) {
  auto bad = [](const std::string& key, auto value) {
    auto pl = rcp(new ParameterList("Implicit Solver"));
    pl->set(key, value);
    return [pl]() { NewtonSolver s(pl); };
  };
  TEST_ASSERT(
      throwsNaming(bad("Preconditioner", std::string("FOO")), {"'Implicit Solver/Preconditioner'", "FOO"}, out));
  TEST_ASSERT(throwsNaming(bad("Jacobian", std::string("Exact")), {"'Implicit Solver/Jacobian'", "Exact"}, out));
  TEST_ASSERT(throwsNaming(bad("Displacement Tolerance", -1e-10),
                           {"'Implicit Solver/Displacement Tolerance' must be positive"}, out));
  TEST_ASSERT(
      throwsNaming(bad("Energy Tolerance", -1.0), {"'Implicit Solver/Energy Tolerance' must be positive"}, out));
  TEST_ASSERT(
      throwsNaming(bad("Linear Tolerance", -1e-4), {"'Implicit Solver/Linear Tolerance' must be positive"}, out));
  TEST_ASSERT(throwsNaming(bad("Residual Tolerance", -1.0), {"'Implicit Solver/Residual Tolerance'"}, out));
  TEST_ASSERT(throwsNaming(bad("Maximum Newton Iterations", 0), {"'Implicit Solver/Maximum Newton Iterations'"}, out));
  TEST_ASSERT(throwsNaming(bad("Displacement Tolerance", std::string("tiny")),
                           {"'Implicit Solver/Displacement Tolerance'"}, out));
  TEST_ASSERT(throwsNaming(bad("Newton Tolerance", 1e-8), {"'Implicit Solver/Newton Tolerance'"}, out));

  // Ifpack2 checks its own list; the error names the pass-through sublist.
  auto relax = params("Jacobian-Free", "RELAXATION");
  relax->sublist("Ifpack2").set("relaxation: type", "Bogus");
  TEST_ASSERT(throwsNaming([relax]() { NewtonSolver s(relax); }, {"'Implicit Solver/Ifpack2'"}, out));
  // Stratimikos likewise.
  auto strat = params("Jacobian-Free");
  strat->sublist("Stratimikos").set("Linear Solver Type", "Amesos2");
  TEST_ASSERT(
      throwsNaming([strat]() { NewtonSolver s(strat); }, {"'Implicit Solver/Stratimikos/Linear Solver Type'"}, out));
  auto belos = params("Jacobian-Free");
  belos->sublist("Stratimikos").sublist("Linear Solver Types").sublist("Belos").set("Solver Type", "No Such Solver");
  TEST_ASSERT(throwsNaming([belos]() { NewtonSolver s(belos); }, {"'Implicit Solver/Stratimikos'"}, out));
}

TEUCHOS_UNIT_TEST(NewtonSolver, LinearAssembledDirectTakesOneNewtonStep) {
  NewmarkBar bar(1000, 0.0);
  NewtonSolver solver(params("Assembled"));
  Vector u(bar.unknownMap());
  const NewtonResult r = solver.solve(bar, u);
  out << summarize(r) << "\n";
  TEST_ASSERT(r.converged);
  TEST_EQUALITY(r.newtonIterations, 1);
  TEST_EQUALITY(r.krylovIterations.size(), 1u);
  // A true direct solve on one rank; on more, one fixed point step with the exact (gathered) inverse.
  const int np = Tpetra::getDefaultComm()->getSize();
  if (!r.krylovIterations.empty()) TEST_EQUALITY(r.krylovIterations[0], np == 1 ? 0 : 1);
  TEST_ASSERT(r.finalResidualNorm < 1e-10);
  TEST_EQUALITY(r.jacobianEvaluations, 1);
}

TEUCHOS_UNIT_TEST(NewtonSolver, LinearJacobianFreeTakesAtMostTwoNewtonSteps) {
  NewmarkBar bar(1000, 0.0);
  auto pl = params("Jacobian-Free");
  pl->set("Linear Tolerance", 1e-8);
  NewtonSolver solver(pl);
  Vector u(bar.unknownMap());
  const NewtonResult r = solver.solve(bar, u);
  out << summarize(r) << "\n";
  TEST_ASSERT(r.converged);
  TEST_ASSERT(r.newtonIterations >= 1 && r.newtonIterations <= 2);

  NewmarkBar ref(1000, 0.0);
  NewtonSolver direct(params("Assembled"));
  Vector uRef(ref.unknownMap());
  direct.solve(ref, uRef);
  TEST_ASSERT(relDiff(u, uRef) < 1e-8);
}

TEUCHOS_UNIT_TEST(NewtonSolver, NonlinearAssembledConvergesQuadratically) {
  NewmarkBar bar(1000, kCubic);
  NewtonSolver solver(params("Assembled"));
  Vector u(bar.unknownMap());
  const NewtonResult r = solver.solve(bar, u);
  out << summarize(r) << "\n  ||R_k||:";
  for (double n : bar.residualNorms) out << " " << std::scientific << std::setprecision(2) << n;
  out << "\n";
  TEST_ASSERT(r.converged);
  TEST_ASSERT(r.newtonIterations >= 3 && r.newtonIterations <= 8);
  // One residual per Newton iterate here (no finite differences): r_{k+1} <= C r_k^2 once in the
  // asymptotic range, above round-off.
  const auto& R = bar.residualNorms;
  TEST_EQUALITY(static_cast<int>(R.size()), r.newtonIterations + 1);
  const double r0 = R.front();
  int quadraticSteps = 0;
  for (size_t k = 0; k + 1 < R.size(); ++k) {
    const double a = R[k] / r0, b = R[k + 1] / r0;
    TEST_ASSERT(b < a);               // monotone
    if (a < 1e-2 && a * a > 1e-12) {  // asymptotic range, and a * a well above round-off
      out << "  step " << k << ": r_k = " << a << ", r_k+1 = " << b << ", r_k+1/r_k^2 = " << b / (a * a) << "\n";
      TEST_ASSERT(b <= 10.0 * a * a);
      ++quadraticSteps;
    }
  }
  TEST_ASSERT(quadraticSteps >= 1);
}

TEUCHOS_UNIT_TEST(NewtonSolver, JacobianFreeMatchesAssembledNewton) {
  NewmarkBar a(1000, kCubic), b(1000, kCubic);
  Vector uA(a.unknownMap()), uJ(b.unknownMap());
  const NewtonResult rA = NewtonSolver(params("Assembled")).solve(a, uA);
  const NewtonResult rJ = NewtonSolver(params("Jacobian-Free")).solve(b, uJ);
  out << "assembled: " << summarize(rA) << "\njacobian-free: " << summarize(rJ) << "\n";
  TEST_ASSERT(rA.converged);
  TEST_ASSERT(rJ.converged);
  const double d = relDiff(uJ, uA);
  out << "relative difference " << d << "\n";
  TEST_ASSERT(d < 1e-8);
  TEST_ASSERT(uA.norm2() > 1e-2);  // a real deflection, not a trivial zero
}

// Krylov iterations of Jacobian-free solves with each preconditioner, on two steps:
//  "large step": dt = 0.01, far above the explicit limit (K dominates P; nonlinear), and
//  "small step": dt = 1e-4 with nodal masses over 3 decades (M dominates P and is badly scaled; linear).
std::map<std::string, int> krylovTotals(const std::string& label, GO n, double c, double dt, double massDecades,
                                        Teuchos::FancyOStream& out, bool& success) {
  const int np = Tpetra::getDefaultComm()->getSize();
  NewmarkBar refBar(n, c, false, dt, massDecades);
  Vector uRef(refBar.unknownMap());
  NewtonSolver(params("Assembled")).solve(refBar, uRef);
  out << label << " (np = " << np << ", n = " << n << ", Linear Tolerance 1e-4, Maximum Krylov Iterations 200):\n";
  std::map<std::string, int> total;
  for (const char* prec : {"None", "RELAXATION", "CHEBYSHEV", "ILUT", "RILUK", "AMESOS2", "SCHWARZ"}) {
    NewmarkBar bar(n, c, false, dt, massDecades);
    Vector u(bar.unknownMap());
    auto pl = params("Jacobian-Free", prec);
    if (std::string(prec) == "SCHWARZ")  // one layer of overlap between ranks, a sparse LU per rank
      pl->sublist("Ifpack2").set("schwarz: overlap level", 1).set("subdomain solver name", "AMESOS2");
    const NewtonResult r = NewtonSolver(pl).solve(bar, u);
    int sum = 0;
    for (int k : r.krylovIterations) sum += k;
    total[prec] = sum;
    out << "  " << std::setw(10) << prec << ": Newton " << r.newtonIterations << ", Krylov total " << std::setw(4)
        << sum << ", residual evaluations " << std::setw(4) << r.residualEvaluations << " | " << summarize(r) << "\n";
    TEST_ASSERT(r.converged);
    TEST_EQUALITY(static_cast<int>(r.krylovIterations.size()), r.newtonIterations);
    TEST_ASSERT(relDiff(u, uRef) < 1e-8);
  }
  return total;
}

TEUCHOS_UNIT_TEST(NewtonSolver, PreconditionersReduceKrylovIterations) {
  // n = 400 keeps this affordable when the test runs oversubscribed (np 2 x OpenMP threads).
  auto large = krylovTotals("large step", 400, kCubic, 0.01, 0, out, success);
  // Stiffness-dominated: the ILU preconditioners do the work; diagonal ones can hardly help.
  TEST_ASSERT(large["RILUK"] < large["None"] / 10);
  TEST_ASSERT(large["ILUT"] < large["None"] / 10);
  // A sparse LU of each rank's block (on one rank the exact inverse of P) does at least as well as
  // its incomplete factorisation; additive Schwarz with that LU as the subdomain solve too.
  TEST_ASSERT(large["AMESOS2"] <= large["RILUK"]);
  TEST_ASSERT(large["SCHWARZ"] < large["None"] / 10);
  auto small = krylovTotals("small step, light nodes", 400, 0.0, 1e-4, 3.0, out, success);
  for (const char* prec : {"RELAXATION", "CHEBYSHEV", "ILUT", "RILUK"}) TEST_ASSERT(small[prec] < small["None"] / 2);
}

TEUCHOS_UNIT_TEST(NewtonSolver, AssembledBelosMatchesDirect) {
  NewmarkBar a(1000, kCubic), b(1000, kCubic);
  Vector uA(a.unknownMap()), uB(b.unknownMap());
  auto pl = params("Assembled", "RILUK");
  pl->set("Assembled Linear Solver", "Belos");
  const NewtonResult rB = NewtonSolver(pl).solve(b, uB);
  const NewtonResult rA = NewtonSolver(params("Assembled")).solve(a, uA);
  out << summarize(rB) << "\n";
  TEST_ASSERT(rB.converged);
  TEST_ASSERT(rB.krylovIterations.size() == static_cast<size_t>(rB.newtonIterations));
  if (!rB.krylovIterations.empty()) TEST_ASSERT(rB.krylovIterations[0] > 0);
  TEST_ASSERT(relDiff(uB, uA) < 1e-8);
  // W_op and W_prec at the same iterate share one assembly.
  TEST_EQUALITY(rB.jacobianEvaluations, rB.newtonIterations);
}

TEUCHOS_UNIT_TEST(NewtonSolver, DisplacementAndEnergyCriteriaAlone) {
  NewmarkBar bar(1000, kCubic);
  auto pl = params("Assembled");
  pl->set("Residual Tolerance", 0.0);  // off: only displacement AND energy can stop it
  Vector u(bar.unknownMap());
  const NewtonResult r = NewtonSolver(pl).solve(bar, u);
  out << summarize(r) << "\n";
  TEST_ASSERT(r.converged);
  TEST_ASSERT(r.reason.find("energy") != std::string::npos);
  TEST_ASSERT(r.displacementNorm >= 0 && r.displacementNorm <= 1e-10);
  TEST_ASSERT(r.energyNorm >= 0 && r.energyNorm <= 1e-20);
}

// The residual's own round-off: the bar carried by a rigid offset w = 1e3 (as a stiff body's nodes
// carry its translation), R = A (u + w) - A w + c u^3 - f. The function is the bar's, but every
// evaluation rounds off ~eps |A| |w|, and Newton stalls there, about 1e-6 against ||R(0)|| ~ 1: the
// absolute residual test (1e-10) and the displacement and energy tests never pass, and the solve
// fails after its 20 iterations. The residual magnitude test accepts the first iterate that is
// below 1e-12 S (S = || |A| (|u + w| + |w|) + |c u^3| + |f| ||, eps S bounds that round-off) and
// no longer falling, and that solution is the offset-free bar's to within what the offset's
// round-off allows.
TEUCHOS_UNIT_TEST(NewtonSolver, ResidualMagnitudeRecognisesTheRoundOffFloor) {
  NewmarkBar exact(1000, kCubic), carried(1000, kCubic);
  carried.offset = 1e3;
  carried.reportsMagnitude = true;
  Vector uExact(exact.unknownMap()), u(carried.unknownMap()), uOld(carried.unknownMap());
  const NewtonResult reference = NewtonSolver(params("Assembled")).solve(exact, uExact);
  TEST_ASSERT(reference.converged);

  auto without = params("Assembled");
  without->set("Residual Magnitude Tolerance", 0.0);
  const NewtonResult old = NewtonSolver(without).solve(carried, uOld);
  out << "without the magnitude test: " << summarize(old) << "\n";
  TEST_ASSERT(!old.converged);
  TEST_ASSERT(old.finalResidualNorm > 1e-9);  // the floor, far above the absolute tolerance

  const NewtonResult r = NewtonSolver(params("Assembled")).solve(carried, u);
  out << "with it: " << summarize(r) << "; ||u - u_exact|| / ||u_exact|| = " << relDiff(u, uExact) << "\n";
  TEST_ASSERT(r.converged);
  TEST_ASSERT(r.reason.find("magnitude") != std::string::npos);
  TEST_ASSERT(r.newtonIterations <= 8);
  TEST_ASSERT(r.residualMagnitudeRatio >= 0 && r.residualMagnitudeRatio <= 1e-12);
  TEST_ASSERT(r.finalResidualNorm <= 2 * old.finalResidualNorm);  // at the floor, not above it
  // The floor's displacement error: ||A^-1|| (~ 1 / 4e4, the mass term) times the floor (~1e-6).
  TEST_ASSERT(relDiff(u, uExact) < 2e-8);
}

TEUCHOS_UNIT_TEST(NewtonSolver, MaximumNewtonIterationsStops) {
  NewmarkBar bar(1000, kCubic);
  auto pl = params("Jacobian-Free", "None");
  pl->set("Maximum Newton Iterations", 2);
  pl->set("Residual Tolerance", 0.0);
  Vector u(bar.unknownMap());
  const NewtonResult r = NewtonSolver(pl).solve(bar, u);
  out << summarize(r) << "\n";
  TEST_ASSERT(!r.converged);
  TEST_EQUALITY(r.newtonIterations, 2);
  TEST_ASSERT(r.reason.find("Maximum Newton Iterations") != std::string::npos);
  TEST_ASSERT(u.norm2() > 0);  // u holds the last iterate
}

TEUCHOS_UNIT_TEST(NewtonSolver, MapMayChangeBetweenSolves) {
  // One solver over several "time steps" whose unknown maps differ; the preconditioner's symbolic
  // setup is redone only when the matrix object changes.
  NewtonSolver solver(params("Jacobian-Free", "RILUK"));
  NewmarkBar a(1000, kCubic), b(700, kCubic), c(1000, kCubic, /*newMatrixEachCall=*/true);
  Vector uA(a.unknownMap()), uB(b.unknownMap()), uC(c.unknownMap());
  const NewtonResult r1 = solver.solve(a, uA);
  const NewtonResult r2 = solver.solve(b, uB);
  uA.putScalar(0.0);
  const NewtonResult r3 = solver.solve(a, uA);  // same static-graph matrix object as r1
  const NewtonResult r4 = solver.solve(c, uC);  // a new matrix object at every Newton step
  for (const auto* r : {&r1, &r2, &r3, &r4})
    out << summarize(*r) << " (jacobians " << r->jacobianEvaluations << ", initialize() "
        << r->preconditionerInitializations << ")\n";
  TEST_ASSERT(r1.converged && r2.converged && r3.converged && r4.converged);
  TEST_EQUALITY(r1.preconditionerInitializations, 1);
  TEST_EQUALITY(r2.preconditionerInitializations, 1);
  TEST_EQUALITY(r3.preconditionerInitializations, 1);  // the cache held b's matrix in between
  TEST_EQUALITY(r4.preconditionerInitializations, r4.jacobianEvaluations);
  TEST_EQUALITY(r1.newtonIterations, r3.newtonIterations);
  auto loose = params("Jacobian-Free", "RILUK");
  loose->set("Residual Tolerance", 1e-6);
  const NewtonResult r5 = NewtonSolver(loose).solve(c, uC);  // converged start: no Newton step at all
  out << summarize(r5) << "\n";
  TEST_ASSERT(r5.converged);
  TEST_EQUALITY(r5.newtonIterations, 0);
  TEST_EQUALITY(r5.krylovIterations.size(), 0u);

  Vector wrongMap(b.unknownMap());
  TEST_THROW(solver.solve(a, wrongMap), std::invalid_argument);
}

TEUCHOS_UNIT_TEST(NewtonSolver, SetupIsBuiltOnceAndReused) {
  // Model evaluator, NOX group, status tests and solver are built at the first solve() and reset at the
  // next ones (same model and map). Asserted: the second solve reuses the set-up. The set-up and solve
  // times are printed as a measurement only (a wall-time bound would test the machine, not impm).
  for (GO n = 1000; n <= maxSetupSize; n *= 10) {
    for (const char* jac : {"Jacobian-Free", "Assembled"}) {
      NewmarkBar bar(n, kCubic);
      Vector u(bar.unknownMap());
      NewtonSolver solver(params(jac));
      const NewtonResult r = solver.solve(bar, u);
      bar.scaleLoad(1.1);
      Vector u2(bar.unknownMap());
      const NewtonResult r2 = solver.solve(bar, u2);
      out << "  n = " << std::setw(6) << n << " " << std::setw(13) << jac << ": setup " << std::scientific
          << std::setprecision(2) << r.setupSeconds << " s (reused: " << r2.setupSeconds << " s) of " << r.solveSeconds
          << " s; Newton " << r.newtonIterations << ", residuals " << r.residualEvaluations << "\n";
      TEST_ASSERT(r.converged && r2.converged);
      TEST_ASSERT(!r.reusedSetUp && r2.reusedSetUp);
    }
  }
}

namespace {

// Every per-solve figure of two results, and their solutions, agree exactly (1e-12 relative for u).
void expectSameSolve(const NewtonResult& a, const Vector& uA, const NewtonResult& b, const Vector& uB,
                     Teuchos::FancyOStream& out, bool& success) {
  TEST_ASSERT(a.converged && b.converged);
  TEST_EQUALITY(a.newtonIterations, b.newtonIterations);
  TEST_ASSERT(a.krylovIterations == b.krylovIterations);
  TEST_EQUALITY(a.residualEvaluations, b.residualEvaluations);
  TEST_EQUALITY(a.jacobianEvaluations, b.jacobianEvaluations);
  TEST_EQUALITY(a.finalResidualNorm, b.finalResidualNorm);
  const double d = relDiff(uA, uB);
  out << "  relative difference of the solutions " << d << "\n";
  TEST_ASSERT(d <= 1e-12);
}

}  // namespace

TEUCHOS_UNIT_TEST(NewtonSolver, SetUpPersistsWhileModelAndMapAreUnchanged) {
  // A sequence of "time steps" of one model (same map, new loads each step) reuses the NOX set-up; each
  // reused solve matches, to round-off, a new solver on a new model in the same state; another map or
  // another model rebuilds.
  for (const char* jac : {"Jacobian-Free", "Assembled"}) {
    out << jac << ":\n";
    NewtonSolver solver(params(jac));
    NewmarkBar a(1000, kCubic);
    Vector uA(a.unknownMap());
    const NewtonResult r1 = solver.solve(a, uA);
    TEST_ASSERT(r1.converged);
    TEST_ASSERT(!r1.reusedSetUp);
    TEST_EQUALITY(solver.setUpBuilds(), 1);

    std::vector<double> factors;
    for (double factor : {1.5, 0.5, 2.0}) {
      a.scaleLoad(factor);
      factors.push_back(factor);
      // Start from the last solution: the first residual then differs from the last one of the previous
      // solve only through the step data, so a stale F, P or preconditioner would show.
      const Vector u0(uA, Teuchos::Copy);
      const NewtonResult r = solver.solve(a, uA);
      out << "  load x" << factor << " (reused " << r.reusedSetUp << "): " << summarize(r) << "; residuals "
          << r.residualEvaluations << ", jacobians " << r.jacobianEvaluations << ", initialize() "
          << r.preconditionerInitializations << "\n";
      TEST_ASSERT(r.reusedSetUp);
      TEST_EQUALITY(solver.setUpBuilds(), 1);
      TEST_ASSERT(r.newtonIterations >= 1);
      // Same static-graph P object: the preconditioner keeps its symbolic set-up.
      if (std::string(jac) == "Jacobian-Free") TEST_EQUALITY(r.preconditionerInitializations, 0);

      NewmarkBar fresh(1000, kCubic);
      for (double f : factors) fresh.scaleLoad(f);
      Vector uF(fresh.unknownMap());
      Tpetra::deep_copy(uF, u0);
      NewtonSolver freshSolver(params(jac));
      const NewtonResult rF = freshSolver.solve(fresh, uF);
      TEST_ASSERT(!rF.reusedSetUp);
      expectSameSolve(r, uA, rF, uF, out, success);
    }

    // Each step starting from zero on a linear bar: the previous solve assembled P at zero too, and that
    // P must not be taken for the new step's (jacobianMatrix is asked again, as by a new solver).
    {
      NewmarkBar lin(1000, 0.0);
      NewtonSolver linSolver(params(jac));
      Vector u(lin.unknownMap());
      const NewtonResult first = linSolver.solve(lin, u);
      lin.scaleLoad(3.0);
      u.putScalar(0.0);
      const NewtonResult second = linSolver.solve(lin, u);
      NewmarkBar fresh(1000, 0.0);
      fresh.scaleLoad(3.0);
      Vector uF(fresh.unknownMap());
      const NewtonResult rF = NewtonSolver(params(jac)).solve(fresh, uF);
      out << "  linear, from zero: jacobians " << first.jacobianEvaluations << ", then " << second.jacobianEvaluations
          << " (reused " << second.reusedSetUp << "); new solver " << rF.jacobianEvaluations << "\n";
      TEST_ASSERT(second.reusedSetUp);
      TEST_ASSERT(second.jacobianEvaluations >= 1);
      expectSameSolve(second, u, rF, uF, out, success);
    }

    // Another map rebuilds; so does going back to the first model (another model than the last).
    NewmarkBar b(700, kCubic);
    Vector uB(b.unknownMap());
    const NewtonResult rB = solver.solve(b, uB);
    TEST_ASSERT(rB.converged && !rB.reusedSetUp);
    TEST_EQUALITY(solver.setUpBuilds(), 2);
    uA.putScalar(0.0);
    const NewtonResult rA = solver.solve(a, uA);
    TEST_ASSERT(rA.converged && !rA.reusedSetUp);
    TEST_EQUALITY(solver.setUpBuilds(), 3);

    // The same model handing out a new Map object with the same indices (Map::isSameAs) reuses.
    a.freshMapObject = true;
    a.scaleLoad(0.25);
    factors.push_back(0.25);
    Vector uA2(a.unknownMap());
    const NewtonResult rSame = solver.solve(a, uA2);
    TEST_ASSERT(rSame.reusedSetUp);
    TEST_EQUALITY(solver.setUpBuilds(), 3);
    NewmarkBar fresh(1000, kCubic);
    for (double f : factors) fresh.scaleLoad(f);
    Vector uF(fresh.unknownMap());
    const NewtonResult rF = NewtonSolver(params(jac)).solve(fresh, uF);
    expectSameSolve(rSame, uA2, rF, uF, out, success);
  }
}

TEUCHOS_UNIT_TEST(NewtonSolver, FailedCallRebuildsNext) {
  // A NOX list that buildSolver rejects throws at the first call and leaves nothing half-built behind:
  // every call builds again (and throws again), rather than reusing a group without a solver.
  auto pl = params("Jacobian-Free");
  pl->sublist("NOX").set("Nonlinear Solver", "No Such Solver");
  NewtonSolver solver(pl);
  NewmarkBar a(200, kCubic);
  Vector u(a.unknownMap());
  TEST_THROW(solver.solve(a, u), std::invalid_argument);
  TEST_THROW(solver.solve(a, u), std::invalid_argument);
  TEST_EQUALITY(solver.setUpBuilds(), 2);
}

TEUCHOS_UNIT_TEST(NewtonSolver, LinearSolveBreakdownIsAFailedSolveNotAnException) {
  // A linear solve that breaks down (here Belos on the NaN an ILU of a NaN P returns) fails this
  // Newton solve with its reason, as a Newton iteration limit would: the implicit step is then
  // retried smaller, or the run stops with its record (Status, Failure, last good state), instead
  // of an exception that leaves none. The next solve builds its NOX set-up afresh and converges.
  NewmarkBar bar(200, kCubic);
  bar.nanInMatrix = true;
  NewtonSolver solver(params("Jacobian-Free", "RILUK"));
  Vector u(bar.unknownMap());
  NewtonResult r;
  TEST_NOTHROW(r = solver.solve(bar, u));
  out << summarize(r) << "\n";
  TEST_ASSERT(!r.converged);
  TEST_ASSERT(r.reason.find("the linear solve broke down") != std::string::npos);
  bar.nanInMatrix = false;
  Vector v(bar.unknownMap());
  const NewtonResult again = solver.solve(bar, v);
  TEST_ASSERT(again.converged);
  TEST_EQUALITY(solver.setUpBuilds(), 2);
}

// GMRES's inner products on a rank that owns no unknowns (a rank whose part of the grid holds no
// mass): Belos computes them through Thyra as C = A^T B with Tpetra::MultiVector::multiply, each
// rank's product of its rows summed over the ranks. Trilinos 13.2's KokkosBlas::gemm left C
// unset on a rank with no rows instead of zeroing it (cmake/trilinos-patches), so whatever the
// memory held entered every rank's sum: NaN or wrong Hessenberg entries now and then. C starts
// as NaN here, so that such a library fails every time, at np 2 (rank 1 owns nothing).
TEUCHOS_UNIT_TEST(NewtonSolver, InnerProductsOnARankWithoutUnknowns) {
  const auto comm = Tpetra::getDefaultComm();
  const GO n = 50;
  const size_t vectors = 3;
  auto rows = rcp(new Map(n, comm->getRank() == 0 ? size_t(n) : 0, 0, comm));
  impm::MultiVector A(rows, vectors), B(rows, vectors);
  A.randomize();
  B.randomize();
  auto small = rcp(new Map(vectors, 0, comm, Tpetra::LocallyReplicated));
  impm::MultiVector C(small, vectors);
  C.putScalar(std::nan(""));
  C.multiply(Teuchos::TRANS, Teuchos::NO_TRANS, 1.0, A, B, 0.0);
  auto c = C.getLocalViewHost(Tpetra::Access::ReadOnly);
  for (size_t i = 0; i < vectors; ++i)
    for (size_t j = 0; j < vectors; ++j) {
      const Scalar dot = A.getVector(i)->dot(*B.getVector(j));
      out << "C(" << i << "," << j << ") = " << c(i, j) << ", dot " << dot << "\n";
      TEST_FLOATING_EQUALITY(c(i, j), dot, 1e-12);
    }
}
