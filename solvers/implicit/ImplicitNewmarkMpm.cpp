// ImplicitNewmark for linear MPM and uniform GIMP, 2D and 3D (one translation unit per family, built in parallel).
#include "solvers/implicit/ImplicitNewmarkImpl.hpp"

namespace impm {
template class ImplicitNewmark<LinearMpm, 2>;
template class ImplicitNewmark<LinearMpm, 3>;
template class ImplicitNewmark<UniformGimp, 2>;
template class ImplicitNewmark<UniformGimp, 3>;
}  // namespace impm
