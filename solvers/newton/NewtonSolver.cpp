#include "solvers/newton/NewtonSolver.hpp"

#include "solvers/newton/ConvergenceTests.hpp"
#include "solvers/newton/GatheredDirectInverse.hpp"
#include "solvers/newton/IfpackPreconditioner.hpp"
#include "solvers/newton/ImplicitModelEvaluator.hpp"
#include "solvers/newton/MueLuPreconditioner.hpp"
#include "solvers/newton/NewtonObserver.hpp"

#include <NOX.H>
#include <NOX_MatrixFree_ModelEvaluatorDecorator.hpp>
#include <NOX_Thyra.H>
#include <NOX_Thyra_MatrixFreeJacobianOperator.hpp>
#include <Stratimikos_DefaultLinearSolverBuilder.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Thyra_SolveSupportTypes.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>

#include <algorithm>
#include <chrono>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace impm {

using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

namespace {
double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}
}  // namespace

// The deck's list validated (NewtonParameters), then the linear solver, the gathered direct
// inverse for several ranks, and the preconditioner: Ifpack2 checks the type and the "Ifpack2" list
// now, MueLu its keys against its master list and the values on a small matrix (not collective).
NewtonSolver::NewtonSolver(const RCP<ParameterList>& params)
    : params_(params.is_null() ? rcp(new ParameterList("Implicit Solver")) : params),
      settings_(NewtonSettings::fromList(*params_)) {
  ParameterList& pl = *params_;
  try {
    Stratimikos::DefaultLinearSolverBuilder builder;
    builder.setParameterList(Teuchos::rcp(new ParameterList(*settings_.stratimikos)));
    lowsFactory_ = builder.createLinearSolveStrategy("");
  } catch (const std::exception& e) {
    throw std::invalid_argument("invalid " + implicitSolverKey("Stratimikos") + ": " + e.what());
  }
  if (settings_.direct()) {
    // Used when the unknowns span several ranks (see gatheredDirect_ in the header). Belos's fixed
    // point iteration x += P^-1 (b - P x) around the exact inverse: the direct solve, then at most
    // two steps of iterative refinement (more only stagnate at round-off once the relative residual
    // tolerance, 1e-10, is below what a badly conditioned P allows; Newton takes the step anyway).
    // Not GMRES: a Krylov method's inner products go through Thyra -> Tpetra::MultiVector::multiply
    // -> KokkosBlas::gemm, which in Trilinos 13.2 returns early on a rank owning no unknowns without
    // zeroing its part of the product (kokkos-kernels #1088); the sum over ranks then adds what the
    // memory held. impm's own Trilinos build is patched (cmake/trilinos-patches), a Trilinos of the
    // user's own may not be; the fixed point iteration takes norms only, right with either.
    auto belos = rcp(new ParameterList("Stratimikos"));
    belos->set("Linear Solver Type", "Belos");
    belos->set("Preconditioner Type", "None");
    ParameterList& b = belos->sublist("Linear Solver Types").sublist("Belos");
    b.set("Solver Type", "Fixed Point");
    b.sublist("Solver Types").sublist("Fixed Point").set("Maximum Iterations", 3);
    b.sublist("VerboseObject").set("Verbosity Level", "none");
    Stratimikos::DefaultLinearSolverBuilder builder;
    builder.setParameterList(belos);
    gatheredLowsFactory_ = builder.createLinearSolveStrategy("");
    gatheredDirect_ = rcp(new GatheredDirectInverse());
  }

  // Ifpack2: checks the type and the "Ifpack2" list now (not collective).
  // MueLu: checks the keys against its master list and the values on a small matrix (not collective).
  if (settings_.usesPreconditioner()) {
    if (settings_.preconditioner == "MUELU")
      prec_ = makeMueLuPreconditioner(pl.sublist("MueLu"));
    else
      prec_ = rcp(new IfpackPreconditionerCache(settings_.preconditioner, pl.sublist("Ifpack2")));
  }
}

