// ImplicitNewmark for the quadratic Lagrange (FE Q9/Hex27) shape, 2D and 3D (one translation unit per family, built in
// parallel).
#include "solvers/implicit/ImplicitNewmarkImpl.hpp"

namespace impm {
template class ImplicitNewmark<QuadraticLagrange, 2>;
template class ImplicitNewmark<QuadraticLagrange, 3>;
}  // namespace impm
