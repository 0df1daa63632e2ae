#include "core/ParticleMigration.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Tpetra_Distributor.hpp>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

namespace impm {

namespace {
// The particles' cell box on this rank, widened by `slack` cells, as plain values for kernels.
struct CellBox {
  int lo[3], hi[3];
  KOKKOS_INLINE_FUNCTION bool contains(const int c[3]) const {
    return c[0] >= lo[0] && c[0] < hi[0] && c[1] >= lo[1] && c[1] < hi[1] && c[2] >= lo[2] && c[2] < hi[2];
  }
};
// The rows of the particles `list` (host indices), packed on the device.
ParticleSet::Packed packList(const ParticleSet& ps, const std::vector<int>& list) {
  ParticleSet::Ids idx("migration_indices", list.size());
  auto ih = Kokkos::create_mirror_view(idx);
  for (size_t k = 0; k < list.size(); ++k) ih(k) = list[k];
  Kokkos::deep_copy(idx, ih);
  ParticleSet::Packed rows("migration_rows", list.size(), ps.packedWidth());
  ps.pack(idx, rows);
  return rows;
}

// `n` rows of `width` values from a host buffer (received), on the device.
ParticleSet::Packed rowsFromHost(const double* buffer, size_t n, int width) {
  ParticleSet::Packed rows("migration_received", n, width);
  auto h = Kokkos::create_mirror_view(rows);
  for (size_t k = 0; k < n; ++k)
    for (int c = 0; c < width; ++c) h(k, c) = buffer[k * width + c];
  Kokkos::deep_copy(rows, h);
  return rows;
}
}  // namespace

namespace {

// Particles outside `box` on this rank: a count only (no allocation), run every step.
int countOutside(const ParticleSet& ps, const StructuredGrid& g, const CellBox& box) {
  auto x = ps.x;
  const int nd = g.dim;
  int outside = 0;
  Kokkos::parallel_reduce(
      "migration_count", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count),
      KOKKOS_LAMBDA(int p, int& count) {
        int c[3] = {0, 0, 0};
        for (int d = 0; d < nd; ++d) c[d] = cellIndexOf(g, d, x(p, d));
        count += box.contains(c) ? 0 : 1;
      },
      outside);
  return outside;
}

// Who stays (in the rank's own box) and who leaves for which neighbour (slot in `neighbours`, the
// owner of the particle's cell). Collective: throws on every rank when a particle went beyond
// the neighbours' cells.
struct Departures {
  std::vector<int> stay;
  std::vector<std::vector<int>> leaving;
  long long count = 0;
};
Departures sortByDestination(const ParticleSet& ps, const GridDistribution& dist, const CellBox& own,
                             const std::vector<int>& neighbours) {
  const StructuredGrid g = dist.grid();
  const RankGrid& ranks = dist.rankGrid();
  auto xh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  Departures out;
  out.leaving.resize(neighbours.size());
  int tooFar = 0;
  for (int p = 0; p < ps.count; ++p) {
    int c[3] = {0, 0, 0};
    for (int d = 0; d < g.dim; ++d) c[d] = cellIndexOf(g, d, xh(p, d));
    if (own.contains(c)) {
      out.stay.push_back(p);
      continue;
    }
    const int owner = ranks.ownerOfCell(c[0], c[1], c[2]);
    const auto slot = std::lower_bound(neighbours.begin(), neighbours.end(), owner);
    if (slot == neighbours.end() || *slot != owner) {
      ++tooFar;
      continue;
    }
    out.leaving[slot - neighbours.begin()].push_back(p);
    ++out.count;
  }
  int anyTooFar = 0;
  Teuchos::reduceAll(*dist.comm(), Teuchos::REDUCE_MAX, tooFar, Teuchos::outArg(anyTooFar));
  if (anyTooFar > 0)
    throw std::runtime_error(
        "particles moved beyond the neighbouring MPI ranks' cells in one step (use fewer ranks, "
        "a smaller time step or a smaller 'Decomposition/Migration Slack Cells')");
  return out;
}

// The leaving rows to each neighbour and the arriving rows from each: counts first, then rows,
// the receives posted before the sends. Zero-length messages still travel as one padding value,
// so that every posted receive matches a send.
std::vector<ParticleSet::Packed> exchangeRows(const ParticleSet& ps, const std::vector<std::vector<int>>& leaving,
                                              const std::vector<int>& neighbours, const Teuchos::Comm<int>& comm) {
  const int nn = (int)neighbours.size(), width = ps.packedWidth();
  auto toHostRows = [&](const ParticleSet::Packed& rows) {
    auto h = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), rows);
    Teuchos::ArrayRCP<double> buf(std::max<size_t>(1, rows.extent(0) * width), 0.0);
    for (size_t k = 0; k < rows.extent(0); ++k)
      for (int c = 0; c < width; ++c) buf[k * width + c] = h(k, c);
    return buf;
  };
  using Request = Teuchos::RCP<Teuchos::CommRequest<int>>;
  auto exchange = [&](std::vector<Teuchos::ArrayRCP<double>>& out, std::vector<Teuchos::ArrayRCP<double>>& in,
                      int tag) {
    std::vector<Request> requests;
    for (int s = 0; s < nn; ++s) requests.push_back(Teuchos::ireceive<int, double>(in[s], neighbours[s], tag, comm));
    for (int s = 0; s < nn; ++s)
      requests.push_back(Teuchos::isend<int, double>(out[s].getConst(), neighbours[s], tag, comm));
    if (!requests.empty()) Teuchos::waitAll(comm, Teuchos::arrayViewFromVector(requests));
  };
  std::vector<Teuchos::ArrayRCP<double>> countsOut(nn), countsIn(nn), rowsOut(nn), rowsIn(nn);
  for (int s = 0; s < nn; ++s) {
    countsOut[s] = Teuchos::ArrayRCP<double>(1, (double)leaving[s].size());
    countsIn[s] = Teuchos::ArrayRCP<double>(1, 0.0);
  }
  exchange(countsOut, countsIn, 4201);
  for (int s = 0; s < nn; ++s) {
    rowsOut[s] = toHostRows(packList(ps, leaving[s]));
    rowsIn[s] = Teuchos::ArrayRCP<double>(std::max(1, (int)countsIn[s][0] * width), 0.0);
  }
  exchange(rowsOut, rowsIn, 4202);
  std::vector<ParticleSet::Packed> arrived;
  for (int s = 0; s < nn; ++s) arrived.push_back(rowsFromHost(rowsIn[s].getRawPtr(), (int)countsIn[s][0], width));
  return arrived;
}

}  // namespace

