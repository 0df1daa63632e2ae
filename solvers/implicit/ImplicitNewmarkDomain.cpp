// ImplicitNewmark for cpGIMP and CPDI, 2D and 3D (one translation unit per family, built in parallel).
#include "solvers/implicit/ImplicitNewmarkImpl.hpp"

namespace impm {
template class ImplicitNewmark<ConvectedGimp, 2>;
template class ImplicitNewmark<ConvectedGimp, 3>;
template class ImplicitNewmark<Cpdi, 2>;
template class ImplicitNewmark<Cpdi, 3>;
}  // namespace impm
