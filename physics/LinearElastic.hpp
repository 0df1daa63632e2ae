// Small-strain isotropic linear elasticity in plane strain or plane stress: the one place the
// elastic law is written. LinearElasticLaw is a Kokkos functor type over a table of parameter
// sets, indexed by the particle's material id, so that several materials (the deck's
// `Materials`) share one kernel instantiation. The kernels in core/ are templated on the
// law type and call only its device interface:
//   stress(m, s0, G, s)      stress after a displacement-gradient increment G from stress s0
//   tangent(m, D)            dsigma/deps on (eps_xx, eps_yy, 2 eps_xy), for K = int B^T D B
//   energyDensity(m, s)      strain energy per unit volume at stress s
#pragma once

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/Types.hpp"

namespace impm {

enum class PlaneCondition { PlaneStrain, PlaneStress };

// One material's parameters, as the deck gives them.
struct ElasticParameters {
  double E = 1.0, nu = 0.0, density = 1.0;
};

// The law on the device: a table of constants indexed by material id. Cheap to copy into
// kernels (one View). Columns: in-plane constants of D = [[c11, c12, 0], [c12, c11, 0],
// [0, 0, c33]], the out-of-plane sigma_zz per unit in-plane volumetric strain (plane strain:
// lambda; plane stress: 0), and 1 / (c11^2 - c12^2) for the compliance in the energy.
struct LinearElasticLaw {
  enum : int { C11 = 0, C12, C33, CZZ, InvDet, Count };
  Kokkos::View<double* [Count], Kokkos::LayoutRight, DeviceType> table;

  // s = s0 + D sym(G) (s: xx, yy, xy, zz). s may alias s0.
  KOKKOS_INLINE_FUNCTION void stress(int m, const double s0[4], double gxx, double gxy, double gyx, double gyy,
                                     double s[4]) const {
    const double a = table(m, C11), b = table(m, C12), c = table(m, C33), z = table(m, CZZ);
    const double gamma = gxy + gyx;  // engineering shear strain increment
    s[0] = s0[0] + a * gxx + b * gyy;
    s[1] = s0[1] + b * gxx + a * gyy;
    s[2] = s0[2] + c * gamma;
    s[3] = s0[3] + z * (gxx + gyy);
  }
  KOKKOS_INLINE_FUNCTION void tangent(int m, double D[3][3]) const {
    const double a = table(m, C11), b = table(m, C12), c = table(m, C33);
    D[0][0] = a; D[0][1] = b; D[0][2] = 0;
    D[1][0] = b; D[1][1] = a; D[1][2] = 0;
    D[2][0] = 0; D[2][1] = 0; D[2][2] = c;
  }
  // (1/2) sigma : eps with eps = D^-1 sigma in the plane (the out-of-plane term vanishes in
  // both plane strain, eps_zz = 0, and plane stress, sigma_zz = 0).
  KOKKOS_INLINE_FUNCTION double energyDensity(int m, const double s[4]) const {
    const double a = table(m, C11), b = table(m, C12), c = table(m, C33), inv = table(m, InvDet);
    const double exx = (a * s[0] - b * s[1]) * inv, eyy = (a * s[1] - b * s[0]) * inv;
    return 0.5 * (s[0] * exx + s[1] * eyy + s[2] * s[2] / c);
  }
};

// The host side: the parameter sets (material id = index), the plane condition, and the
// device law built from them.
class LinearElastic {
 public:
  using Law = LinearElasticLaw;
  LinearElastic() : LinearElastic(std::vector<ElasticParameters>{ElasticParameters{}}, PlaneCondition::PlaneStrain) {}
  LinearElastic(const std::vector<ElasticParameters>& materials, PlaneCondition plane) : params_(materials), plane_(plane) {
    law_.table = decltype(law_.table)("elastic_constants", materials.size());
    auto h = Kokkos::create_mirror_view(law_.table);
    for (int m = 0; m < (int)materials.size(); ++m) {
      h(m, Law::C11) = c11(m); h(m, Law::C12) = c12(m); h(m, Law::C33) = c33(m); h(m, Law::CZZ) = czz(m);
      h(m, Law::InvDet) = 1.0 / (c11(m) * c11(m) - c12(m) * c12(m));
    }
    Kokkos::deep_copy(law_.table, h);
  }
  // One material (id 0).
  LinearElastic(double E, double nu, double density, PlaneCondition plane = PlaneCondition::PlaneStrain)
      : LinearElastic(std::vector<ElasticParameters>{ElasticParameters{E, nu, density}}, plane) {}

  const Law& law() const { return law_; }
  int count() const { return (int)params_.size(); }
  const ElasticParameters& parameters(int m) const { return params_[m]; }
  PlaneCondition plane() const { return plane_; }
  double density(int m) const { return params_[m].density; }
  double c11(int m) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ == PlaneCondition::PlaneStrain ? E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) : E / (1 - nu * nu);
  }
  double c12(int m) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ == PlaneCondition::PlaneStrain ? E * nu / ((1 + nu) * (1 - 2 * nu)) : E * nu / (1 - nu * nu);
  }
  double c33(int m) const { return params_[m].E / (2 * (1 + params_[m].nu)); }
  double czz(int m) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ == PlaneCondition::PlaneStrain ? E * nu / ((1 + nu) * (1 - 2 * nu)) : 0.0;
  }
  // The modulus a 1D bar of this 2D model sees: E in plane stress, E/(1 - nu^2) in plane strain.
  double barModulus(int m = 0) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ == PlaneCondition::PlaneStress ? E : E / (1 - nu * nu);
  }
  // P-wave speed of the 2D model, for the explicit stable time step; the fastest over the table.
  double pWaveSpeed(int m) const { return std::sqrt(c11(m) / density(m)); }
  double maxPWaveSpeed() const {
    double c = 0;
    for (int m = 0; m < count(); ++m) c = std::max(c, pWaveSpeed(m));
    return c;
  }
  std::string planeName() const { return plane_ == PlaneCondition::PlaneStrain ? "plane strain" : "plane stress"; }

 private:
  std::vector<ElasticParameters> params_;
  PlaneCondition plane_ = PlaneCondition::PlaneStrain;
  Law law_;
};

}  // namespace impm