long long migrateParticles(ParticleSet& ps, const GridDistribution& dist, int slack) {
  const auto& comm = *dist.comm();
  if (comm.getSize() == 1 || ps.fixedPositions()) return 0;
  CellBox own{}, margin{};
  for (int d = 0; d < 3; ++d) {
    own.lo[d] = dist.cellBegin(d);
    own.hi[d] = dist.cellEnd(d);
    margin.lo[d] = own.lo[d] - slack;
    margin.hi[d] = own.hi[d] + slack;
  }
  // The lists are built on the rare steps on which some particle left its rank's margin.
  int trigger = 0;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MAX, countOutside(ps, dist.grid(), margin), Teuchos::outArg(trigger));
  if (trigger == 0) return 0;
  const std::vector<int> neighbours = dist.rankGrid().neighbours(comm.getRank());
  const Departures departures = sortByDestination(ps, dist, own, neighbours);
  const std::vector<ParticleSet::Packed> arrived = exchangeRows(ps, departures.leaving, neighbours, comm);
  // The kept particles keep their order, then the arrivals in increasing rank of their sender:
  // the order depends only on the decomposition (a restart at the same rank count is bit for bit).
  ParticleSet next(0, ps.dim);
  if (ps.hasHistory()) next.allocateHistory();  // J2's b_e and alpha travel with their particles
  if (ps.hasAffine()) next.allocateAffine();    // so does the APIC / TPIC affine velocity
  next.unpackAppend(packList(ps, departures.stay));
  for (const auto& rows : arrived) next.unpackAppend(rows);
  ps = next;
  long long moved = 0;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, departures.count, Teuchos::outArg(moved));
  return moved;
}

