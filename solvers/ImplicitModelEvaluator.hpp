// Thyra model evaluator over a ResidualModel (solvers/ResidualModel.hpp), and the preconditioners
// (Ifpack2, or a gathered direct solve) it builds from the assembled matrix P.
//
// Supports IN_ARG_x, OUT_ARG_f, OUT_ARG_W_prec (when a preconditioner is configured) and OUT_ARG_W_op
// (assembled Newton: W_op is a Thyra::TpetraLinearOp re-pointed at the current P). For Jacobian-free
// Newton-Krylov wrap it in NOX::MatrixFreeModelEvaluatorDecorator, which supplies the W_op.
// NewtonSolver keeps one across solve() calls while the ResidualModel and its unknown map are unchanged
// (beginSolve() between them) and builds a new one when the map changes; the preconditioner cache is
// owned by the solver, so that an unchanged matrix graph is not set up again either way.
#pragma once

#include "solvers/ResidualModel.hpp"

#include <Ifpack2_Preconditioner.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Thyra_StateFuncModelEvaluatorBase.hpp>

#include <string>

namespace impm {

using RowMatrix = Tpetra::RowMatrix<Scalar, LO, GO, Node>;
using TpetraOperator = Tpetra::Operator<Scalar, LO, GO, Node>;
using Ifpack2Preconditioner = Ifpack2::Preconditioner<Scalar, LO, GO, Node>;

// For an Ifpack2 SCHWARZ list (the Ifpack2 preconditioner's, or MueLu's "coarse: params") on a
// rank that owns no rows: an AMESOS2 subdomain solve becomes RILUK. KLU2 throws on an empty block,
// on that rank alone, and the other ranks would wait for it in a collective for ever; the subdomain
// solve is local and, on an empty block, the same nothing whatever the solver. Returns whether it
// changed the list.
bool avoidAmesosOnEmptyBlock(Teuchos::ParameterList& schwarz, bool rankIsEmpty);

// An approximate (or exact) inverse of P, kept up to date with the matrix it is handed. Collective.
class PreconditionerCache {
 public:
  virtual ~PreconditionerCache() = default;
  // Brings the operator up to date with P (fill complete, maps equal to the unknown map).
  // `valuesVersion` (from ResidualModel::jacobianVersion) lets an up-to-date operator skip its
  // numeric set-up when P is the same object with the same values; -1 means "unknown".
  virtual Teuchos::RCP<TpetraOperator> update(const Teuchos::RCP<const CrsMatrix>& P, long valuesVersion = -1) = 0;
  // Symbolic setups (Ifpack2 initialize(), symbolic factorisation) so far.
  virtual int initializations() const = 0;
  // The unknowns' node coordinates (ResidualModel::unknownCoordinates, may be null), handed over
  // before each update() for preconditioners that use geometry (MueLu's rigid-body modes).
  virtual void setUnknownGeometry(const Teuchos::RCP<const MultiVector>& /*coordinates*/, int /*unknownsPerNode*/) {}
};

// Block Jacobi with an exact solve of each block: on every rank, sparse LU (Amesos2 KLU2, on a
// serial communicator) of the rank's rows of P restricted to its own columns. What Ifpack2's
// AMESOS2 preconditioner computes across ranks, without its two faults in 13.2: KLU2 crashes on a
// rank with no rows (a rank whose cells hold no particle), and the wrapper's set-up is collective
// (Map::isSameAs), so that rank cannot simply be skipped. No communication at all.
class LocalBlockDirectInverse : public TpetraOperator {
 public:
  // Refactors the rank's block of P (a new symbolic factorisation when its pattern changed).
  void factor(const Teuchos::RCP<const CrsMatrix>& P);
  int symbolicFactorizations() const { return symbolic_; }

  Teuchos::RCP<const Map> getDomainMap() const override { return map_; }
  Teuchos::RCP<const Map> getRangeMap() const override { return map_; }
  void apply(const MultiVector& X, MultiVector& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS,
             Scalar alpha = Teuchos::ScalarTraits<Scalar>::one(),
             Scalar beta = Teuchos::ScalarTraits<Scalar>::zero()) const override;

 private:
  class Block;
  Teuchos::RCP<const Map> map_;
  Teuchos::RCP<Block> block_;  // null on a rank without rows
  int symbolic_ = 0;
};

// An Ifpack2 preconditioner of a given type: initialize() (symbolic) when P is a new object or its
// graph may have changed, compute() (numeric) on every update. AMESOS2 on several ranks is a
// LocalBlockDirectInverse (the same block-Jacobi LU).
class IfpackPreconditionerCache : public PreconditionerCache {
 public:
  // Throws std::invalid_argument naming 'Implicit Solver/Preconditioner' or 'Implicit Solver/Ifpack2'
  // when Ifpack2 does not know `type` or rejects `params` (checked on a 1x1 matrix, not collective).
  IfpackPreconditionerCache(const std::string& type, const Teuchos::ParameterList& params);

