// Small-strain isotropic linear elasticity in plane strain, plane stress or 3D: the one place the
// elastic law is written. LinearElasticLaw is a Kokkos functor type over a table of parameter
// sets, indexed by the particle's material id, so that several materials (the deck's
// `Materials`) share one kernel instantiation. The kernels in core/ are templated on the
// law type and call only its device interface:
//   stress<Dim>(m, s0, G, s)   stress after a displacement-gradient increment G from stress s0
//   tangent<Dim>(m, D)         dsigma/deps on the Voigt strains (2D: xx, yy, 2xy), K = int B^T D B
//   energyDensity<Dim>(m, s)   strain energy per unit volume at stress s
#pragma once

#include <Kokkos_Core.hpp>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "core/ParticleSet.hpp"
#include "core/Types.hpp"

namespace impm {

// The 2D idealisations, and Solid for 3D.
enum class PlaneCondition { PlaneStrain, PlaneStress, Solid };

// One material's parameters, as the deck gives them.
struct ElasticParameters {
  double E = 1.0, nu = 0.0, density = 1.0;
};

// The law on the device: a table of constants indexed by material id. Cheap to copy into
// kernels (one View). Columns: c11 = lambda + 2 mu (plane stress: E / (1 - nu^2)), c12 = lambda
// (plane stress: nu E / (1 - nu^2)), c33 = mu, the out-of-plane sigma_zz of a 2D model per
// unit in-plane volumetric strain (plane strain: lambda; plane stress: 0), and
// 1 / (c11^2 - c12^2) for the 2D compliance in the energy. In 3D (Solid) c11, c12, c33 are
// lambda + 2 mu, lambda and mu.
struct LinearElasticLaw {
  enum : int { C11 = 0, C12, C33, CZZ, InvDet, Count };
  Kokkos::View<double* [Count], Kokkos::LayoutRight, DeviceType> table;

  // s = s0 + D sym(G) in the stored layout (StressLayout<Dim>); G[i][j] = d(du_i)/dx_j. s may
  // alias s0.
  template <int Dim>
  KOKKOS_INLINE_FUNCTION void stress(int m, const double* s0, const double (&G)[Dim][Dim], double* s) const {
    const double a = table(m, C11), b = table(m, C12), c = table(m, C33);
    if constexpr (Dim == 2) {
      const double z = table(m, CZZ);
      const double gamma = G[0][1] + G[1][0];  // engineering shear strain increment
      const double gxx = G[0][0], gyy = G[1][1];
      s[0] = s0[0] + a * gxx + b * gyy;
      s[1] = s0[1] + b * gxx + a * gyy;
      s[2] = s0[2] + c * gamma;
      s[3] = s0[3] + z * (gxx + gyy);
    } else {
      const double exx = G[0][0], eyy = G[1][1], ezz = G[2][2];
      const double sxx = s0[0] + a * exx + b * (eyy + ezz);
      const double syy = s0[1] + a * eyy + b * (exx + ezz);
      const double szz = s0[3] + a * ezz + b * (exx + eyy);
      s[2] = s0[2] + c * (G[0][1] + G[1][0]);  // xy
      s[4] = s0[4] + c * (G[1][2] + G[2][1]);  // yz
      s[5] = s0[5] + c * (G[0][2] + G[2][0]);  // xz
      s[0] = sxx; s[1] = syy; s[3] = szz;
    }
  }
  // dsigma/deps on the Voigt strains of StressLayout<Dim> (engineering shears), for K = int B^T D B.
  template <int Dim>
  KOKKOS_INLINE_FUNCTION void tangent(int m, double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) const {
    const double a = table(m, C11), b = table(m, C12), c = table(m, C33);
    constexpr int nv = StressLayout<Dim>::voigt;
    for (int i = 0; i < nv; ++i)
      for (int j = 0; j < nv; ++j) D[i][j] = 0.0;
    // Normal components: 0, 1 (and 3 in 3D); shears: 2 (and 4, 5).
    const int normals[3] = {0, 1, 3};
    const int nn = Dim;
    for (int i = 0; i < nn; ++i)
      for (int j = 0; j < nn; ++j) D[normals[i]][normals[j]] = i == j ? a : b;
    D[2][2] = c;
    if constexpr (Dim == 3) { D[4][4] = c; D[5][5] = c; }
  }
  // (1/2) sigma : eps with eps = D^-1 sigma (in 2D in the plane: the out-of-plane term vanishes
  // in both plane strain, eps_zz = 0, and plane stress, sigma_zz = 0).
  template <int Dim>
  KOKKOS_INLINE_FUNCTION double energyDensity(int m, const double* s) const {
    const double a = table(m, C11), b = table(m, C12), c = table(m, C33);
    if constexpr (Dim == 2) {
      const double inv = table(m, InvDet);
      const double exx = (a * s[0] - b * s[1]) * inv, eyy = (a * s[1] - b * s[0]) * inv;
      return 0.5 * (s[0] * exx + s[1] * eyy + s[2] * s[2] / c);
    } else {
      // lambda = b, mu = c: eps_ii = (s_ii - lambda / (3 lambda + 2 mu) tr s) / (2 mu).
      const double trace = s[0] + s[1] + s[3];
      const double k = b / (3 * b + 2 * c);
      const double exx = (s[0] - k * trace) / (2 * c), eyy = (s[1] - k * trace) / (2 * c), ezz = (s[3] - k * trace) / (2 * c);
      return 0.5 * (s[0] * exx + s[1] * eyy + s[3] * ezz + (s[2] * s[2] + s[4] * s[4] + s[5] * s[5]) / c);
    }
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
    return plane_ != PlaneCondition::PlaneStress ? E * (1 - nu) / ((1 + nu) * (1 - 2 * nu)) : E / (1 - nu * nu);
  }
  double c12(int m) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ != PlaneCondition::PlaneStress ? E * nu / ((1 + nu) * (1 - 2 * nu)) : E * nu / (1 - nu * nu);
  }
  double c33(int m) const { return params_[m].E / (2 * (1 + params_[m].nu)); }
  double czz(int m) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ == PlaneCondition::PlaneStrain ? E * nu / ((1 + nu) * (1 - 2 * nu)) : 0.0;
  }
  // The modulus a slender 1D bar of this model sees: E in plane stress and in 3D (lateral faces
  // free), E/(1 - nu^2) in plane strain.
  double barModulus(int m = 0) const {
    const double E = params_[m].E, nu = params_[m].nu;
    return plane_ != PlaneCondition::PlaneStrain ? E : E / (1 - nu * nu);
  }
  // P-wave speed of the model (2D or 3D), for the explicit stable time step; the fastest over the table.
  double pWaveSpeed(int m) const { return std::sqrt(c11(m) / density(m)); }
  double maxPWaveSpeed() const {
    double c = 0;
    for (int m = 0; m < count(); ++m) c = std::max(c, pWaveSpeed(m));
    return c;
  }
  std::string planeName() const {
    return plane_ == PlaneCondition::PlaneStrain ? "plane strain" : plane_ == PlaneCondition::PlaneStress ? "plane stress" : "3D";
  }

 private:
  std::vector<ElasticParameters> params_;
  PlaneCondition plane_ = PlaneCondition::PlaneStrain;
  Law law_;
};

}  // namespace impm
