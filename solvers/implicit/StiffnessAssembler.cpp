#include "solvers/implicit/StiffnessAssembler.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <map>

namespace impm {

template <int Dim>
StiffnessAssembler<Dim>::StiffnessAssembler(const GridDistribution& dist, int blockNodes, int blockStride,
                                            StiffnessFill fill)
    : dist_(dist) {
  constexpr bool hostExecution = Kokkos::SpaceAccessibility<Kokkos::HostSpace, MemorySpace>::accessible;
  parallelFill_ = fill == StiffnessFill::Parallel || (fill == StiffnessFill::Auto && !hostExecution);
  const StructuredGrid& g = dist.grid();
  const LocalNodeIndexer& gix = dist.ghostedIndexer();
  blocks_.stride = blockStride;
  // Along each direction the blocks start at multiples of the stride inside the rank's ghosted box
  // of nodes. A block may reach past the box's far end: a particle near it whose stencil spans fewer
  // nodes than a block (a CPDI domain, a GIMP particle away from a cell line) has its block start
  // there; the block's nodes outside the box are not coupled (the particle does not reach them).
  for (int d = 0; d < Dim; ++d) {
    const int bn = std::min(blockNodes, g.cells(d) + 1);
    const int first = ((gix.lo[d] + blockStride - 1) / blockStride) * blockStride;
    blocks_.nodes[d] = bn;
    blocks_.first[d] = first;
    blocks_.count[d] = gix.end(d) - 1 >= first ? (gix.end(d) - 1 - first) / blockStride + 1 : 0;
  }
  nd_ = Dim * blocks_.nodeCount();
}

// Visits every (block, r nd + c, row gid, column gid) coupling of two free dofs of a block.
template <int Dim>
template <class Visit>
void StiffnessAssembler<Dim>::forEachBlockCoupling(const MultiVector& stateGhosted, int freeX,
                                                   const FreeDofMap<Dim>& dofs, Visit&& visit) const {
  auto sg = stateGhosted.getLocalViewHost(Tpetra::Access::ReadOnly);
  const LocalNodeIndexer& gix = dist_.ghostedIndexer();
  const auto ghostMap = dist_.ghostedNodeMap();
  const BlockGrid& b = blocks_;
  const int nd = nd_, nodeCount = b.nodeCount();
  std::vector<GO> gid(nd);
  std::vector<char> freeDof(nd);
  for (int f = 0; f < fields_; ++f)
    for (int ci = 0; ci < b.count[0]; ++ci)
      for (int cj = 0; cj < b.count[1]; ++cj)
        for (int ck = 0; ck < b.count[2]; ++ck) {
          const int bi = b.first[0] + ci * b.stride, bj = b.first[1] + cj * b.stride, bk = b.first[2] + ck * b.stride;
          for (int a = 0; a < nodeCount; ++a) {
            const int i = bi + a % b.nodes[0], j = bj + (a / b.nodes[0]) % b.nodes[1],
                      k = bk + a / (b.nodes[0] * b.nodes[1]);
            const bool inBox = gix.contains(i, j, k);
            const int ln = inBox ? gix(i, j, k) : 0;
            for (int d = 0; d < Dim; ++d) {
              gid[Dim * a + d] = inBox ? dofs.gid(ghostMap->getGlobalElement(ln), d, f) : -1;
              freeDof[Dim * a + d] = inBox && sg(ln, freeX + f * stride_ + d) > 0.5;
            }
          }
          const long block = b.index(bi, bj, bk) + f * b.size();
          for (int r = 0; r < nd; ++r)
            for (int c = 0; c < nd; ++c)
              if (freeDof[r] && freeDof[c]) visit(block, r * nd + c, gid[r], gid[c]);
        }
}

template <int Dim>
template <class Visit>
void StiffnessAssembler<Dim>::forEachNodeCoupling(const MultiVector& stateGhosted, int freeX,
                                                  const FreeDofMap<Dim>& dofs, Visit&& visit) const {
  if (fields_ < 2) return;
  auto sg = stateGhosted.getLocalViewHost(Tpetra::Access::ReadOnly);
  const auto ghostMap = dist_.ghostedNodeMap();
  for (size_t n = 0; n < sg.extent(0); ++n) {
    const GO node = ghostMap->getGlobalElement(LO(n));
    for (int a = 0; a < fields_; ++a)
      for (int b = 0; b < fields_; ++b)
        for (int d = 0; d < Dim; ++d)
          for (int e = 0; e < Dim; ++e)
            if (a != b && sg(n, freeX + a * stride_ + d) > 0.5 && sg(n, freeX + b * stride_ + e) > 0.5)
              visit(dofs.gid(node, d, a), dofs.gid(node, e, b));
  }
}

template <int Dim>
bool StiffnessAssembler<Dim>::updatePattern(const MultiVector& stateGhosted, int freeX, const FreeDofMap<Dim>& dofs) {
  std::vector<GO> key;
  {
    auto sg = stateGhosted.getLocalViewHost(Tpetra::Access::ReadOnly);
    const auto ghostMap = dist_.ghostedNodeMap();
    for (size_t n = 0; n < sg.extent(0); ++n)
      for (int f = 0; f < fields_; ++f)
        for (int d = 0; d < Dim; ++d)
          if (sg(n, freeX + f * stride_ + d) > 0.5) key.push_back(dofs.gid(ghostMap->getGlobalElement((LO)n), d, f));
  }
  const int sameHere = (!P_.is_null() && key == patternKey_) ? 1 : 0;
  int same = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_MIN, sameHere, Teuchos::outArg(same));
  if (same) return false;
  buildGraph(stateGhosted, freeX, dofs);
  patternKey_ = std::move(key);
  return true;
}

