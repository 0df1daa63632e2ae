// The assembled matrix P of an implicit step: the block matrices of the stiffness kernels (one
// dense block per particle, or per particle-cell pair for the seed's GIMP stiffness) summed into a
// Tpetra CrsMatrix over the free dofs, plus an optional lumped-mass diagonal and optional
// couplings among a node's fields (multi-field contact's stiffness).
//
// The graph is built once per pattern of free dofs a rank sees: every block of the rank's ghost
// region couples its free dofs (blocks without particles hold zeros), so that moving particles
// only change values and Ifpack2 keeps its symbolic set-up. Each rank fills an overlap matrix
// over its ghost region and one Export sums the overlapping rows.
//
// Values are filled deterministically: every matrix entry sums its block contributions in block
// order, so that P is the same bit for bit at any thread count. On a host execution space
// (OpenMP) one sequential pass over the blocks does it; on a device, a parallel gather that sums
// each entry's contributions in the same order (the choice: Fill; the two agree bit for bit,
// test_stiffness_assembler). The sequential pass is the faster on the host: it launches no
// kernels, which cost about a millisecond each when the threads have gone idle in a direct solve.
#pragma once

#include <Tpetra_CrsMatrix.hpp>
#include <vector>

#include "core/GridDistribution.hpp"
#include "core/kernels/Stiffness.hpp"
#include "solvers/newton/ResidualModel.hpp"
#include "solvers/implicit/FreeDofMap.hpp"

namespace impm {

// How the values are summed: Auto (Sequential on a host execution space, Parallel on a device).
enum class StiffnessFill { Auto, Sequential, Parallel };

template <int Dim>
class StiffnessAssembler {
 public:
  // Blocks of blockNodes nodes per direction (fewer on a grid with fewer nodes) whose first nodes
  // are multiples of blockStride (2 for Q9 elements, else 1).
  StiffnessAssembler(const GridDistribution& dist, int blockNodes, int blockStride,
                     StiffnessFill fill = StiffnessFill::Auto);

  // Several velocity fields (multi-field contact): field f's free flags and mass sit f * stride
  // columns after field 0's, its dofs are FreeDofMap's field f, and a block couples the dofs of
  // its own field (BlockMatrices::field).
  void setFields(int fields, int stride) {
    fields_ = fields;
    stride_ = stride;
  }

  // The graph for the free dofs flagged (> 1/2) in columns freeX.. of the ghosted grid state;
  // kept while that set is unchanged on every rank. Collective. True when (re)built.
  bool updatePattern(const MultiVector& stateGhosted, int freeX, const FreeDofMap<Dim>& dofs);

  // Couplings of the fields at a node, each field against a weighted mean of them (the contact
  // law's linearization, ContactActiveSet::jacobian): per owned node, a 3 x 3 block B_a per field
  // (row-major, at 9 a) and then a weight w_b per field (at 9 fields + b);
  // P((n, d, a), (n, e, b)) += factor B_a(d, e) (delta_ab - w_b).
  struct NodeCouplings {
    Kokkos::View<const double**, Kokkos::LayoutRight, DeviceType> values;
    double factor = 0.0;
  };

  // P = sum of the blocks + massFactor diag(m) at the free dofs (when lumpedMass is given: the
  // mass in its column massColumn) + the node couplings (when given). Requires updatePattern for
  // this step's dofs.
  void fill(const BlockMatrices& blocks, const FreeDofMap<Dim>& dofs, const MultiVector* lumpedMass, int massColumn,
            double massFactor, const NodeCouplings* couplings = nullptr);

  Teuchos::RCP<CrsMatrix> matrix() const { return P_; }
  void forgetMatrix() { P_ = Teuchos::null; }

  // Checkpoint: P's rows (per row: gid, entry count, then column gid and value pairs), and P
  // taken back when its rows are the free dofs on every rank (collective; false otherwise). The
  // graph is rebuilt at the next updatePattern.
  void save(std::vector<double>& rows) const;
  bool restore(const std::vector<double>& rows, const FreeDofMap<Dim>& dofs);

 private:
  // The blocks of the rank's ghost region, numbered x slowest.
  struct BlockGrid {
    int nodes[3] = {1, 1, 1}, first[3] = {0, 0, 0}, count[3] = {1, 1, 1}, stride = 1;
    KOKKOS_INLINE_FUNCTION long index(int bi, int bj, int bk) const {
      return (long((bi - first[0]) / stride) * count[1] + (bj - first[1]) / stride) * count[2] +
             (bk - first[2]) / stride;
    }
    long size() const { return long(count[0]) * count[1] * count[2]; }
    int nodeCount() const { return nodes[0] * nodes[1] * nodes[2]; }
  };
  template <class Visit>
  void forEachBlockCoupling(const MultiVector& stateGhosted, int freeX, const FreeDofMap<Dim>& dofs,
                            Visit&& visit) const;
  void buildGraph(const MultiVector& stateGhosted, int freeX, const FreeDofMap<Dim>& dofs);
  void sumBlocks(const BlockMatrices& blocks) const;            // the parallel gather
  void sumBlocksSequential(const BlockMatrices& blocks) const;  // one pass, block after block
  void addNodeCouplings(const NodeCouplings& couplings, const FreeDofMap<Dim>& dofs);
  // The couplings of the free components of every node's fields (several fields: those of
  // different fields, which no block holds).
  template <class Visit>
  void forEachNodeCoupling(const MultiVector& stateGhosted, int freeX, const FreeDofMap<Dim>& dofs,
                           Visit&& visit) const;

  const GridDistribution& dist_;
  BlockGrid blocks_;
  int nd_ = 0;  // dofs per block
  int fields_ = 1, stride_ = 0;
  bool parallelFill_ = false;
  Teuchos::RCP<CrsMatrix> P_, overlapP_;
  Teuchos::RCP<const Export> exporter_;
  std::vector<GO> patternKey_;
  // Offsets into overlapP_'s values: per block and local dof pair (r, c) (-1: not free), per
  // free dof for its diagonal, and per free dof, field b and component e for the entry coupling it
  // to its node's dof (e, b) (-1: not free).
  Kokkos::View<long*, DeviceType> blockOffsets_, diagonalOffsets_;
  Kokkos::View<long**, Kokkos::LayoutRight, DeviceType> nodeOffsets_;
};

}  // namespace impm
