#include "core/ParticleMigration.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <stdexcept>
#include <string>
#include <vector>

namespace impm {

namespace {
// Destination of each particle: 0 stays, -1 left neighbour, +1 right neighbour, 2 too far.
enum : int { Stay = 0, Left = -1, Right = 1, TooFar = 2 };
}  // namespace

long long migrateParticles(ParticleSet& ps, const GridDistribution& dist) {
  const auto& comm = *dist.comm();
  if (comm.getSize() == 1 || ps.fixedPositions()) return 0;
  const StructuredGrid g = dist.grid();
  const int rank = comm.getRank(), nranks = comm.getSize();
  const int begin = dist.cellColumnBegin(), end = dist.cellColumnEnd();
  // The neighbours' slabs (balanced slabs, as GridDistribution makes them).
  const int base = g.nx / nranks, extra = g.nx % nranks;
  auto slabBegin = [&](int r) { return r * base + std::min(r, extra); };
  const int leftBegin = rank > 0 ? slabBegin(rank - 1) : begin;
  const int rightEnd = rank < nranks - 1 ? slabBegin(rank + 1) + base + (rank + 1 < extra ? 1 : 0) : end;

  // Destination of particle p from its cell column c.
  auto destinationOf = [=](int c) {
    if (c < begin) return c >= leftBegin ? int(Left) : int(TooFar);
    if (c >= end) return c < rightEnd ? int(Right) : int(TooFar);
    return int(Stay);
  };
  // Every step: a count only (no allocation); the lists are built on the rare steps that need them.
  auto x = ps.x;
  int leaving = 0;
  Kokkos::parallel_reduce(
      "migration_count", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, int& count) {
        const int c = cellColumnOf(g, x(p, 0));
        count += (c < begin || c >= end) ? 1 : 0;
      },
      leaving);
  long long moved = 0, local = leaving;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, local, Teuchos::outArg(moved));
  if (moved == 0) return 0;

  auto xh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  std::vector<int> stay, toLeft, toRight;
  int tooFar = 0;
  for (int p = 0; p < ps.count; ++p) {
    const int d = destinationOf(cellColumnOf(g, xh(p, 0)));
    if (d == Stay) stay.push_back(p);
    else if (d == Left) toLeft.push_back(p);
    else if (d == Right) toRight.push_back(p);
    else ++tooFar;
  }
  int anyTooFar = 0;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, tooFar, Teuchos::outArg(anyTooFar));
  if (anyTooFar > 0)
    throw std::runtime_error("particles moved beyond the neighbouring rank's cell columns in one step (use fewer ranks or "
                             "a smaller time step)");

  const int width = ps.packedWidth();
  auto packRows = [&](const std::vector<int>& list) {
    ParticleSet::Ids idx("migration_indices", list.size());
    auto ih = Kokkos::create_mirror_view(idx);
    for (size_t k = 0; k < list.size(); ++k) ih(k) = list[k];
    Kokkos::deep_copy(idx, ih);
    ParticleSet::Packed rows("migration_rows", list.size(), width);
    ps.pack(idx, rows);
    return rows;
  };
  const ParticleSet::Packed kept = packRows(stay), sendLeft = packRows(toLeft), sendRight = packRows(toRight);

  // Counts first, then rows, with each neighbour (receives posted before the sends).
  using Teuchos::ArrayRCP;
  using Request = Teuchos::RCP<Teuchos::CommRequest<int>>;
  const int leftRank = rank - 1, rightRank = rank + 1;
  auto exchange = [&](const ArrayRCP<double>& toL, const ArrayRCP<double>& toR, ArrayRCP<double>& fromL,
                      ArrayRCP<double>& fromR, int tag) {
    std::vector<Request> requests;
    if (leftRank >= 0) requests.push_back(Teuchos::ireceive<int, double>(fromL, leftRank, tag, comm));
    if (rightRank < nranks) requests.push_back(Teuchos::ireceive<int, double>(fromR, rightRank, tag, comm));
    if (leftRank >= 0) requests.push_back(Teuchos::isend<int, double>(toL.getConst(), leftRank, tag, comm));
    if (rightRank < nranks) requests.push_back(Teuchos::isend<int, double>(toR.getConst(), rightRank, tag, comm));
    Teuchos::waitAll(comm, Teuchos::arrayViewFromVector(requests));
  };
  ArrayRCP<double> countL(1, (double)toLeft.size()), countR(1, (double)toRight.size());
  ArrayRCP<double> fromLCount(1, 0.0), fromRCount(1, 0.0);
  exchange(countL, countR, fromLCount, fromRCount, 4201);

  auto toHostRows = [&](const ParticleSet::Packed& rows) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), rows);
    ArrayRCP<double> buf(std::max<size_t>(1, rows.extent(0) * width), 0.0);
    for (size_t k = 0; k < rows.extent(0); ++k)
      for (int c = 0; c < width; ++c) buf[k * width + c] = h(k, c);
    return buf;
  };
  const int nFromL = (int)fromLCount[0], nFromR = (int)fromRCount[0];
  ArrayRCP<double> fromL(std::max(1, nFromL * width), 0.0), fromR(std::max(1, nFromR * width), 0.0);
  ArrayRCP<double> bufL = toHostRows(sendLeft), bufR = toHostRows(sendRight);
  // Zero-length messages still travel as one padding value, so that every posted receive matches a send.
  exchange(bufL, bufR, fromL, fromR, 4202);

  auto rowsOf = [&](const ArrayRCP<double>& buf, int n) {
    ParticleSet::Packed rows("migration_received", n, width);
    auto h = Kokkos::create_mirror_view(rows);
    for (int k = 0; k < n; ++k)
      for (int c = 0; c < width; ++c) h(k, c) = buf[k * width + c];
    Kokkos::deep_copy(rows, h);
    return rows;
  };
  ParticleSet next(0, ps.dim);
  if (ps.hasHistory()) next.allocateHistory();  // J2's b_e and alpha travel with their particles
  next.unpackAppend(kept);
  next.unpackAppend(rowsOf(fromL, nFromL));
  next.unpackAppend(rowsOf(fromR, nFromR));
  ps = next;
  return moved;
}

}  // namespace impm
