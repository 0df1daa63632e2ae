// Stiffness contributions K_e = int B^T D B, assembled over blocks of grid nodes, at the
// particles' current state (D from the law at J = V / V0 and, for history materials, at the
// step's increment from the stored history: J2's consistent tangent; finite-strain materials add
// the geometric term int grad S_a . sigma . grad S_b).
//
// Two ways to integrate, both as Kokkos kernels that fill one small dense matrix per entry:
//  - overlapStiffness (the seed's GIMP stiffness, slide 6): one entry per particle-cell pair.
//    The particle's D is spread over its domain (chi_p) and the integral is exact: on one cell
//    the integrand is a polynomial of degree <= 2 in x and in y, so 2 x 2 Gauss-Legendre
//    points on the overlap box integrate it exactly. Block = the cell's 2 x 2 nodes.
//  - stencilStiffness: one entry per particle, V_p B_p^T D B_p with B_p from the particle's
//    stencil gradients. For MPM and the FE modes the particle is an integration point (point
//    gradients; the FE reference's particles are Gauss points with their weights as volumes);
//    for GIMP it uses the averaged gradients and is then the exact derivative of the GIMP
//    internal force (the seed's integrated stiffness is not). Block = the stencil's nodes.
// Local dof of block node (a, b[, c]): Dim (a + blockNodes[0] (b + blockNodes[1] c)) + component.
#pragma once

#include "core/ParticleCellPairs.hpp"
#include "core/ParticleStencil.hpp"
#include "core/SmallMatrix.hpp"