template <int Dim>
void StiffnessAssembler<Dim>::buildGraph(const MultiVector& stateGhosted, int freeX, const FreeDofMap<Dim>& dofs) {
  const auto unknownMap = dofs.map();
  std::map<GO, std::vector<GO>> rows;
  forEachBlockCoupling(stateGhosted, freeX, dofs, [&](long, int, GO row, GO col) { rows[row].push_back(col); });
  forEachNodeCoupling(stateGhosted, freeX, dofs, [&](GO row, GO col) { rows[row].push_back(col); });
  std::vector<GO> rowGids;
  size_t maxPerRow = 1;
  for (auto& [r, cols] : rows) {
    std::sort(cols.begin(), cols.end());
    cols.erase(std::unique(cols.begin(), cols.end()), cols.end());
    rowGids.push_back(r);
    maxPerRow = std::max(maxPerRow, cols.size());
  }
  const Tpetra::global_size_t invalid = Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid();
  auto overlapMap = Teuchos::rcp(new Map(invalid, Teuchos::ArrayView<const GO>(rowGids), 0, dist_.comm()));
  auto overlapGraph = Teuchos::rcp(new Tpetra::CrsGraph<LO, GO, Node>(overlapMap, maxPerRow));
  for (const auto& [r, cols] : rows) overlapGraph->insertGlobalIndices(r, Teuchos::ArrayView<const GO>(cols));
  overlapGraph->fillComplete(unknownMap, unknownMap);
  overlapP_ = Teuchos::rcp(new CrsMatrix(overlapGraph));
  overlapP_->fillComplete(unknownMap, unknownMap);
  exporter_ = Teuchos::rcp(new Export(overlapMap, unknownMap));
  auto firstP = Teuchos::rcp(new CrsMatrix(unknownMap, 2 * maxPerRow));
  firstP->doExport(*overlapP_, *exporter_, Tpetra::ADD);
  firstP->fillComplete(unknownMap, unknownMap);
  P_ = Teuchos::rcp(new CrsMatrix(firstP->getCrsGraph()));  // static graph: values only from now on

  // Offsets in the overlap matrix's values: per block and (r, c), and per free dof's diagonal.
  auto lcl = overlapP_->getLocalMatrixDevice();
  auto rowPtr = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), lcl.graph.row_map);
  auto entries = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), lcl.graph.entries);
  const auto rowMap = overlapP_->getRowMap();
  const auto colMap = overlapP_->getColMap();
  auto offsetOf = [&](GO row, GO col) {
    const LO lr = rowMap->getLocalElement(row), lc = colMap->getLocalElement(col);
    size_t off = rowPtr(lr);
    while (off < rowPtr(lr + 1) && entries(off) != lc) ++off;
    if (off == rowPtr(lr + 1)) throw std::logic_error("StiffnessAssembler: an entry is missing from the graph");
    return long(off);
  };
  blockOffsets_ = Kokkos::View<long*, DeviceType>("block_offsets", fields_ * blocks_.size() * nd_ * nd_);
  auto hb = Kokkos::create_mirror_view(blockOffsets_);
  Kokkos::deep_copy(hb, -1L);
  const long ndd = long(nd_) * nd_;
  forEachBlockCoupling(stateGhosted, freeX, dofs,
                       [&](long block, int rc, GO row, GO col) { hb(block * ndd + rc) = offsetOf(row, col); });
  Kokkos::deep_copy(blockOffsets_, hb);
  diagonalOffsets_ = Kokkos::View<long*, DeviceType>("diagonal_offsets", dofs.size());
  auto hd = Kokkos::create_mirror_view(diagonalOffsets_);
  for (size_t k = 0; k < dofs.size(); ++k) hd(k) = offsetOf(dofs.gids()[k], dofs.gids()[k]);
  Kokkos::deep_copy(diagonalOffsets_, hd);
  // Every pair of a node's free dofs is in the graph (a field's through the blocks around the
  // node, two fields' through forEachNodeCoupling). Only contact (several fields) adds couplings.
  if (fields_ < 2) {
    nodeOffsets_ = decltype(nodeOffsets_)();
    return;
  }
  nodeOffsets_ = decltype(nodeOffsets_)("node_offsets", dofs.size(), fields_ * Dim);
  auto hn = Kokkos::create_mirror_view(nodeOffsets_);
  const LO invalidLocal = Teuchos::OrdinalTraits<LO>::invalid();
  auto node = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), dofs.node());
  const auto ownedMap = dist_.ownedNodeMap();
  for (size_t k = 0; k < dofs.size(); ++k) {
    const GO row = dofs.gids()[k], nodeGid = ownedMap->getGlobalElement(node(k));
    for (int b = 0; b < fields_; ++b)
      for (int e = 0; e < Dim; ++e) {
        const GO col = dofs.gid(nodeGid, e, b);
        hn(k, b * Dim + e) = colMap->getLocalElement(col) != invalidLocal ? offsetOf(row, col) : -1L;
      }
  }
  Kokkos::deep_copy(nodeOffsets_, hn);
}