// What solve() keeps between calls while the model and its unknown map are unchanged.
struct NewtonSolver::NoxSetUp {
  const ResidualModel* model = nullptr;  // compared by address only
  RCP<const Map> map;                    // the map everything below was built on
  bool gathered = false;
  RCP<ImplicitModelEvaluator> me;
  RCP<NOX::Thyra::MatrixFreeJacobianOperator<double>> jfnkOp;  // null for assembled Newton
  RCP<NOX::Thyra::Group> group;
  RCP<NOX::StatusTest::FiniteValue> finite;
  RCP<NOX::StatusTest::NormF> normF;
  RCP<DisplacementNormTest> displacement;
  RCP<EnergyNormTest> energy;
  RCP<ResidualMagnitudeTest> magnitude;  // null when Residual Magnitude Tolerance = 0
  RCP<NOX::StatusTest::MaxIters> maxIters;
  RCP<NewtonObserver> observer;
  RCP<NOX::Solver::Generic> solver;
};

NewtonSolver::~NewtonSolver() = default;

bool NewtonSolver::canReuse(const ResidualModel& model, const Map& map, bool gathered) const {
  // Decided locally (pointer comparison, else the local part of Map::isSameAs), then agreed on by
  // one reduction: Map::isSameAs itself short-cuts on pointer equality without communicating, so
  // calling it where the pointers differ on some ranks only would leave the others waiting.
  int local = 0;
  if (nox_ && nox_->model == &model && nox_->gathered == gathered) {
    const Map& old = *nox_->map;
    local = &old == &map || (old.getComm()->getSize() == map.getComm()->getSize() &&
                             old.getGlobalNumElements() == map.getGlobalNumElements() &&
                             old.getIndexBase() == map.getIndexBase() && old.locallySameAs(map));
  }
  int global = 0;
  Teuchos::reduceAll(*map.getComm(), Teuchos::REDUCE_MIN, local, Teuchos::outArg(global));
  return global == 1;
}

// Solves from the initial guess u: builds or resets the NOX set-up, runs NOX, reports.
NewtonResult NewtonSolver::solve(ResidualModel& model, Vector& u) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  NewtonResult result;

  const RCP<const Map> map = model.unknownMap();
  TEUCHOS_TEST_FOR_EXCEPTION(map.is_null(), std::invalid_argument, "impm::NewtonSolver::solve: null unknownMap()");
  TEUCHOS_TEST_FOR_EXCEPTION(!u.getMap()->isSameAs(*map), std::invalid_argument,
                             "impm::NewtonSolver::solve: u is not on the model's unknownMap()");
  // A direct solve over several ranks goes through the gathered KLU2 inverse (see the header).
  const bool gathered = !gatheredDirect_.is_null() && map->getComm()->getSize() > 1;
  const RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> lows = gathered ? gatheredLowsFactory_ : lowsFactory_;
  const RCP<PreconditionerCache> prec = gathered ? gatheredDirect_ : prec_;
  const int initsBefore = prec.is_null() ? 0 : prec->initializations();

  // Whatever goes wrong below (a bad NOX list, a throwing model), the next call starts afresh.
  struct DropUnlessDone {
    std::unique_ptr<NoxSetUp>& setUp;
    bool done = false;
    ~DropUnlessDone() {
      if (!done) setUp.reset();
    }
  } guard{nox_};

  const auto beforeReduction = clock::now();
  result.reusedSetUp = canReuse(model, *map, gathered);
  const auto afterReduction = clock::now();
  if (result.reusedSetUp)
    resetSetUp(u);
  else
    buildSetUp(model, map, u, gathered, lows, prec);
  NoxSetUp& s = *nox_;
  const auto beforeF = clock::now();
  s.group->computeF();  // the matrix-free operator needs F at the base point
  const auto afterF = clock::now();
  // The operator points at the group's own x and F vectors; setting it again after a reset is cheap.
  if (!s.jfnkOp.is_null()) s.jfnkOp->setBaseEvaluationToNOXGroup(s.group.create_weak());
  if (!result.reusedSetUp) buildStatusTestsAndSolver(model);
  // Not counted: the residual at the initial guess, and the reduction deciding on reuse (the first
  // collective of the call, where a rank waits for the others to finish their previous work).
  result.setupSeconds =
      seconds(start, beforeReduction) + seconds(afterReduction, beforeF) + seconds(afterF, clock::now());

  NOX::StatusTest::StatusType status;
  try {
    status = s.solver->solve();
  } catch (const char* e) {
    throw std::runtime_error(std::string("impm::NewtonSolver: NOX failed: ") + e);
  } catch (const Thyra::CatastrophicSolveFailure& e) {
    // A linear solve that broke down (Belos on a NaN residual, a singular direct solve): this
    // Newton solve failed, so the step is retried smaller or the run stops with its record; the
    // NOX set-up is rebuilt at the next call (the guard drops it).
    const std::string what = e.what();
    const size_t reason = what.rfind("\n", what.find_last_not_of("\n "));
    result.converged = false;
    result.newtonIterations = s.solver->getNumIterations();
    result.reason = "failed after " + std::to_string(result.newtonIterations) +
                    " Newton iterations: the linear solve broke down (" +
                    what.substr(reason == std::string::npos ? 0 : reason + 1,
                                what.find_last_not_of("\n ") + 1 - (reason == std::string::npos ? 0 : reason + 1)) +
                    ")";
    result.residualEvaluations = s.me->residualEvaluations();
    result.jacobianEvaluations = s.me->jacobianEvaluations();
    result.solveSeconds = seconds(start, clock::now());
    return result;
  }

  // Copy the last iterate back, and report.
  const NOX::Abstract::Group& soln = s.solver->getSolutionGroup();
  const auto& xs = dynamic_cast<const NOX::Thyra::Vector&>(soln.getX());
  Tpetra::deep_copy(
      u, *Thyra::TpetraOperatorVectorExtraction<Scalar, LO, GO, Node>::getConstTpetraVector(xs.getThyraRCPVector()));
  result.converged = status == NOX::StatusTest::Converged;
  result.newtonIterations = s.solver->getNumIterations();
  result.krylovIterations = s.observer->iterations;
  result.residualNorms = s.observer->residualNorms;
  result.finalResidualNorm = soln.isF() ? soln.getNormF() : -1.0;
  result.displacementNorm = s.displacement->ratio();
  result.energyNorm = s.energy->ratio();
  result.residualMagnitudeRatio = s.magnitude.is_null() ? -1.0 : s.magnitude->ratio();
  result.residualEvaluations = s.me->residualEvaluations();
  result.jacobianEvaluations = s.me->jacobianEvaluations();
  result.preconditionerInitializations = prec.is_null() ? 0 : prec->initializations() - initsBefore;
  result.reason = describeOutcome(result, status);
  guard.done = true;
  result.solveSeconds = seconds(start, clock::now());
  return result;
}

