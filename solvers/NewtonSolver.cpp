#include "solvers/NewtonSolver.hpp"

#include "solvers/ConvergenceTests.hpp"
#include "solvers/ImplicitModelEvaluator.hpp"
#include "solvers/MueLuPreconditioner.hpp"

#include <NOX.H>
#include <NOX_MatrixFree_ModelEvaluatorDecorator.hpp>
#include <NOX_Observer.hpp>
#include <NOX_SolverStats.hpp>
#include <NOX_Thyra.H>
#include <NOX_Thyra_MatrixFreeJacobianOperator.hpp>
#include <Stratimikos_DefaultLinearSolverBuilder.hpp>
#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iomanip>
#include <memory>
#include <sstream>
#include <stdexcept>

namespace impm {

using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

namespace {

const std::string kList = "Implicit Solver";
// Relative tolerance of preconditioned GMRES when it stands in for a direct solve.
constexpr double kAssembledBelosTolerance = 1e-10;

std::string where(const std::string& key) { return "'" + kList + "/" + key + "'"; }

std::string valueString(const Teuchos::ParameterEntry& e) {
  std::ostringstream os;
  e.leftshift(os, false);
  return os.str();
}

std::string sci(double v) {
  std::ostringstream os;
  os << std::scientific << std::setprecision(3) << v;
  return os.str();
}

// Accept ints and doubles (YAML decks write "1" for 1.0), stored as double.
RCP<Teuchos::AnyNumberParameterEntryValidator> numberValidator() {
  Teuchos::AnyNumberParameterEntryValidator::AcceptedTypes accept(false);
  accept.allowInt(true).allowDouble(true).allowString(false);
  return rcp(new Teuchos::AnyNumberParameterEntryValidator(Teuchos::AnyNumberParameterEntryValidator::PREFER_DOUBLE,
                                                           accept));
}

bool stratimikosHasAmesos2() {
  Stratimikos::DefaultLinearSolverBuilder builder;
  RCP<const ParameterList> valid = builder.getValidParameters();
  return valid->isSublist("Linear Solver Types") && valid->sublist("Linear Solver Types").isSublist("Amesos2");
}

template <class T>
void setDefault(ParameterList& pl, const std::string& key, const T& value) {
  if (!pl.isParameter(key)) pl.set(key, value);
}

void setDefault(ParameterList& pl, const std::string& key, const char* value) {
  setDefault(pl, key, std::string(value));
}

// Per-key check of the user's list with messages naming 'Implicit Solver/<key>'; then Teuchos fills
// the defaults and converts numbers. Pass-through sublists are left to their packages.
void validateList(ParameterList& pl, const ParameterList& valid) {
  for (auto it = pl.begin(); it != pl.end(); ++it) {
    const std::string& key = pl.name(it);
    const Teuchos::ParameterEntry& entry = pl.entry(it);
    const Teuchos::ParameterEntry* ve = valid.getEntryPtr(key);
    if (ve == nullptr) {
      std::string keys;
      for (auto v = valid.begin(); v != valid.end(); ++v) keys += (keys.empty() ? "'" : ", '") + valid.name(v) + "'";
      throw std::invalid_argument("unknown key " + where(key) + " (valid here: " + keys + ")");
    }
    if (ve->isList() != entry.isList())
      throw std::invalid_argument(where(key) + (ve->isList() ? " must be a sublist, not a value" : " must be a value, not a sublist"));
    if (ve->isList()) continue;
    const RCP<const Teuchos::ParameterEntryValidator> validator = ve->validator();
    if (validator.is_null()) continue;
    try {
      validator->validate(entry, key, kList);
    } catch (const std::exception&) {
      std::string msg = "invalid value '" + valueString(entry) + "' for " + where(key);
      RCP<const Teuchos::Array<std::string>> strings = validator->validStringValues();
      if (!strings.is_null()) {
        msg += " (valid: ";
        for (Teuchos::Array<std::string>::size_type k = 0; k < strings->size(); ++k) msg += (k ? ", " : "") + (*strings)[k];
        msg += ")";
      } else {
        msg += " (expected a " + std::string(ve->getAny().typeName()) + ")";
      }
      throw std::invalid_argument(msg);
    }
  }
  try {
    pl.validateParametersAndSetDefaults(valid, 0);
  } catch (const std::exception& e) {
    throw std::invalid_argument("invalid '" + kList + "' list: " + std::string(e.what()));
  }
}

double positive(const ParameterList& pl, const std::string& key) {
  const double v = pl.get<double>(key);
  if (!(v > 0) || !std::isfinite(v)) throw std::invalid_argument(where(key) + " must be positive (got " + sci(v) + ")");
  return v;
}

int positiveInt(const ParameterList& pl, const std::string& key) {
  const int v = pl.get<int>(key);
  if (v < 1) throw std::invalid_argument(where(key) + " must be positive (got " + std::to_string(v) + ")");
  return v;
}

// Krylov iterations of each Newton step, from NOX's solver statistics.
// Also the residual norm ||R||_2 at the initial guess and after each Newton iteration (the
// convergence rate in tests).
class KrylovObserver : public NOX::Observer {
 public:
  std::vector<int> iterations;
  std::vector<double> residualNorms;
  void runPreSolve(const NOX::Solver::Generic& solver) override {
    const NOX::Abstract::Group& g = solver.getSolutionGroup();
    if (g.isF()) residualNorms.push_back(g.getNormF());
  }
  void runPostIterate(const NOX::Solver::Generic& solver) override {
    // Also called after a converged initial guess or a failed direction, with no new linear solve.
    if (solver.getNumIterations() > static_cast<int>(iterations.size())) {
      iterations.push_back(solver.getSolverStatistics()->linearSolve.lastLinearSolve_NumIterations);
      const NOX::Abstract::Group& g = solver.getSolutionGroup();
      if (g.isF()) residualNorms.push_back(g.getNormF());
    }
  }
};

double seconds(std::chrono::steady_clock::time_point a, std::chrono::steady_clock::time_point b) {
  return std::chrono::duration<double>(b - a).count();
}

}  // namespace

// ---------------------------------------------------------------------------------------------

RCP<const ParameterList> NewtonSolver::validParameters() {
  static RCP<const ParameterList> valid;
  if (!valid.is_null()) return valid;
  auto pl = rcp(new ParameterList(kList));
  const bool amesos2 = stratimikosHasAmesos2();

  Teuchos::setStringToIntegralParameter<int>(
      "Jacobian", "Jacobian-Free",
      "Jacobian-Free: Newton-Krylov with J v ~ (R(u + d v) - R(u)) / d (NOX matrix-free operator), "
      "Belos GMRES right-preconditioned by Ifpack2 on the assembled P. Assembled: the Jacobian is P itself",
      Teuchos::tuple<std::string>("Jacobian-Free", "Assembled"), Teuchos::tuple<int>(0, 1), pl.get());
  if (amesos2) {
    Teuchos::setStringToIntegralParameter<int>(
        "Assembled Linear Solver", "Amesos2",
        "Jacobian = Assembled only. Amesos2: direct sparse LU (KLU2; Stratimikos/Linear Solver Types/Amesos2). "
        "Belos: GMRES preconditioned by 'Preconditioner', to a relative tolerance of min(Linear Tolerance, 1e-10)",
        Teuchos::tuple<std::string>("Amesos2", "Belos"), Teuchos::tuple<int>(0, 1), pl.get());
  } else {
    Teuchos::setStringToIntegralParameter<int>(
        "Assembled Linear Solver", "Belos",
        "Jacobian = Assembled only. Belos: GMRES preconditioned by 'Preconditioner', to a relative tolerance "
        "of min(Linear Tolerance, 1e-10) (this Trilinos has no Amesos2 in Stratimikos)",
        Teuchos::tuple<std::string>("Belos"), Teuchos::tuple<int>(1), pl.get());
  }
  pl->set("Preconditioner", "RILUK",
          "Ifpack2 preconditioner built from the assembled P (initialize() once per matrix graph, compute() "
          "each Newton step): RILUK (incomplete LU, level of fill 'fact: iluk level-of-fill'), ILUT, "
          "RELAXATION (Jacobi unless 'relaxation: type' says otherwise), CHEBYSHEV, AMESOS2 (sparse direct LU of "
          "each rank's diagonal block, KLU2 unless 'Amesos2 solver name' says otherwise: on one rank the exact "
          "inverse of P), SCHWARZ (additive Schwarz, 'schwarz: overlap level' layers of overlap between ranks, "
          "'subdomain solver name' RILUK unless set, e.g. AMESOS2), MUELU (smoothed-aggregation algebraic multigrid "
          "with Ifpack2 smoothers and the rigid-body modes as near-null space; options in the 'MueLu' sublist; "
          "needs a Trilinos with MueLu), or None. Across MPI ranks the ILU variants and AMESOS2 act as block Jacobi",
          rcp(new Teuchos::StringValidator(Teuchos::tuple<std::string>("RILUK", "ILUT", "RELAXATION", "CHEBYSHEV",
                                                                       "AMESOS2", "SCHWARZ", "MUELU", "None"))));
  pl->set("Line Search", "Full Step",
          "how far along each Newton direction to go (NOX's line searches): Full Step (always 1); Backtrack (the full "
          "step when it lowers ||R||, else halve it until ||R|| decreases, at most 'Line Search Iterations' times, "
          "else take the full step: for large rotations, where full steps overshoot); "
          "Polynomial (quadratic then cubic interpolation until the Armijo condition holds; one more J v product "
          "per Newton iteration for the slope); More-Thuente (cubic interpolation until the strong Wolfe "
          "conditions hold). The convergence tests judge the full Newton direction, not the damped step",
          rcp(new Teuchos::StringValidator(Teuchos::tuple<std::string>("Full Step", "Backtrack", "Polynomial", "More-Thuente"))));
  pl->set("Line Search Iterations", 8,
          "the most trial steps of one line search (Backtrack, Polynomial, More-Thuente); when none is accepted the "
          "full step is taken",
          rcp(new Teuchos::EnhancedNumberValidator<int>()));
  pl->set("Displacement Tolerance", 1e-10,
          "converged when ||du_k|| <= tol * ||u_k|| (du_k: update of Newton iteration k; 2-norms) AND the "
          "energy criterion holds",
          numberValidator());
  pl->set("Energy Tolerance", 1e-20,
          "converged when |du_k . R(u_{k-1})| <= tol * |du_1 . R(u_0)| (relative work of the residual) AND the "
          "displacement criterion holds. The energy scales like the square of the residual, so 1e-20 matches a "
          "residual reduction of about 1e-10",
          numberValidator());
  pl->set("Residual Tolerance", 1e-10,
          "also converged when the unscaled 2-norm of R(u) is below this absolute value (force units); "
          "0 disables this test",
          numberValidator());
  pl->set("Residual Magnitude Tolerance", 1e-12,
          "also converged when ||R(u_k)|| <= tol * S(u_k) and the last Newton iteration did not halve ||R||: S = "
          "|| |P| |u| + |M (4/dt v + a)| + |F_ext| || (dof by dof absolute values; P the assembled matrix) is the "
          "size of the terms R is summed from, its round-off is bounded by about eps S (eps = 2.2e-16), and Newton "
          "stalls at that floor (a stiff body's translation makes S large; Jacobian-free differences add their own "
          "noise). A residual that is both below 1e-12 of the problem's own force scale and no longer falling is "
          "converged as far as the arithmetic can tell; 0 disables this test",
          numberValidator());
  pl->set("Maximum Newton Iterations", 20, "the step fails when not converged after this many Newton iterations",
          rcp(new Teuchos::EnhancedNumberValidator<int>()));
  pl->set("Linear Tolerance", 1e-4,
          "relative residual tolerance of each GMRES solve (Jacobian-Free; constant forcing term)", numberValidator());
  pl->set("Maximum Krylov Iterations", 200,
          "GMRES iteration limit per Newton step (also the restart length, capped at 100)",
          rcp(new Teuchos::EnhancedNumberValidator<int>()));
  pl->sublist("Ifpack2", false, "passed unchanged to the Ifpack2 preconditioner's setParameters (Ifpack2 checks it)")
      .disableRecursiveValidation();
  pl->sublist("MueLu", false,
              "Preconditioner = MUELU: passed to MueLu::CreateTpetraPreconditioner (MueLu checks it); impm's "
              "defaults where it is silent: smoothed aggregation (uncoupled), smoother RELAXATION (Symmetric "
              "Gauss-Seidel, 2 sweeps), coarse KLU2 below 500 rows, verbosity none. impm sets 'number of "
              "equations' (the dimension) and the near-null space (rigid-body modes) itself")
      .disableRecursiveValidation();
  pl->sublist("NOX", false,
              "passed to NOX (defaults: Line Search Based, the 'Line Search' above, Newton with a constant forcing term, errors "
              "printed only, Complete status test checks); these keys win over the derived ones")
      .disableRecursiveValidation();
  pl->sublist("Stratimikos", false,
              "passed to Stratimikos::DefaultLinearSolverBuilder (defaults: Belos Pseudo Block GMRES, or Amesos2 "
              "KLU2 for an assembled direct solve; Preconditioner Type None, since the Ifpack2 preconditioner "
              "arrives through the model evaluator's W_prec)")
      .disableRecursiveValidation();
  pl->sublist("Jacobian-Free Operator", false,
              "passed to NOX::Thyra::MatrixFreeJacobianOperator (defaults: Difference Type Forward, Perturbation "
              "Algorithm 'Knoll Keyes JCP 2004', lambda 1e-6). Central differences are broken in Trilinos 13.2")
      .disableRecursiveValidation();
  valid = pl;
  return valid;
}

NewtonSolver::NewtonSolver(const RCP<ParameterList>& params)
    : params_(params.is_null() ? rcp(new ParameterList(kList)) : params) {
  ParameterList& pl = *params_;
  validateList(pl, *validParameters());

  jacobian_ = Teuchos::getIntegralValue<int>(pl, "Jacobian") == 0 ? JacobianMode::JacobianFree : JacobianMode::Assembled;
  assembledSolver_ =
      Teuchos::getIntegralValue<int>(pl, "Assembled Linear Solver") == 0 ? AssembledSolver::Amesos2 : AssembledSolver::Belos;
  precType_ = pl.get<std::string>("Preconditioner");
  displacementTol_ = positive(pl, "Displacement Tolerance");
  energyTol_ = positive(pl, "Energy Tolerance");
  residualTol_ = pl.get<double>("Residual Tolerance");
  if (!(residualTol_ >= 0) || !std::isfinite(residualTol_))
    throw std::invalid_argument(where("Residual Tolerance") + " must be non-negative (got " + sci(residualTol_) + ")");
  magnitudeTol_ = pl.get<double>("Residual Magnitude Tolerance");
  if (!(magnitudeTol_ >= 0) || !(magnitudeTol_ < 1))
    throw std::invalid_argument(where("Residual Magnitude Tolerance") + " must be in [0, 1) (got " + sci(magnitudeTol_) + ")");
  linearTol_ = positive(pl, "Linear Tolerance");
  if (linearTol_ >= 1) throw std::invalid_argument(where("Linear Tolerance") + " must be below 1 (got " + sci(linearTol_) + ")");
  maxNewton_ = positiveInt(pl, "Maximum Newton Iterations");
  maxKrylov_ = positiveInt(pl, "Maximum Krylov Iterations");
  const bool direct = jacobian_ == JacobianMode::Assembled && assembledSolver_ == AssembledSolver::Amesos2;

  // Matrix-free operator settings (copied; NOX fills its defaults into the copy at each set-up build).
  jfnkParams_ = rcp(new ParameterList(pl.sublist("Jacobian-Free Operator")));
  setDefault(*jfnkParams_, "Difference Type", "Forward");
  setDefault(*jfnkParams_, "Perturbation Algorithm", "Knoll Keyes JCP 2004");
  setDefault(*jfnkParams_, "lambda", 1e-6);
  if (jacobian_ == JacobianMode::JacobianFree) {
    try {
      ParameterList print;
      NOX::Thyra::MatrixFreeJacobianOperator<double> probe(print);
      probe.setParameterList(rcp(new ParameterList(*jfnkParams_)));
    } catch (const std::exception& e) {
      throw std::invalid_argument("invalid " + where("Jacobian-Free Operator") + ": " + e.what());
    }
    if (jfnkParams_->get<std::string>("Difference Type") != "Forward")
      throw std::invalid_argument(where("Jacobian-Free Operator/Difference Type") +
                                  " must be Forward (Central differences are broken in Trilinos 13.2)");
  }

  // Stratimikos: the linear solver. Our derived settings are defaults; the deck's keys win.
  auto strat = rcp(new ParameterList(pl.sublist("Stratimikos")));
  const std::string lsType = direct ? "Amesos2" : "Belos";
  if (strat->isParameter("Linear Solver Type") && strat->get<std::string>("Linear Solver Type") != lsType) {
    throw std::invalid_argument(
        where("Stratimikos/Linear Solver Type") + " = " + strat->get<std::string>("Linear Solver Type") +
        (jacobian_ == JacobianMode::JacobianFree ? " cannot solve with a Jacobian-free operator: use Belos"
                                                 : " contradicts " + where("Assembled Linear Solver") + " = " + lsType));
  }
  strat->set("Linear Solver Type", lsType);
  setDefault(*strat, "Preconditioner Type", "None");
  if (direct) {
    ParameterList& amesos2 = strat->sublist("Linear Solver Types").sublist("Amesos2");
    setDefault(amesos2, "Solver Type", "KLU2");
    setDefault(amesos2.sublist("VerboseObject"), "Verbosity Level", "none");
  } else {
    ParameterList& belos = strat->sublist("Linear Solver Types").sublist("Belos");
    setDefault(belos, "Solver Type", "Pseudo Block GMRES");
    const std::string solverType = belos.get<std::string>("Solver Type");
    ParameterList& solver = belos.sublist("Solver Types").sublist(solverType);
    setDefault(solver, "Maximum Iterations", maxKrylov_);
    if (solverType.find("GMRES") != std::string::npos) setDefault(solver, "Num Blocks", std::min(maxKrylov_, 100));
    setDefault(belos.sublist("VerboseObject"), "Verbosity Level", "none");
  }
  try {
    Stratimikos::DefaultLinearSolverBuilder builder;
    builder.setParameterList(strat);
    lowsFactory_ = builder.createLinearSolveStrategy("");
  } catch (const std::exception& e) {
    throw std::invalid_argument("invalid " + where("Stratimikos") + ": " + e.what());
  }
  if (direct) {
    // Used when the unknowns span several ranks (see gatheredDirect_ in the header).
    auto belos = rcp(new ParameterList("Stratimikos"));
    belos->set("Linear Solver Type", "Belos");
    belos->set("Preconditioner Type", "None");
    ParameterList& b = belos->sublist("Linear Solver Types").sublist("Belos");
    b.set("Solver Type", "Pseudo Block GMRES");
    b.sublist("Solver Types").sublist("Pseudo Block GMRES").set("Maximum Iterations", 20);
    b.sublist("Solver Types").sublist("Pseudo Block GMRES").set("Num Blocks", 20);
    b.sublist("VerboseObject").set("Verbosity Level", "none");
    Stratimikos::DefaultLinearSolverBuilder builder;
    builder.setParameterList(belos);
    gatheredLowsFactory_ = builder.createLinearSolveStrategy("");
    gatheredDirect_ = rcp(new GatheredDirectInverse());
  }

  // NOX: Newton with full steps; our derived settings are defaults, the deck's keys win.
  noxParams_ = rcp(new ParameterList(pl.sublist("NOX")));
  ParameterList& nox = *noxParams_;
  setDefault(nox, "Nonlinear Solver", "Line Search Based");
  {
    // The deck's 'Line Search' in NOX's spelling; NOX/Line Search/Method, when given, must agree.
    std::string method = pl.get<std::string>("Line Search");
    if (method == "More-Thuente") method = "More'-Thuente";
    ParameterList& ls = nox.sublist("Line Search");
    if (ls.isParameter("Method") && ls.get<std::string>("Method") != method && !pl.getEntry("Line Search").isDefault())
      throw std::invalid_argument(where("NOX/Line Search/Method") + " = " + ls.get<std::string>("Method") +
                                  " contradicts " + where("Line Search") + " = " + pl.get<std::string>("Line Search"));
    setDefault(ls, "Method", method);
    const int iterations = positiveInt(pl, "Line Search Iterations");
    const std::string chosen = ls.get<std::string>("Method");
    if (chosen != "Full Step") {
      ParameterList& options = ls.sublist(chosen);
      setDefault(options, "Max Iters", iterations);
      // A line search that finds no acceptable step takes the full Newton step and goes on.
      setDefault(options, "Recovery Step", 1.0);
      if (chosen == "Polynomial") setDefault(options, "Recovery Step Type", "Constant");
      // The slope from a difference of residuals: the Jacobian-free group has no Jacobian to
      // apply, and an assembled one would be reassembled at every trial point.
      if (chosen == "More'-Thuente") setDefault(options, "Optimize Slope Calculation", true);
    }
  }
  setDefault(nox.sublist("Direction"), "Method", "Newton");
  ParameterList& newton = nox.sublist("Direction").sublist("Newton");
  setDefault(newton, "Forcing Term Method", "Constant");
  const double linTol = jacobian_ == JacobianMode::JacobianFree ? linearTol_ : std::min(linearTol_, kAssembledBelosTolerance);
  setDefault(newton.sublist("Linear Solver"), "Tolerance", linTol);
  setDefault(nox.sublist("Printing"), "Output Information", static_cast<int>(NOX::Utils::Error));
  setDefault(nox.sublist("Solver Options"), "Status Test Check Type", "Complete");

  // Ifpack2: checks the type and the "Ifpack2" list now (not collective).
  // MueLu: checks the keys against its master list and the values on a small matrix (not collective).
  if (usesPreconditioner()) {
    if (precType_ == "MUELU")
      prec_ = makeMueLuPreconditioner(pl.sublist("MueLu"));
    else
      prec_ = rcp(new IfpackPreconditionerCache(precType_, pl.sublist("Ifpack2")));
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
  RCP<KrylovObserver> observer;
  RCP<NOX::Solver::Generic> solver;
};

NewtonSolver::~NewtonSolver() = default;

bool NewtonSolver::usesPreconditioner() const {
  if (precType_ == "None") return false;
  return jacobian_ == JacobianMode::JacobianFree || assembledSolver_ == AssembledSolver::Belos;
}

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
  if (!result.reusedSetUp) {
    // Model evaluator and NOX group for this model and map.
    nox_.reset();
    auto s = std::make_unique<NoxSetUp>();
    s->model = &model;
    s->map = map;
    s->gathered = gathered;
    s->me = rcp(new ImplicitModelEvaluator(model, map, lows, jacobian_ == JacobianMode::Assembled, prec));
    RCP<Thyra::VectorBase<double>> x0 =
        Thyra::createVector<Scalar, LO, GO, Node>(rcp(new Vector(u, Teuchos::Copy)), s->me->get_x_space());
    const NOX::Thyra::Vector noxX0(x0);
    if (jacobian_ == JacobianMode::JacobianFree) {
      ParameterList print;
      print.set("Output Information", static_cast<int>(NOX::Utils::Error));
      s->jfnkOp = rcp(new NOX::Thyra::MatrixFreeJacobianOperator<double>(print));
      s->jfnkOp->setParameterList(rcp(new ParameterList(*jfnkParams_)));  // before setBaseEvaluationToNOXGroup
      RCP<Thyra::ModelEvaluator<double>> decorated = rcp(new NOX::MatrixFreeModelEvaluatorDecorator<double>(s->me));
      RCP<Thyra::PreconditionerBase<double>> precOp = prec.is_null() ? Teuchos::null : decorated->create_W_prec();
      s->group = rcp(new NOX::Thyra::Group(noxX0, decorated, s->jfnkOp, lows, precOp, Teuchos::null, Teuchos::null));
    } else {
      RCP<Thyra::PreconditionerBase<double>> precOp = prec.is_null() ? Teuchos::null : s->me->create_W_prec();
      s->group = rcp(new NOX::Thyra::Group(noxX0, s->me, s->me->create_W_op(), lows, precOp, Teuchos::null, Teuchos::null));
    }
    nox_ = std::move(s);
    ++setUpBuilds_;
  } else {
    // Same model and map: a new initial guess for the kept group and solver. reset() sets x in the
    // group, which invalidates every value it holds (F, Jacobian, linear solver with its
    // preconditioner, Newton direction), and zeroes the solver's iteration count and statistics;
    // beginSolve() makes the model evaluator forget P, so the next time step's residual function is
    // evaluated afresh throughout. The status tests re-initialise at iteration 0.
    NoxSetUp& s = *nox_;
    s.me->beginSolve();
    s.observer->iterations.clear();
    s.observer->residualNorms.clear();
    RCP<Thyra::VectorBase<double>> x0 = Thyra::createMember(s.me->get_x_space());
    Tpetra::deep_copy(*Thyra::TpetraOperatorVectorExtraction<Scalar, LO, GO, Node>::getTpetraVector(x0), u);
    s.solver->reset(NOX::Thyra::Vector(x0));
  }
  NoxSetUp& s = *nox_;
  const RCP<ImplicitModelEvaluator>& me = s.me;
  const auto beforeF = clock::now();
  s.group->computeF();  // the matrix-free operator needs F at the base point
  const auto afterF = clock::now();
  // The operator points at the group's own x and F vectors; setting it again after a reset is cheap.
  if (!s.jfnkOp.is_null()) s.jfnkOp->setBaseEvaluationToNOXGroup(s.group.create_weak());

  if (!result.reusedSetUp) {
    // Status tests: finite residual, then (NormF OR (displacement AND energy)), then MaxIters.
    s.finite = rcp(new NOX::StatusTest::FiniteValue);
    s.normF = rcp(new NOX::StatusTest::NormF(residualTol_, NOX::StatusTest::NormF::Unscaled));
    s.displacement = rcp(new DisplacementNormTest(displacementTol_));
    s.energy = rcp(new EnergyNormTest(energyTol_));
    auto both = rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::AND));
    both->addStatusTest(s.displacement);
    both->addStatusTest(s.energy);
    s.maxIters = rcp(new NOX::StatusTest::MaxIters(maxNewton_));
    auto tests = rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR));
    tests->addStatusTest(s.finite);
    tests->addStatusTest(s.normF);
    tests->addStatusTest(both);
    if (magnitudeTol_ > 0) {
      s.magnitude = rcp(new ResidualMagnitudeTest(model, magnitudeTol_));
      tests->addStatusTest(s.magnitude);
    }
    tests->addStatusTest(s.maxIters);

    auto noxParams = rcp(new ParameterList(*noxParams_));
    s.observer = rcp(new KrylovObserver);
    noxParams->sublist("Solver Options").set<RCP<NOX::Observer>>("Observer", s.observer);
    try {
      s.solver = NOX::Solver::buildSolver(s.group, tests, noxParams);
    } catch (const std::exception& e) {
      throw std::invalid_argument("invalid " + where("NOX") + ": " + e.what());
    } catch (const char* e) {  // NOX throws "NOX Error" strings
      throw std::invalid_argument("invalid " + where("NOX") + ": " + e);
    }
  }
  const RCP<NOX::Solver::Generic>& solver = s.solver;
  // Not counted: the residual at the initial guess, and the reduction deciding on reuse (the first
  // collective of the call, where a rank waits for the others to finish their previous work).
  result.setupSeconds =
      seconds(start, beforeReduction) + seconds(afterReduction, beforeF) + seconds(afterF, clock::now());

  NOX::StatusTest::StatusType status;
  try {
    status = solver->solve();
  } catch (const char* e) {
    throw std::runtime_error(std::string("impm::NewtonSolver: NOX failed: ") + e);
  }

  // Copy the last iterate back, and report.
  const NOX::Abstract::Group& soln = solver->getSolutionGroup();
  const auto& xs = dynamic_cast<const NOX::Thyra::Vector&>(soln.getX());
  Tpetra::deep_copy(u, *Thyra::TpetraOperatorVectorExtraction<Scalar, LO, GO, Node>::getConstTpetraVector(
                           xs.getThyraRCPVector()));

  result.converged = status == NOX::StatusTest::Converged;
  result.newtonIterations = solver->getNumIterations();
  result.krylovIterations = s.observer->iterations;
  result.residualNorms = s.observer->residualNorms;
  result.finalResidualNorm = soln.isF() ? soln.getNormF() : -1.0;
  result.displacementNorm = s.displacement->ratio();
  result.energyNorm = s.energy->ratio();
  result.residualMagnitudeRatio = s.magnitude.is_null() ? -1.0 : s.magnitude->ratio();
  result.residualEvaluations = me->residualEvaluations();
  result.jacobianEvaluations = me->jacobianEvaluations();
  result.preconditionerInitializations = prec.is_null() ? 0 : prec->initializations() - initsBefore;

  std::ostringstream why;
  const std::string its = " after " + std::to_string(result.newtonIterations) + " Newton iteration" +
                          (result.newtonIterations == 1 ? "" : "s");
  const std::string values = "||R|| = " + sci(result.finalResidualNorm) + ", ||du||/||u|| = " +
                             sci(result.displacementNorm) + ", energy ratio = " + sci(result.energyNorm) +
                             (s.magnitude.is_null() ? std::string() : ", ||R||/S = " + sci(result.residualMagnitudeRatio));
  if (result.converged) {
    if (s.normF->getStatus() == NOX::StatusTest::Converged)
      why << "converged" << its << ": ||R|| = " << sci(result.finalResidualNorm) << " < Residual Tolerance "
          << sci(residualTol_);
    else if (!s.magnitude.is_null() && s.magnitude->getStatus() == NOX::StatusTest::Converged)
      why << "converged" << its << ": ||R|| = " << sci(result.finalResidualNorm) << " <= " << sci(magnitudeTol_)
          << " x its magnitude " << sci(s.magnitude->magnitude()) << " and no longer falling (round-off floor)";
    else
      why << "converged" << its << ": ||du||/||u|| = " << sci(result.displacementNorm) << " <= "
          << sci(displacementTol_) << " and energy ratio = " << sci(result.energyNorm) << " <= " << sci(energyTol_);
  } else if (s.finite->getStatus() == NOX::StatusTest::Failed) {
    why << "failed" << its << ": the residual is not finite (NaN or Inf)";
  } else if (s.maxIters->getStatus() == NOX::StatusTest::Failed) {
    why << "not converged" << its << " (Maximum Newton Iterations = " << maxNewton_ << "): " << values;
  } else {
    why << "NOX stopped" << its << " (status " << status << "; a Newton direction or line search failed): " << values;
  }
  result.reason = why.str();
  guard.done = true;
  result.solveSeconds = seconds(start, clock::now());
  return result;
}

}  // namespace impm