  Teuchos::RCP<TpetraOperator> update(const Teuchos::RCP<const CrsMatrix>& P, long valuesVersion = -1) override;
  int initializations() const override { return initializations_; }

  const std::string& type() const { return type_; }
  int computations() const { return computations_; }

 private:
  Teuchos::RCP<Ifpack2Preconditioner> create(const Teuchos::RCP<const CrsMatrix>& P) const;

  std::string type_;
  Teuchos::ParameterList params_;
  Teuchos::RCP<Ifpack2Preconditioner> prec_;
  Teuchos::RCP<LocalBlockDirectInverse> blockDirect_;
  Teuchos::RCP<const CrsMatrix> matrix_;  // held so its address cannot be reused by a new matrix
  int initializations_ = 0, computations_ = 0;
  long valuesVersion_ = -1;
};

// P^{-1} by sparse LU (Amesos2 KLU2) of P gathered onto rank 0: works around Amesos2 13.2, whose KLU2
// returns wrong solutions for a matrix distributed over several ranks (it is right on one rank, which
// is how it is used here: on a serial communicator). Every update refactors; apply() gathers the
// vectors to rank 0 and scatters the solution back. Meant for moderate sizes (a direct solve).
class GatheredDirectInverse : public PreconditionerCache {
 public:
  GatheredDirectInverse();
  ~GatheredDirectInverse() override;
  Teuchos::RCP<TpetraOperator> update(const Teuchos::RCP<const CrsMatrix>& P, long valuesVersion = -1) override;
  int initializations() const override { return factorizations_; }

 private:
  class Op;
  Teuchos::RCP<Op> op_;
  int factorizations_ = 0;
};

class ImplicitModelEvaluator : public Thyra::StateFuncModelEvaluatorBase<double> {
 public:
  // supportsWop: advertise OUT_ARG_W_op (assembled Newton). prec: null for no preconditioner.
  ImplicitModelEvaluator(ResidualModel& model, const Teuchos::RCP<const Map>& map,
                         const Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& W_factory,
                         bool supportsWop, const Teuchos::RCP<PreconditionerCache>& prec);

  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> get_x_space() const override { return space_; }
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> get_f_space() const override { return space_; }
  Thyra::ModelEvaluatorBase::InArgs<double> createInArgs() const override;
  // An uninitialised Thyra::TpetraLinearOp; evalModel points it at P.
  Teuchos::RCP<Thyra::LinearOpBase<double>> create_W_op() const override;
  // A Thyra::DefaultPreconditioner; evalModel sets its right operator to the Ifpack2 preconditioner.
  Teuchos::RCP<Thyra::PreconditionerBase<double>> create_W_prec() const override;
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> get_W_factory() const override {
    return W_factory_;
  }

  const Teuchos::RCP<const Map>& map() const { return map_; }
  // Evaluations since construction or the last beginSolve().
  int residualEvaluations() const { return residualEvaluations_; }
  int jacobianEvaluations() const { return jacobianEvaluations_; }
  // Starts a new solve, possibly of a different residual function on the same map (the next time
  // step): forgets the matrix P and the point it was assembled at, so that the first W_op / W_prec
  // request asks the model again, and zeroes the evaluation counters. The preconditioner cache is
  // not touched (it keeps its symbolic set-up while P is the same static-graph object, and refactors
  // when ResidualModel::jacobianVersion says the values changed).
  void beginSolve();

 private:
  Thyra::ModelEvaluatorBase::OutArgs<double> createOutArgsImpl() const override;
  void evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& inArgs,
                     const Thyra::ModelEvaluatorBase::OutArgs<double>& outArgs) const override;
  // P at x, reusing the last one when x has not changed (NOX asks for W_op and W_prec separately).
  Teuchos::RCP<const CrsMatrix> matrixAt(const Vector& x) const;

  ResidualModel* model_;
  Teuchos::RCP<const Map> map_;
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> space_;
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> W_factory_;
  bool supportsWop_;
  Teuchos::RCP<PreconditionerCache> prec_;

  mutable Teuchos::RCP<const CrsMatrix> P_;
  mutable Teuchos::RCP<Vector> xOfP_, diff_;
  mutable int residualEvaluations_ = 0, jacobianEvaluations_ = 0;
};

}  // namespace impm
