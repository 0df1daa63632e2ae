#include "core/RankGrid.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <string>

#include "core/InputDeck.hpp"

namespace impm {

namespace {
const char* const kAxis[3] = {"X", "Y", "Z"};

// Balanced cuts: the first `cells % parts` parts one cell wider.
std::vector<int> evenCuts(int cells, int parts) {
  std::vector<int> c(parts + 1, 0);
  const int base = cells / parts, extra = cells % parts;
  for (int r = 0; r < parts; ++r) c[r + 1] = c[r] + base + (r < extra ? 1 : 0);
  return c;
}
}  // namespace

RankGrid::RankGrid(const StructuredGrid& grid, int nranks, std::array<int, 3> requested, int minCells)
    : nranks_(nranks), minCells_(std::max(1, minCells)) {
  const int nd = grid.dim == 3 ? 3 : 2;
  for (int d = 0; d < 3; ++d) cells_[d] = d < nd ? grid.cells(d) : 1;
  if (nd == 2 && requested[2] > 1)
    throw DeckError("'Decomposition/Ranks Z' = " + std::to_string(requested[2]) + " on a 2D grid; use 0 or 1");
  for (int d = 0; d < nd; ++d)
    if (requested[d] < 0)
      throw DeckError("'Decomposition/Ranks " + std::string(kAxis[d]) +
                      "' must be 0 (chosen by impm) or positive, got " + std::to_string(requested[d]));
  const bool anyRequested = requested[0] > 0 || requested[1] > 0 || requested[2] > 0;
  if (anyRequested && requested[0] > 0 && requested[1] > 0 && (nd == 2 || requested[2] > 0)) {
    const long long product = (long long)requested[0] * requested[1] * (nd == 3 ? requested[2] : 1);
    if (product != nranks)
      throw DeckError("'Decomposition/Ranks X' x 'Ranks Y'" + std::string(nd == 3 ? " x 'Ranks Z'" : "") + " = " +
                      std::to_string(product) + " but the run has " + std::to_string(nranks) + " MPI rank(s)");
  }
  // Every factorisation p_x p_y p_z = nranks that leaves each rank minCells cells per direction;
  // the one with the smallest interface (nodes on the cuts) wins, ties to more cuts across x
  // (long bars then split in x slabs).
  const long long nodes[3] = {cells_[0] + 1LL, cells_[1] + 1LL, nd == 3 ? cells_[2] + 1LL : 1LL};
  long long best = std::numeric_limits<long long>::max();
  for (int px = 1; px <= nranks; ++px) {
    if (nranks % px) continue;
    for (int py = 1; py <= nranks / px; ++py) {
      if ((nranks / px) % py) continue;
      const int pz = nranks / px / py;
      const int p[3] = {px, py, pz};
      bool ok = true;
      for (int d = 0; d < 3; ++d) {
        if (requested[d] > 0 && p[d] != requested[d]) ok = false;
        // An unsplit direction needs no width: no neighbour lies across it.
        if (d < nd ? p[d] > 1 && (long long)p[d] * minCells_ > cells_[d] : p[d] != 1) ok = false;
      }
      if (!ok) continue;
      const long long interface =
          (px - 1) * nodes[1] * nodes[2] + (py - 1) * nodes[0] * nodes[2] + (pz - 1) * nodes[0] * nodes[1];
      if (interface <= best) {  // ties go to the later: more cuts across x, then y
        best = interface;
        dims_ = {px, py, pz};
      }
    }
  }
  long long requestedProduct = 1;
  for (int d = 0; d < nd; ++d) requestedProduct *= std::max(1, requested[d]);
  if (best == std::numeric_limits<long long>::max() && anyRequested && nranks % requestedProduct != 0) {
    std::string asked;
    for (int d = 0; d < nd; ++d)
      if (requested[d] > 0)
        asked += std::string(asked.empty() ? "" : ", ") + "'Decomposition/Ranks " + kAxis[d] +
                 "' = " + std::to_string(requested[d]);
    throw DeckError(asked + " cannot split " + std::to_string(nranks) +
                    " MPI rank(s): the rank counts per direction "
                    "must multiply to the number of ranks");
  }
  if (best == std::numeric_limits<long long>::max()) {
    std::string cells =
        "'Grid/Cells X' = " + std::to_string(cells_[0]) + ", 'Grid/Cells Y' = " + std::to_string(cells_[1]);
    if (nd == 3) cells += ", 'Grid/Cells Z' = " + std::to_string(cells_[2]);
    throw DeckError(std::to_string(nranks) + " MPI ranks leave a rank without cells on this grid (" + cells +
                    (anyRequested ? ", with the requested 'Decomposition/Ranks X/Y/Z'" : "") +
                    "; each rank needs at least " + std::to_string(minCells_) +
                    " cell(s) per direction); use fewer ranks or more cells");
  }
  for (int d = 0; d < 3; ++d) cuts_[d] = evenCuts(cells_[d], dims_[d]);
}

std::array<int, 3> RankGrid::coordsOf(int rank) const {
  return {rank / (dims_[1] * dims_[2]), (rank / dims_[2]) % dims_[1], rank % dims_[2]};
}

int RankGrid::ownerOfCell(int ci, int cj, int ck) const {
  const int c[3] = {ci, cj, ck};
  std::array<int, 3> at{};
  for (int d = 0; d < 3; ++d) {
    const int cell = std::max(0, std::min(cells_[d] - 1, c[d]));
    at[d] = int(std::upper_bound(cuts_[d].begin(), cuts_[d].end(), cell) - cuts_[d].begin()) - 1;
  }
  return rankAt(at);
}

void RankGrid::cellBox(int rank, int lo[3], int hi[3]) const {
  const auto c = coordsOf(rank);
  for (int d = 0; d < 3; ++d) {
    lo[d] = cuts_[d][c[d]];
    hi[d] = cuts_[d][c[d] + 1];
  }
}

std::vector<int> RankGrid::neighbours(int rank) const {
  const auto c = coordsOf(rank);
  std::vector<int> out;
  for (int dx = -1; dx <= 1; ++dx)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dz = -1; dz <= 1; ++dz) {
        const std::array<int, 3> n{c[0] + dx, c[1] + dy, c[2] + dz};
        bool inside = true;
        for (int d = 0; d < 3; ++d) inside = inside && n[d] >= 0 && n[d] < dims_[d];
        if (inside && n != c) out.push_back(rankAt(n));
      }
  std::sort(out.begin(), out.end());
  return out;
}

