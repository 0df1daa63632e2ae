// ImplicitNewmark for the B-splines, 2D and 3D (one translation unit per family, built in parallel).
#include "solvers/implicit/ImplicitNewmarkImpl.hpp"

namespace impm {
template class ImplicitNewmark<QuadraticBSpline, 2>;
template class ImplicitNewmark<QuadraticBSpline, 3>;
template class ImplicitNewmark<CubicBSpline, 2>;
template class ImplicitNewmark<CubicBSpline, 3>;
}  // namespace impm
