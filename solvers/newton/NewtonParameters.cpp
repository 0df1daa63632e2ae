#include "solvers/newton/NewtonParameters.hpp"

#include <NOX.H>
#include <NOX_Thyra.H>
#include <NOX_Thyra_MatrixFreeJacobianOperator.hpp>
#include <Stratimikos_DefaultLinearSolverBuilder.hpp>
#include <Teuchos_StandardParameterEntryValidators.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <stdexcept>

#include "core/DeckSchema.hpp"

namespace impm {

using Teuchos::ParameterList;
using Teuchos::RCP;
using Teuchos::rcp;

std::string implicitSolverKey(const std::string& key) { return "'Implicit Solver/" + key + "'"; }

std::string scientific(double v) {
  std::ostringstream os;
  os << std::scientific << std::setprecision(3) << v;
  return os.str();
}

namespace {

const std::string kList = "Implicit Solver";
// Relative tolerance of preconditioned GMRES when it stands in for a direct solve.
constexpr double kAssembledBelosTolerance = 1e-10;

std::string where(const std::string& key) { return implicitSolverKey(key); }

std::string valueString(const Teuchos::ParameterEntry& e) {
  std::ostringstream os;
  e.leftshift(os, false);
  return os.str();
}

std::string sci(double v) { return scientific(v); }

// Accept ints and doubles (YAML decks write "1" for 1.0), stored as double.
using schema::numberValidator;

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
      throw std::invalid_argument(
          where(key) + (ve->isList() ? " must be a sublist, not a value" : " must be a value, not a sublist"));
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
        for (Teuchos::Array<std::string>::size_type k = 0; k < strings->size(); ++k)
          msg += (k ? ", " : "") + (*strings)[k];
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

}  // namespace

RCP<const ParameterList> newtonValidParameters() {
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
          "each Newton step): RILUK (incomplete LU, level of fill 'fact: iluk level-of-fill'; 'fact: type' "
          "KSPILUK factorises with Kokkos Kernels, faster for small steps unless OMP_WAIT_POLICY is passive), ILUT, "
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
          "else take the full step: for large rotations, where full steps overshoot; the default with "
          "'Contact/Type' = Multi Field); "
          "Polynomial (quadratic then cubic interpolation until the Armijo condition holds; one more J v product "
          "per Newton iteration for the slope); More-Thuente (cubic interpolation until the strong Wolfe "
          "conditions hold). The convergence tests judge the full Newton direction, not the damped step",
          rcp(new Teuchos::StringValidator(
              Teuchos::tuple<std::string>("Full Step", "Backtrack", "Polynomial", "More-Thuente"))));
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
              "Gauss-Seidel, 3 sweeps) in a W-cycle, coarse KLU2 below 500 rows, verbosity none. impm sets 'number of "
              "equations' (the dimension) and the near-null space (rigid-body modes) itself")
      .disableRecursiveValidation();
  pl->sublist("NOX", false,
              "passed to NOX (defaults: Line Search Based, the 'Line Search' above, Newton with a constant forcing "
              "term, errors "
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

namespace {

// The mode, the preconditioner and the tolerances, each checked.
void readTolerances(const ParameterList& pl, NewtonSettings& s) {
  s.jacobian = Teuchos::getIntegralValue<int>(pl, "Jacobian") == 0 ? NewtonSettings::JacobianMode::JacobianFree
                                                                   : NewtonSettings::JacobianMode::Assembled;
  s.assembledSolver = Teuchos::getIntegralValue<int>(pl, "Assembled Linear Solver") == 0
                          ? NewtonSettings::AssembledSolver::Amesos2
                          : NewtonSettings::AssembledSolver::Belos;
  s.preconditioner = pl.get<std::string>("Preconditioner");
  s.displacementTol = positive(pl, "Displacement Tolerance");
  s.energyTol = positive(pl, "Energy Tolerance");
  s.residualTol = pl.get<double>("Residual Tolerance");
  if (!(s.residualTol >= 0) || !std::isfinite(s.residualTol))
    throw std::invalid_argument(where("Residual Tolerance") + " must be non-negative (got " + sci(s.residualTol) + ")");
  s.magnitudeTol = pl.get<double>("Residual Magnitude Tolerance");
  if (!(s.magnitudeTol >= 0) || !(s.magnitudeTol < 1))
    throw std::invalid_argument(where("Residual Magnitude Tolerance") + " must be in [0, 1) (got " +
                                sci(s.magnitudeTol) + ")");
  s.linearTol = positive(pl, "Linear Tolerance");
  if (s.linearTol >= 1)
    throw std::invalid_argument(where("Linear Tolerance") + " must be below 1 (got " + sci(s.linearTol) + ")");
  s.maxNewton = positiveInt(pl, "Maximum Newton Iterations");
  s.maxKrylov = positiveInt(pl, "Maximum Krylov Iterations");
}

// Matrix-free operator settings (copied; NOX fills its defaults into the copy at each set-up build).
void deriveJacobianFreeOperator(const ParameterList& pl, NewtonSettings& s) {
  s.jacobianFreeOperator = rcp(new ParameterList(pl.sublist("Jacobian-Free Operator")));
  setDefault(*s.jacobianFreeOperator, "Difference Type", "Forward");
  setDefault(*s.jacobianFreeOperator, "Perturbation Algorithm", "Knoll Keyes JCP 2004");
  setDefault(*s.jacobianFreeOperator, "lambda", 1e-6);
  if (s.jacobian == NewtonSettings::JacobianMode::JacobianFree) {
    try {
      ParameterList print;
      NOX::Thyra::MatrixFreeJacobianOperator<double> probe(print);
      probe.setParameterList(rcp(new ParameterList(*s.jacobianFreeOperator)));
    } catch (const std::exception& e) {
      throw std::invalid_argument("invalid " + where("Jacobian-Free Operator") + ": " + e.what());
    }
    if (s.jacobianFreeOperator->get<std::string>("Difference Type") != "Forward")
      throw std::invalid_argument(where("Jacobian-Free Operator/Difference Type") +
                                  " must be Forward (Central differences are broken in Trilinos 13.2)");
  }
}

// Stratimikos: the linear solver. Our derived settings are defaults; the deck's keys win.
void deriveStratimikos(const ParameterList& pl, NewtonSettings& s) {
  const bool direct = s.direct();
  s.stratimikos = rcp(new ParameterList(pl.sublist("Stratimikos")));
  const std::string lsType = direct ? "Amesos2" : "Belos";
  if (s.stratimikos->isParameter("Linear Solver Type") &&
      s.stratimikos->get<std::string>("Linear Solver Type") != lsType) {
    throw std::invalid_argument(where("Stratimikos/Linear Solver Type") + " = " +
                                s.stratimikos->get<std::string>("Linear Solver Type") +
                                (s.jacobian == NewtonSettings::JacobianMode::JacobianFree
                                     ? " cannot solve with a Jacobian-free operator: use Belos"
                                     : " contradicts " + where("Assembled Linear Solver") + " = " + lsType));
  }
  s.stratimikos->set("Linear Solver Type", lsType);
  setDefault(*s.stratimikos, "Preconditioner Type", "None");
  if (direct) {
    ParameterList& amesos2 = s.stratimikos->sublist("Linear Solver Types").sublist("Amesos2");
    setDefault(amesos2, "Solver Type", "KLU2");
    setDefault(amesos2.sublist("VerboseObject"), "Verbosity Level", "none");
  } else {
    ParameterList& belos = s.stratimikos->sublist("Linear Solver Types").sublist("Belos");
    setDefault(belos, "Solver Type", "Pseudo Block GMRES");
    const std::string solverType = belos.get<std::string>("Solver Type");
    ParameterList& solver = belos.sublist("Solver Types").sublist(solverType);
    setDefault(solver, "Maximum Iterations", s.maxKrylov);
    if (solverType.find("GMRES") != std::string::npos) setDefault(solver, "Num Blocks", std::min(s.maxKrylov, 100));
    setDefault(belos.sublist("VerboseObject"), "Verbosity Level", "none");
  }
}

// NOX: Newton with full steps (or the deck's line search); our derived settings are defaults, the
// deck's keys win.
void deriveNox(const ParameterList& pl, NewtonSettings& s) {
  s.nox = rcp(new ParameterList(pl.sublist("NOX")));
  ParameterList& nox = *s.nox;
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
  const double linTol = s.jacobian == NewtonSettings::JacobianMode::JacobianFree
                            ? s.linearTol
                            : std::min(s.linearTol, kAssembledBelosTolerance);
  setDefault(newton.sublist("Linear Solver"), "Tolerance", linTol);
  setDefault(nox.sublist("Printing"), "Output Information", static_cast<int>(NOX::Utils::Error));
  setDefault(nox.sublist("Solver Options"), "Status Test Check Type", "Complete");
}

}  // namespace

NewtonSettings NewtonSettings::fromList(ParameterList& pl) {
  validateList(pl, *newtonValidParameters());
  NewtonSettings s;
  readTolerances(pl, s);
  deriveJacobianFreeOperator(pl, s);
  deriveStratimikos(pl, s);
  deriveNox(pl, s);
  return s;
}

}  // namespace impm