// values(e) = sum over the blocks k in order of K_k at e: the contributions are counted per entry,
// placed (in any order) into each entry's slots, each entry's slots sorted by position in the
// block array, and summed, all in parallel. The same sum in the same order as a sequential loop
// over the blocks adding into zeroed values.
template <int Dim>
void StiffnessAssembler<Dim>::sumBlocks(const BlockMatrices& Kb) const {
  using Exec = ExecutionSpace;
  auto values = overlapP_->getLocalMatrixDevice().values;
  const long nnz = long(values.extent(0));
  const long ndd = long(nd_) * nd_;
  const long total = long(Kb.count) * ndd;
  if (Kb.count > 0 && long(Kb.K.extent(1)) * long(Kb.K.extent(2)) != ndd)
    throw std::logic_error("StiffnessAssembler: the stiffness blocks do not match the assembler's block size");
  const BlockGrid grid = blocks_;
  auto offsets = blockOffsets_;
  auto O = Kb.origin;
  auto F = Kb.field;
  const bool multiField = F.extent(0) > 0;
  const long blockCount = grid.size();
  auto entryOf = KOKKOS_LAMBDA(long i) {
    const long k = i / ndd;
    const long b = grid.index(O(k, 0), O(k, 1), Dim == 3 ? O(k, Dim - 1) : 0);
    const long fieldShift = multiField ? F(k) * blockCount : 0L;
    return b >= 0 && b < blockCount ? offsets((b + fieldShift) * ndd + i % ndd) : -1L;
  };
  Kokkos::View<long*, DeviceType> start("entry_start", nnz + 1);
  Kokkos::parallel_for(
      "stiffness_count", Kokkos::RangePolicy<Exec>(0, total), KOKKOS_LAMBDA(long i) {
        const long e = entryOf(i);
        if (e >= 0) Kokkos::atomic_increment(&start(e + 1));
      });
  Kokkos::parallel_scan(
      "stiffness_entry_start", Kokkos::RangePolicy<Exec>(0, nnz + 1), KOKKOS_LAMBDA(long e, long& partial, bool final) {
        partial += start(e);
        if (final) start(e) = partial;
      });
  long slotCount = 0;
  Kokkos::deep_copy(slotCount, Kokkos::subview(start, nnz));
  Kokkos::View<long*, DeviceType> cursor("entry_cursor", nnz + 1), slots("entry_slots", slotCount);
  Kokkos::deep_copy(cursor, start);
  Kokkos::parallel_for(
      "stiffness_place", Kokkos::RangePolicy<Exec>(0, total), KOKKOS_LAMBDA(long i) {
        const long e = entryOf(i);
        if (e >= 0) slots(Kokkos::atomic_fetch_add(&cursor(e), 1L)) = i;
      });
  const double* K = Kb.K.data();
  Kokkos::parallel_for(
      "stiffness_sum", Kokkos::RangePolicy<Exec>(0, nnz), KOKKOS_LAMBDA(long e) {
        const long lo = start(e), hi = start(e + 1);
        for (long s = lo + 1; s < hi; ++s)  // insertion sort: a few dozen slots per entry
          for (long q = s; q > lo && slots(q - 1) > slots(q); --q) {
            const long tmp = slots(q);
            slots(q) = slots(q - 1);
            slots(q - 1) = tmp;
          }
        double sum = 0.0;
        for (long s = lo; s < hi; ++s) sum += K[slots(s)];
        values(e) = sum;
      });
}

