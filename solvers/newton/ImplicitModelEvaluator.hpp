// Thyra model evaluator over a ResidualModel (solvers/newton/ResidualModel.hpp) (the preconditioners it
// applies are in PreconditionerCache.hpp and its implementations).
//
// Supports IN_ARG_x, OUT_ARG_f, OUT_ARG_W_prec (when a preconditioner is configured) and OUT_ARG_W_op
// (assembled Newton: W_op is a Thyra::TpetraLinearOp re-pointed at the current P). For Jacobian-free
// Newton-Krylov wrap it in NOX::MatrixFreeModelEvaluatorDecorator, which supplies the W_op.
// NewtonSolver keeps one across solve() calls while the ResidualModel and its unknown map are unchanged
// (beginSolve() between them) and builds a new one when the map changes; the preconditioner cache is
// owned by the solver, so that an unchanged matrix graph is not set up again either way.
#pragma once

#include <Teuchos_ParameterList.hpp>
#include <Thyra_StateFuncModelEvaluatorBase.hpp>

#include "solvers/newton/PreconditionerCache.hpp"
#include "solvers/newton/ResidualModel.hpp"

namespace impm {

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
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> get_W_factory() const override { return W_factory_; }

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