void NewtonSolver::buildSetUp(ResidualModel& model, const RCP<const Map>& map, const Vector& u, bool gathered,
                              const RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& lows,
                              const RCP<PreconditionerCache>& prec) {
  nox_.reset();
  auto s = std::make_unique<NoxSetUp>();
  s->model = &model;
  s->map = map;
  s->gathered = gathered;
  s->me = rcp(new ImplicitModelEvaluator(model, map, lows, !settings_.jacobianFree(), prec));
  RCP<Thyra::VectorBase<double>> x0 =
      Thyra::createVector<Scalar, LO, GO, Node>(rcp(new Vector(u, Teuchos::Copy)), s->me->get_x_space());
  const NOX::Thyra::Vector noxX0(x0);
  if (settings_.jacobianFree()) {
    ParameterList print;
    print.set("Output Information", static_cast<int>(NOX::Utils::Error));
    s->jfnkOp = rcp(new NOX::Thyra::MatrixFreeJacobianOperator<double>(print));
    s->jfnkOp->setParameterList(
        rcp(new ParameterList(*settings_.jacobianFreeOperator)));  // before setBaseEvaluationToNOXGroup
    RCP<Thyra::ModelEvaluator<double>> decorated = rcp(new NOX::MatrixFreeModelEvaluatorDecorator<double>(s->me));
    RCP<Thyra::PreconditionerBase<double>> precOp = prec.is_null() ? Teuchos::null : decorated->create_W_prec();
    s->group = rcp(new NOX::Thyra::Group(noxX0, decorated, s->jfnkOp, lows, precOp, Teuchos::null, Teuchos::null));
  } else {
    RCP<Thyra::PreconditionerBase<double>> precOp = prec.is_null() ? Teuchos::null : s->me->create_W_prec();
    s->group =
        rcp(new NOX::Thyra::Group(noxX0, s->me, s->me->create_W_op(), lows, precOp, Teuchos::null, Teuchos::null));
  }
  nox_ = std::move(s);
  ++setUpBuilds_;
}