template <int Dim>
void StiffnessAssembler<Dim>::sumBlocksSequential(const BlockMatrices& Kb) const {
  auto values = overlapP_->getLocalMatrixDevice().values;
  auto hv = Kokkos::create_mirror_view(values);
  auto O = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kb.origin);
  auto F = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kb.field);
  const bool multiField = F.extent(0) > 0;
  auto K = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), Kb.K);
  auto offsets = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), blockOffsets_);
  const long ndd = long(nd_) * nd_;
  if (Kb.count > 0 && long(Kb.K.extent(1)) * long(Kb.K.extent(2)) != ndd)
    throw std::logic_error("StiffnessAssembler: the stiffness blocks do not match the assembler's block size");
  if (!K.span_is_contiguous()) throw std::logic_error("StiffnessAssembler: the stiffness blocks are not contiguous");
  Kokkos::deep_copy(hv, 0.0);
  double* sum = hv.data();
  const double* blockValues = K.data();  // LayoutRight: block k's ndd values, row after row, at k ndd
  for (int k = 0; k < Kb.count; ++k) {
    const long b = blocks_.index(O(k, 0), O(k, 1), Dim == 3 ? O(k, Dim - 1) : 0);
    if (b < 0 || b >= blocks_.size())
      throw std::logic_error("StiffnessAssembler: a stiffness block starts outside the rank's block grid");
    const long* off = &offsets((b + (multiField ? F(k) * blocks_.size() : 0L)) * ndd);
    const double* Kk = blockValues + k * ndd;
    for (long rc = 0; rc < ndd; ++rc)
      if (off[rc] >= 0) sum[off[rc]] += Kk[rc];
  }
  Kokkos::deep_copy(values, hv);
}

template <int Dim>
void StiffnessAssembler<Dim>::fill(const BlockMatrices& blocks, const FreeDofMap<Dim>& dofs,
                                   const MultiVector* lumpedMass, int massColumn, double massFactor,
                                   const NodeCouplings* couplings) {
  using Exec = ExecutionSpace;
  const auto unknownMap = dofs.map();
  overlapP_->resumeFill();
  if (parallelFill_)
    sumBlocks(blocks);
  else
    sumBlocksSequential(blocks);
  if (lumpedMass) {
    auto values = overlapP_->getLocalMatrixDevice().values;
    auto m = lumpedMass->getLocalViewDevice(Tpetra::Access::ReadOnly);
    auto diagonal = diagonalOffsets_;
    auto node = dofs.node();
    auto field = dofs.field();
    const int stride = stride_;
    Kokkos::parallel_for(
        "stiffness_lumped_mass", Kokkos::RangePolicy<Exec>(0, diagonal.extent(0)),
        KOKKOS_LAMBDA(int k) { values(diagonal(k)) += massFactor * m(node(k), massColumn + field(k) * stride); });
  }
  if (couplings) addNodeCouplings(*couplings, dofs);
  overlapP_->fillComplete(unknownMap, unknownMap);
  P_->resumeFill();
  P_->setAllToScalar(0.0);
  P_->doExport(*overlapP_, *exporter_, Tpetra::ADD);
  P_->fillComplete(unknownMap, unknownMap);
}