namespace impm {

// Per entry: the block's first node (i, j[, k]) and its dense matrix over the block's dofs.
struct BlockMatrices {
  int count = 0;
  int dim = 2;
  int blockNodes[3] = {2, 2, 1};                                // nodes per direction of a block (1 in z for 2D)
  Kokkos::View<int**, Kokkos::LayoutRight, DeviceType> origin;  // count x dim
  Kokkos::View<double***, Kokkos::LayoutRight, DeviceType> K;
  Kokkos::View<int*, DeviceType> field;  // each block's velocity field (empty: all field 0)
  int nodes() const { return blockNodes[0] * blockNodes[1] * blockNodes[2]; }
  int dofs() const { return dim * nodes(); }
};

namespace detail {
// K(k) += w B^T D B for node gradients grad[a][d] of the block's nodes (nn of them), with the
// material tangent D on the Voigt strains of StressLayout<Dim> (engineering shears).
// B_a[v][c], strain component v = (i, j) from displacement component c of node a, is grad_a[j] at
// c = i, grad_a[i] at c = j (a shear) and zero elsewhere. The sums over v skip those zeros and keep
// the order of v, so K is what the dense products B_b^T (D B_a) give, bit for bit.
template <int Dim, class KView>
KOKKOS_INLINE_FUNCTION void addBtDB(const KView& K, int k, int nn, const double (*grad)[Dim], double w,
                                    const double (&D)[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt]) {
  using SL = StressLayout<Dim>;
  constexpr int nv = SL::voigt;
  for (int a = 0; a < nn; ++a) {
    double DB[nv][Dim];  // D B_a
    for (int r = 0; r < nv; ++r)
      for (int c = 0; c < Dim; ++c) {
        double sum = 0;
        for (int v = 0; v < nv; ++v) {
          const int i = SL::first(v), j = SL::second(v);
          if (c == i)
            sum += D[r][v] * grad[a][j];
          else if (c == j)
            sum += D[r][v] * grad[a][i];
        }
        DB[r][c] = sum;
      }
    for (int b = 0; b < nn; ++b)
      for (int rb = 0; rb < Dim; ++rb)
        for (int c = 0; c < Dim; ++c) {
          double sum = 0;  // row rb of B_b^T times column c of D B_a
          for (int v = 0; v < nv; ++v) {
            const int i = SL::first(v), j = SL::second(v);
            if (rb == i)
              sum += grad[b][j] * DB[v][c];
            else if (rb == j)
              sum += grad[b][i] * DB[v][c];
          }
          K(k, Dim * b + rb, Dim * a + c) += w * sum;
        }
  }
}

// The trial state of particle p (Assembled Newton on finite strain): G from its gradient view,
// the stress s of the law at F = (I + G) F_n (from a copy of the particle's history), the volume
// Vp times det(I + G), and the nn node gradients moved onto the deformed domain, (I + G)^-T grad S.
template <int Dim, class Law, class GradientView, class DeformationView, class HistoryView>
KOKKOS_INLINE_FUNCTION void moveToTrialState(const Law& law, int mat, int p, const GradientView& Gp,
                                             const DeformationView& Fp, const HistoryView& hist, bool withHistory,
                                             double (&G)[Dim][Dim], double* s, double& Vp, int nn,
                                             double (*grad)[Dim]) {
  double dF[Dim][Dim], inv[Dim][Dim], F[Dim][Dim], Fn[Dim][Dim];
  for (int i = 0; i < Dim; ++i)
    for (int j = 0; j < Dim; ++j) {
      G[i][j] = Gp(p, i, j);
      dF[i][j] = (i == j ? 1.0 : 0.0) + G[i][j];
      Fn[i][j] = Fp(p, i, j);
    }
  multiply<Dim>(dF, Fn, F);
  const double Jd = determinant<Dim>(dF);
  inverse<Dim>(dF, Jd, inv);
  double hTrial[ParticleSet::kHistoryCount];  // the stress update's copy (the trial state is discarded)
  if (withHistory)
    for (int i = 0; i < ParticleSet::kHistoryCount; ++i) hTrial[i] = hist(p, i);
  law.template stress<Dim>(mat, s, G, F, withHistory ? hTrial : nullptr, s);
  Vp *= Jd;
  for (int n = 0; n < nn; ++n) {
    double gn[Dim];
    for (int j = 0; j < Dim; ++j) {
      double v = 0;
      for (int k = 0; k < Dim; ++k) v += inv[k][j] * grad[n][k];
      gn[j] = v;
    }
    for (int j = 0; j < Dim; ++j) grad[n][j] = gn[j];
  }
}

// The geometric (initial-stress) term of the current-configuration tangent:
// V grad S_a . sigma . grad S_b on each component.
template <int Dim, class KView>
KOKKOS_INLINE_FUNCTION void addGeometricStiffness(const KView& K, int p, int nn, const double (*grad)[Dim],
                                                  const double* s, double V) {
  using SL = StressLayout<Dim>;
  for (int a = 0; a < nn; ++a)
    for (int b = 0; b < nn; ++b) {
      double k = 0;
      for (int i = 0; i < Dim; ++i)
        for (int j = 0; j < Dim; ++j) k += grad[a][i] * s[SL::index(i, j)] * grad[b][j];
      for (int c = 0; c < Dim; ++c) K(p, Dim * a + c, Dim * b + c) += V * k;
    }
}
}  // namespace detail

// The seed's GIMP stiffness (2D only).
template <class ExecSpace, class Law>
BlockMatrices overlapStiffness(const StructuredGrid& g, const ParticleCellPairs& pairs, const ParticleSet& ps,
                               const Law& law) {
  BlockMatrices out;
  out.count = pairs.count;
  out.origin = decltype(out.origin)("overlap_block_origin", pairs.count, 2);
  {
    auto O = out.origin;
    auto C = pairs.cell;
    Kokkos::parallel_for(
        "overlap_block_origin", Kokkos::RangePolicy<ExecSpace>(0, pairs.count), KOKKOS_LAMBDA(int k) {
          O(k, 0) = C(k, 0);
          O(k, 1) = C(k, 1);
        });
  }
  out.K = Kokkos::View<double***, Kokkos::LayoutRight, DeviceType>("overlap_stiffness", pairs.count, 8, 8);
  auto P = pairs.particle;
  auto C = pairs.cell;
  auto B = pairs.box;
  auto V = ps.volume;
  auto V0 = ps.volume0;
  auto hs = ps.halfSize;
  auto matId = ps.material;
  auto x = ps.x;
  auto hist = ps.history;
  auto K = out.K;
  Kokkos::parallel_for(
      "overlap_stiffness", Kokkos::RangePolicy<ExecSpace>(0, pairs.count), KOKKOS_LAMBDA(int k) {
        const int p = P(k);
        const double cx = g.x0 + C(k, 0) * g.hx, cy = g.y0 + C(k, 1) * g.hy;
        // Gauss points +-1/sqrt(3) on the box; weight = box area / 4 * thickness of the particle.
        const double a = B(k, 0), b = B(k, 1), c = B(k, 2), d = B(k, 3);
        const double s = 0.5773502691896257;
        const double qx[2] = {0.5 * (a + b) - 0.5 * (b - a) * s, 0.5 * (a + b) + 0.5 * (b - a) * s};
        const double qy[2] = {0.5 * (c + d) - 0.5 * (d - c) * s, 0.5 * (c + d) + 0.5 * (d - c) * s};
        // The particle's volume over its domain clipped to the grid (the boxes are clipped too,
        // as the stencils are; see ParticleStencil::build1d).
        const double clippedWidth =
            detail::minOf(x(p, 0) + hs(p, 0), g.xMax()) - detail::maxOf(x(p, 0) - hs(p, 0), g.x0);
        const double clippedHeight =
            detail::minOf(x(p, 1) + hs(p, 1), g.yMax()) - detail::maxOf(x(p, 1) - hs(p, 1), g.y0);
        const double thickness = V(p) / (clippedWidth * clippedHeight);
        const double wq = 0.25 * (b - a) * (d - c) * thickness;
        double D[3][3], h[ParticleSet::kHistoryCount];
        const double G[2][2] = {};  // at the step's start
        if (law.hasHistory(matId(p)))
          for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h[i] = hist(p, i);
        law.template tangent<2>(matId(p), G, V(p) / V0(p), h, D);
        for (int ix = 0; ix < 2; ++ix)
          for (int iy = 0; iy < 2; ++iy) {
            const double xi = (qx[ix] - cx) / g.hx, eta = (qy[iy] - cy) / g.hy;
            const double Nx[2] = {1.0 - xi, xi}, Ny[2] = {1.0 - eta, eta};
            const double dNx[2] = {-1.0 / g.hx, 1.0 / g.hx}, dNy[2] = {-1.0 / g.hy, 1.0 / g.hy};
            double grad[4][2];
            for (int dj = 0; dj < 2; ++dj)
              for (int di = 0; di < 2; ++di) {
                grad[di + 2 * dj][0] = dNx[di] * Ny[dj];
                grad[di + 2 * dj][1] = Nx[di] * dNy[dj];
              }
            detail::addBtDB<2>(K, k, 4, grad, wq, D);
          }
      });
  return out;
}

// Blocks are Shape::max_nodes_1d nodes wide (fewer on a grid with fewer node lines); a stencil
// shorter than that (GIMP near a cell line) sits inside the block, which is shifted to stay
// inside the grid. With massFactor c > 0 the block also gets c times the particle's consistent
// mass, c m_p S_ap S_bp per component. Block node (a, b[, c]) is local node
// a + bn_x (b + bn_y c); its dofs are Dim (node) + component.
//
// With atTrialState (Assembled Newton on finite strain), each finite-strain particle's block is
// the exact derivative of its deformed-domain internal force (InternalForce.hpp) at the trial
// displacement whose gradient G is in ps.gradient: with dF = I + G, the gradients on the deformed
// domain dF^-T grad S, its volume det(dF) V, and the law's stress and tangent at F = dF F_n.
template <class ExecSpace, class Shape, int Dim, class Law>
BlockMatrices stencilStiffness(const StructuredGrid& g, const ParticleSet& ps, const Law& law, double massFactor = 0.0,
                               bool atTrialState = false) {
  constexpr int bn = Shape::max_nodes_1d;
  constexpr int maxNodes = Dim == 2 ? bn * bn : bn * bn * bn;
  BlockMatrices out;
  out.count = ps.count;
  out.dim = Dim;
  int bnd[3] = {1, 1, 1};
  for (int d = 0; d < Dim; ++d) bnd[d] = bn < g.cells(d) + 1 ? bn : g.cells(d) + 1;
  for (int d = 0; d < 3; ++d) out.blockNodes[d] = bnd[d];
  const int nn = bnd[0] * bnd[1] * bnd[2], nd = Dim * nn;
  // Not zeroed here: the kernel writes every origin and zeroes each block before summing into it.
  out.origin =
      decltype(out.origin)(Kokkos::view_alloc("stencil_block_origin", Kokkos::WithoutInitializing), ps.count, Dim);
  out.K = Kokkos::View<double***, Kokkos::LayoutRight, DeviceType>(
      Kokkos::view_alloc("stencil_stiffness", Kokkos::WithoutInitializing), ps.count, nd, nd);
  auto O = out.origin;
  auto K = out.K;
  auto x = ps.x;
  auto hs = ps.halfSize;
  auto V = ps.volume;
  auto V0 = ps.volume0;
  auto m = ps.mass;
  auto matId = ps.material;
  auto sigma = ps.stress;
  const FixedParticleViews<Dim> fixed(ps);
  auto Fp = fixed.F;
  auto Gp = fixed.gradient;
  auto hist = ps.history;
  const int b0 = bnd[0], b1 = bnd[1], b2 = bnd[2];
  const auto deformation = DomainDeformation<Shape, Dim>::of(ps);
  Kokkos::parallel_for(
      "stencil_stiffness", Kokkos::RangePolicy<ExecSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        const ParticleStencil<Shape, Dim> st(g, x, hs, deformation, p);
        const int blockN[3] = {b0, b1, b2};
        int origin[3] = {0, 0, 0};
        for (int d = 0; d < Dim; ++d) {
          const int last = g.cells(d) + 1 - blockN[d];
          origin[d] = st.first[d] < last ? st.first[d] : last;
          O(p, d) = origin[d];
        }
        double grad[maxNodes][Dim], w[maxNodes];
        for (int n = 0; n < maxNodes; ++n) {
          w[n] = 0.0;
          for (int d = 0; d < Dim; ++d) grad[n][d] = 0.0;
        }
        st.forEachOffset([&](const int* off, double wn, const double* gn) {
          int local[3] = {0, 0, 0};
          for (int d = 0; d < Dim; ++d) local[d] = st.first[d] + off[d] - origin[d];
          const int n = local[0] + b0 * (local[1] + b1 * local[2]);
          w[n] = wn;
          for (int d = 0; d < Dim; ++d) grad[n][d] = gn[d];
        });
        for (int r = 0; r < nd; ++r)
          for (int c = 0; c < nd; ++c) K(p, r, c) = 0.0;
        double D[StressLayout<Dim>::voigt][StressLayout<Dim>::voigt];
        using SL = StressLayout<Dim>;
        const int mat = matId(p);
        const bool finite = law.finiteStrain(mat);
        double Vp = V(p), s[SL::count];
        for (int c = 0; c < SL::count; ++c) s[c] = sigma(p, c);
        // The increment's gradient (zero at the step's start) and the step's starting history:
        // the state the tangent is taken at.
        double G[Dim][Dim] = {}, h[ParticleSet::kHistoryCount];
        const bool withHistory = law.hasHistory(mat);
        if (withHistory)
          for (int i = 0; i < ParticleSet::kHistoryCount; ++i) h[i] = hist(p, i);
        if (finite && atTrialState)
          detail::moveToTrialState<Dim>(law, mat, p, Gp, Fp, hist, withHistory, G, s, Vp, nn, grad);
        law.template tangent<Dim>(mat, G, Vp / V0(p), withHistory ? h : nullptr, D);
        detail::addBtDB<Dim>(K, p, nn, grad, Vp, D);
        if (finite) detail::addGeometricStiffness<Dim>(K, p, nn, grad, s, Vp);
        if (massFactor > 0.0)
          for (int a = 0; a < nn; ++a)
            for (int b = 0; b < nn; ++b)
              for (int c = 0; c < Dim; ++c) K(p, Dim * a + c, Dim * b + c) += massFactor * m(p) * w[a] * w[b];
      });
  return out;
}

}  // namespace impm