// Same model and map: a new initial guess for the kept group and solver. reset() sets x in the
// group, which invalidates every value it holds (F, Jacobian, linear solver with its
// preconditioner, Newton direction), and zeroes the solver's iteration count and statistics;
// beginSolve() makes the model evaluator forget P, so the next time step's residual function is
// evaluated afresh throughout. The status tests re-initialise at iteration 0.
void NewtonSolver::resetSetUp(const Vector& u) {
  NoxSetUp& s = *nox_;
  s.me->beginSolve();
  s.observer->iterations.clear();
  s.observer->residualNorms.clear();
  RCP<Thyra::VectorBase<double>> x0 = Thyra::createMember(s.me->get_x_space());
  Tpetra::deep_copy(*Thyra::TpetraOperatorVectorExtraction<Scalar, LO, GO, Node>::getTpetraVector(x0), u);
  s.solver->reset(NOX::Thyra::Vector(x0));
}

void NewtonSolver::buildStatusTestsAndSolver(ResidualModel& model) {
  NoxSetUp& s = *nox_;
  s.finite = rcp(new NOX::StatusTest::FiniteValue);
  s.normF = rcp(new NOX::StatusTest::NormF(settings_.residualTol, NOX::StatusTest::NormF::Unscaled));
  s.displacement = rcp(new DisplacementNormTest(settings_.displacementTol));
  s.energy = rcp(new EnergyNormTest(settings_.energyTol));
  auto both = rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::AND));
  both->addStatusTest(s.displacement);
  both->addStatusTest(s.energy);
  s.maxIters = rcp(new NOX::StatusTest::MaxIters(settings_.maxNewton));
  auto tests = rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR));
  tests->addStatusTest(s.finite);
  tests->addStatusTest(s.normF);
  tests->addStatusTest(both);
  if (settings_.magnitudeTol > 0) {
    s.magnitude = rcp(new ResidualMagnitudeTest(model, settings_.magnitudeTol));
    tests->addStatusTest(s.magnitude);
  }
  tests->addStatusTest(s.maxIters);

  auto noxParams = rcp(new ParameterList(*settings_.nox));
  s.observer = rcp(new NewtonObserver);
  noxParams->sublist("Solver Options").set<RCP<NOX::Observer>>("Observer", s.observer);
  try {
    s.solver = NOX::Solver::buildSolver(s.group, tests, noxParams);
  } catch (const std::exception& e) {
    throw std::invalid_argument("invalid " + implicitSolverKey("NOX") + ": " + e.what());
  } catch (const char* e) {  // NOX throws "NOX Error" strings
    throw std::invalid_argument("invalid " + implicitSolverKey("NOX") + ": " + e);
  }
}

std::string NewtonSolver::describeOutcome(const NewtonResult& result, int status) const {
  const NoxSetUp& s = *nox_;
  const auto sci = [](double v) { return scientific(v); };
  std::ostringstream why;
  const std::string its = " after " + std::to_string(result.newtonIterations) + " Newton iteration" +
                          (result.newtonIterations == 1 ? "" : "s");
  const std::string values =
      "||R|| = " + sci(result.finalResidualNorm) + ", ||du||/||u|| = " + sci(result.displacementNorm) +
      ", energy ratio = " + sci(result.energyNorm) +
      (s.magnitude.is_null() ? std::string() : ", ||R||/S = " + sci(result.residualMagnitudeRatio));
  if (result.converged) {
    if (s.normF->getStatus() == NOX::StatusTest::Converged)
      why << "converged" << its << ": ||R|| = " << sci(result.finalResidualNorm) << " < Residual Tolerance "
          << sci(settings_.residualTol);
    else if (!s.magnitude.is_null() && s.magnitude->getStatus() == NOX::StatusTest::Converged)
      why << "converged" << its << ": ||R|| = " << sci(result.finalResidualNorm)
          << " <= " << sci(settings_.magnitudeTol) << " x its magnitude " << sci(s.magnitude->magnitude())
          << " and no longer falling (round-off floor)";
    else
      why << "converged" << its << ": ||du||/||u|| = " << sci(result.displacementNorm)
          << " <= " << sci(settings_.displacementTol) << " and energy ratio = " << sci(result.energyNorm)
          << " <= " << sci(settings_.energyTol);
  } else if (s.finite->getStatus() == NOX::StatusTest::Failed) {
    why << "failed" << its << ": the residual is not finite (NaN or Inf)";
  } else if (s.maxIters->getStatus() == NOX::StatusTest::Failed) {
    why << "not converged" << its << " (Maximum Newton Iterations = " << settings_.maxNewton << "): " << values;
  } else {
    why << "NOX stopped" << its << " (status " << static_cast<NOX::StatusTest::StatusType>(status)
        << "; a Newton direction or line search failed): " << values;
  }
  return why.str();
}

}  // namespace impm