// Each free dof's row gets its node's couplings: one writer per entry, so the order is fixed.
template <int Dim>
void StiffnessAssembler<Dim>::addNodeCouplings(const NodeCouplings& couplings, const FreeDofMap<Dim>& dofs) {
  auto values = overlapP_->getLocalMatrixDevice().values;
  auto offsets = nodeOffsets_;
  auto J = couplings.values;
  auto node = dofs.node();
  auto component = dofs.component();
  auto field = dofs.field();
  const double factor = couplings.factor;
  const int fields = fields_;
  Kokkos::parallel_for(
      "stiffness_node_couplings", Kokkos::RangePolicy<ExecutionSpace>(0, offsets.extent(0)), KOKKOS_LAMBDA(int k) {
        const int n = node(k), a = field(k), d = component(k);
        for (int b = 0; b < fields; ++b) {
          const double mean = J(n, 9 * fields + b);
          for (int e = 0; e < Dim; ++e) {
            const double value = J(n, 9 * a + 3 * d + e) * ((a == b ? 1.0 : 0.0) - mean);
            if (offsets(k, b * Dim + e) >= 0 && value != 0.0) values(offsets(k, b * Dim + e)) += factor * value;
          }
        }
      });
}

template <int Dim>
void StiffnessAssembler<Dim>::save(std::vector<double>& rows) const {
  if (P_.is_null()) return;
  const auto rowMap = P_->getRowMap(), colMap = P_->getColMap();
  typename CrsMatrix::local_inds_host_view_type cols;
  typename CrsMatrix::values_host_view_type values;
  for (LO r = 0; r < (LO)P_->getNodeNumRows(); ++r) {
    P_->getLocalRowView(r, cols, values);
    rows.push_back(double(rowMap->getGlobalElement(r)));
    rows.push_back(double(cols.extent(0)));
    for (size_t k = 0; k < cols.extent(0); ++k) {
      rows.push_back(double(colMap->getGlobalElement(cols(k))));
      rows.push_back(values(k));
    }
  }
}

template <int Dim>
bool StiffnessAssembler<Dim>::restore(const std::vector<double>& saved, const FreeDofMap<Dim>& dofs) {
  std::vector<GO> rowGids;
  std::vector<std::vector<GO>> cols;
  std::vector<std::vector<double>> values;
  size_t longest = 1;
  for (size_t i = 0; i < saved.size();) {
    rowGids.push_back(GO(saved[i]));
    const size_t n = size_t(saved[i + 1]);
    i += 2;
    cols.emplace_back(n);
    values.emplace_back(n);
    for (size_t k = 0; k < n; ++k, i += 2) {
      cols.back()[k] = GO(saved[i]);
      values.back()[k] = saved[i + 1];
    }
    longest = std::max(longest, n);
  }
  const int sameHere = rowGids == dofs.gids() ? 1 : 0;
  int same = 0;
  Teuchos::reduceAll(*dist_.comm(), Teuchos::REDUCE_MIN, sameHere, Teuchos::outArg(same));
  if (!same) return false;
  P_ = Teuchos::rcp(new CrsMatrix(dofs.map(), longest));
  for (size_t r = 0; r < rowGids.size(); ++r)
    P_->insertGlobalValues(rowGids[r], Teuchos::ArrayView<const GO>(cols[r]),
                           Teuchos::ArrayView<const double>(values[r]));
  P_->fillComplete(dofs.map(), dofs.map());
  patternKey_.clear();
  return true;
}

template class StiffnessAssembler<2>;
template class StiffnessAssembler<3>;

}  // namespace impm
