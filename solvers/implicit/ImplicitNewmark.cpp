#include <Teuchos_ParameterList.hpp>
#include <string>

namespace impm::implicit {

// "Jacobian-Free Newton, preconditioner RILUK" or "Assembled Newton, linear solver KLU2".
std::string describeSolver(const Teuchos::ParameterList& p) {
  const std::string jac = p.get<std::string>("Jacobian");
  if (jac == "Assembled") return "Assembled Newton, linear solver " + p.get<std::string>("Assembled Linear Solver");
  return jac + " Newton, preconditioner " + p.get<std::string>("Preconditioner");
}

}  // namespace impm::implicit
