#include "solvers/newton/ImplicitModelEvaluator.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Thyra_DefaultPreconditioner.hpp>
#include <Thyra_TpetraLinearOp.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>

#include <stdexcept>

#include "core/PhaseTimer.hpp"

namespace impm {

using Teuchos::RCP;
using Teuchos::rcp;
using TOE = Thyra::TpetraOperatorVectorExtraction<Scalar, LO, GO, Node>;
using ThyraTpetraOp = Thyra::TpetraLinearOp<Scalar, LO, GO, Node>;

ImplicitModelEvaluator::ImplicitModelEvaluator(ResidualModel& model, const RCP<const Map>& map,
                                               const RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& W_factory,
                                               bool supportsWop, const RCP<PreconditionerCache>& prec)
    : model_(&model),
      map_(map),
      space_(Thyra::createVectorSpace<Scalar, LO, GO, Node>(map)),
      W_factory_(W_factory),
      supportsWop_(supportsWop),
      prec_(prec) {}

void ImplicitModelEvaluator::beginSolve() {
  P_ = Teuchos::null;  // xOfP_ and diff_ stay allocated; they are only read while P_ is set
  residualEvaluations_ = 0;
  jacobianEvaluations_ = 0;
}

Thyra::ModelEvaluatorBase::InArgs<double> ImplicitModelEvaluator::createInArgs() const {
  Thyra::ModelEvaluatorBase::InArgsSetup<double> inArgs;
  inArgs.setModelEvalDescription(this->description());
  inArgs.setSupports(Thyra::ModelEvaluatorBase::IN_ARG_x);
  return std::move(inArgs);
}

Thyra::ModelEvaluatorBase::OutArgs<double> ImplicitModelEvaluator::createOutArgsImpl() const {
  Thyra::ModelEvaluatorBase::OutArgsSetup<double> outArgs;
  outArgs.setModelEvalDescription(this->description());
  outArgs.setSupports(Thyra::ModelEvaluatorBase::OUT_ARG_f);
  if (supportsWop_) outArgs.setSupports(Thyra::ModelEvaluatorBase::OUT_ARG_W_op);
  if (!prec_.is_null()) outArgs.setSupports(Thyra::ModelEvaluatorBase::OUT_ARG_W_prec);
  return std::move(outArgs);
}

RCP<Thyra::LinearOpBase<double>> ImplicitModelEvaluator::create_W_op() const {
  TEUCHOS_TEST_FOR_EXCEPTION(!supportsWop_, std::logic_error,
                             "impm::ImplicitModelEvaluator: W_op requested but not supported");
  return rcp(new ThyraTpetraOp());
}

RCP<Thyra::PreconditionerBase<double>> ImplicitModelEvaluator::create_W_prec() const {
  if (prec_.is_null()) return Teuchos::null;
  return rcp(new Thyra::DefaultPreconditioner<double>());
}

RCP<const CrsMatrix> ImplicitModelEvaluator::matrixAt(const Vector& x) const {
  if (!P_.is_null()) {
    diff_->update(1.0, x, -1.0, *xOfP_, 0.0);
    if (diff_->normInf() == 0.0) return P_;
  }
  RCP<const CrsMatrix> P = model_->jacobianMatrix(x);
  ++jacobianEvaluations_;
  TEUCHOS_TEST_FOR_EXCEPTION(P.is_null() || !P->isFillComplete(), std::runtime_error,
                             "impm::NewtonSolver: ResidualModel::jacobianMatrix returned a null or "
                             "not fill-complete matrix");
  if (P.get() != P_.get()) {
    // Collective (Map::isSameAs); cheap when the maps are the model's own map objects.
    TEUCHOS_TEST_FOR_EXCEPTION(!P->getRangeMap()->isSameAs(*map_) || !P->getDomainMap()->isSameAs(*map_),
                               std::runtime_error,
                               "impm::NewtonSolver: the matrix from ResidualModel::jacobianMatrix must have "
                               "range and domain maps equal to ResidualModel::unknownMap()");
  }
  if (xOfP_.is_null()) {
    xOfP_ = rcp(new Vector(map_));
    diff_ = rcp(new Vector(map_));
  }
  Tpetra::deep_copy(*xOfP_, x);
  P_ = P;
  return P_;
}

void ImplicitModelEvaluator::evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& inArgs,
                                           const Thyra::ModelEvaluatorBase::OutArgs<double>& outArgs) const {
  TEUCHOS_TEST_FOR_EXCEPTION(inArgs.get_x().is_null(), std::logic_error,
                             "impm::ImplicitModelEvaluator: evalModel without x");
  const RCP<const Vector> x = TOE::getConstTpetraVector(inArgs.get_x());

  const RCP<Thyra::VectorBase<double>> f_out = outArgs.get_f();
  if (!f_out.is_null()) {
    const RCP<Vector> f = TOE::getTpetraVector(f_out);
    model_->residual(*x, *f);
    ++residualEvaluations_;
  }

  if (supportsWop_) {
    const RCP<Thyra::LinearOpBase<double>> W_out = outArgs.get_W_op();
    if (!W_out.is_null()) {
      // Re-point NOX's W_op at the current P: Amesos2 sees a new matrix object (full factorisation)
      // or the same one with new values (numeric refactorisation).
      auto W = Teuchos::rcp_dynamic_cast<ThyraTpetraOp>(W_out, true);
      W->constInitialize(space_, space_, matrixAt(*x));
    }
  }

  if (!prec_.is_null()) {
    const RCP<Thyra::PreconditionerBase<double>> W_prec_out = outArgs.get_W_prec();
    if (!W_prec_out.is_null()) {
      const RCP<const CrsMatrix> P = matrixAt(*x);
      prec_->setUnknownGeometry(model_->unknownCoordinates(), model_->unknownsPerNode());
      RCP<TpetraOperator> M = prec_->update(P, model_->jacobianVersion());
      auto prec = Teuchos::rcp_dynamic_cast<Thyra::DefaultPreconditioner<double>>(W_prec_out, true);
      const RCP<Thyra::LinearOpBase<double>> op = Thyra::tpetraLinearOp<Scalar, LO, GO, Node>(space_, space_, M);
      prec->initializeRight(op);  // (a typed RCP would be ambiguous between the const and non-const overloads)
    }
  }
}

}  // namespace impm