void RankGrid::setCuts(int d, const std::vector<int>& cuts) {
  bool ok = (int)cuts.size() == dims_[d] + 1 && cuts.front() == 0 && cuts.back() == cells_[d];
  for (size_t r = 0; ok && r + 1 < cuts.size(); ++r) ok = cuts[r + 1] - cuts[r] >= (dims_[d] > 1 ? minCells_ : 1);
  if (!ok)
    throw std::invalid_argument("cuts along " + std::string(kAxis[d]) + " must be " + std::to_string(dims_[d] + 1) +
                                " increasing cell indices from 0 to " + std::to_string(cells_[d]) +
                                ", parts at least " + std::to_string(minCells_) + " cells wide");
  cuts_[d] = cuts;
}

std::vector<int> balancedCuts(const std::vector<double>& weights, int parts, int minCells,
                              const std::vector<int>& current) {
  const int n = (int)weights.size();
  minCells = parts > 1 ? std::max(1, minCells) : 1;
  if (parts < 1 || (long long)parts * minCells > n)
    throw std::invalid_argument("balancedCuts: " + std::to_string(parts) + " parts of at least " +
                                std::to_string(minCells) + " cells in " + std::to_string(n) + " cells");
  std::vector<double> prefix(n + 1, 0.0);
  for (int i = 0; i < n; ++i) prefix[i + 1] = prefix[i] + weights[i];
  auto sum = [&](int a, int b) { return prefix[b] - prefix[a]; };
  // Which suffixes [b, n) split into k parts, each at least minCells wide and of weight at most
  // `limit`: canFinish[k][b]. (Extending each part as far as the limit allows is not enough:
  // with a minimum width, a shorter part can be what lets a later part avoid a heavy cell.)
  // Weights are non-negative, so the parts that may start at b end in a window [b + minCells,
  // e(b)] with e non-decreasing in b, and a running count of canFinish[k - 1] answers each b.
  auto suffixSplits = [&](double limit) {
    std::vector<std::vector<char>> canFinish(parts + 1, std::vector<char>(n + 1, 0));
    canFinish[0][n] = 1;
    std::vector<int> count(n + 2, 0);
    for (int k = 1; k <= parts; ++k) {
      for (int j = 0; j <= n; ++j) count[j + 1] = count[j] + canFinish[k - 1][j];
      int e = 0;  // the furthest end with sum(b, e) <= limit
      for (int b = 0; b <= n; ++b) {
        e = std::max(e, b);
        while (e < n && sum(b, e + 1) <= limit) ++e;
        const int first = b + minCells;
        if (first <= e) canFinish[k][b] = count[e + 1] - count[first] > 0;
      }
    }
    return canFinish;
  };
  // The cuts within `limit`: each part as long as the limit allows while the rest can still be
  // split (so that, among optimal cuts, the earlier parts are the longer ones).
  auto cutsWithin = [&](double limit, std::vector<int>* cuts) {
    const auto canFinish = suffixSplits(limit);
    if (!canFinish[parts][0]) return false;
    if (!cuts) return true;
    cuts->assign(1, 0);
    int a = 0;
    for (int left = parts; left > 1; --left) {
      int b = a + minCells;
      for (int e = a + minCells; e <= n && sum(a, e) <= limit; ++e)
        if (canFinish[left - 1][e]) b = e;
      cuts->push_back(b);
      a = b;
    }
    cuts->push_back(n);
    return true;
  };
  auto largestPart = [&](const std::vector<int>& c) {
    double worst = 0;
    for (size_t r = 0; r + 1 < c.size(); ++r) worst = std::max(worst, sum(c[r], c[r + 1]));
    return worst;
  };
  // Bisection on the largest part's weight.
  double lo = 0, hi = prefix[n];
  for (int it = 0; it < 200 && hi - lo > 1e-9 * std::max(1.0, prefix[n]); ++it) {
    const double mid = 0.5 * (lo + hi);
    (cutsWithin(mid, nullptr) ? hi : lo) = mid;
  }
  std::vector<int> cuts;
  cutsWithin(hi, &cuts);
  const double optimum = largestPart(cuts);
  bool currentValid = (int)current.size() == parts + 1 && current.front() == 0 && current.back() == n;
  for (size_t r = 0; currentValid && r + 1 < current.size(); ++r)
    currentValid = current[r + 1] - current[r] >= minCells;
  if (currentValid && largestPart(current) <= optimum * (1 + 1e-12)) return current;
  return cuts;
}

}  // namespace impm