long long sendParticlesToOwners(ParticleSet& ps, const GridDistribution& dist) {
  const auto& comm = *dist.comm();
  if (comm.getSize() == 1) return 0;
  const StructuredGrid g = dist.grid();
  const int rank = comm.getRank(), nd = g.dim;
  auto xh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  std::vector<int> stay, leaving, destination;
  for (int p = 0; p < ps.count; ++p) {
    int c[3] = {0, 0, 0};
    for (int d = 0; d < nd; ++d) c[d] = cellIndexOf(g, d, xh(p, d));
    const int owner = dist.rankGrid().ownerOfCell(c[0], c[1], c[2]);
    if (owner == rank) {
      stay.push_back(p);
    } else {
      leaving.push_back(p);
      destination.push_back(owner);
    }
  }
  // Grouped by destination (stable), as the Distributor sends them.
  std::vector<int> order(leaving.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = (int)k;
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return destination[a] < destination[b]; });
  const int width = ps.packedWidth();
  std::vector<int> sent(order.size()), procs(order.size());
  for (size_t k = 0; k < order.size(); ++k) {
    sent[k] = leaving[order[k]];
    procs[k] = destination[order[k]];
  }
  auto rh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), packList(ps, sent));
  std::vector<double> exports(rh.data(), rh.data() + sent.size() * width);

  Tpetra::Distributor distributor(dist.comm());
  const size_t arriving = distributor.createFromSends(Teuchos::ArrayView<const int>(procs));
  std::vector<double> imports(std::max<size_t>(1, arriving * width));
  distributor.doPostsAndWaits(Teuchos::ArrayView<const double>(exports), (size_t)width,
                              Teuchos::ArrayView<double>(imports.data(), arriving * width));

  const ParticleSet::Packed kept = packList(ps, stay);
  const ParticleSet::Packed received = rowsFromHost(imports.data(), arriving, width);
  ParticleSet next(0, ps.dim);
  if (ps.hasHistory()) next.allocateHistory();
  if (ps.hasAffine()) next.allocateAffine();
  next.unpackAppend(kept);
  next.unpackAppend(received);
  ps = next;
  long long moved = 0, local = (long long)leaving.size();
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, local, Teuchos::outArg(moved));
  return moved;
}

std::array<std::vector<double>, 3> particleHistograms(const ParticleSet& ps, const StructuredGrid& g,
                                                      const Teuchos::Comm<int>& comm) {
  const int nd = g.dim;
  int n[3] = {g.nx, g.ny, nd == 3 ? g.nz : 1};
  auto xh = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  std::vector<double> local(n[0] + n[1] + n[2], 0.0), global(local.size(), 0.0);
  for (int p = 0; p < ps.count; ++p) {
    int offset = 0;
    for (int d = 0; d < 3; ++d) {
      const int c = d < nd ? cellIndexOf(g, d, xh(p, d)) : 0;
      local[offset + c] += 1.0;
      offset += n[d];
    }
  }
  Teuchos::reduceAll(comm, Teuchos::REDUCE_SUM, (int)local.size(), local.data(), global.data());
  std::array<std::vector<double>, 3> h;
  int offset = 0;
  for (int d = 0; d < 3; ++d) {
    h[d].assign(global.begin() + offset, global.begin() + offset + n[d]);
    offset += n[d];
  }
  return h;
}

}  // namespace impm
