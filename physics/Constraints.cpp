#include "physics/Constraints.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace impm {

std::vector<std::pair<int, int>> faceNodes(const StructuredGrid& g, const RectangularBody& body, const std::string& face) {
  auto col = [&](double x) { return (int)std::lround((x - g.x0) / g.hx); };
  auto row = [&](double y) { return (int)std::lround((y - g.y0) / g.hy); };
  std::vector<std::pair<int, int>> nodes;
  if (face == "x-" || face == "x+") {
    const int i = col(face == "x-" ? body.xMin : body.xMax);
    for (int j = row(body.yMin); j <= row(body.yMax); ++j) nodes.emplace_back(i, j);
  } else if (face == "y-" || face == "y+") {
    const int j = row(face == "y-" ? body.yMin : body.yMax);
    for (int i = col(body.xMin); i <= col(body.xMax); ++i) nodes.emplace_back(i, j);
  } else {
    throw std::invalid_argument("unknown face '" + face + "'");
  }
  return nodes;
}

std::vector<std::pair<int, int>> boxNodes(const StructuredGrid& g, double xMin, double xMax, double yMin, double yMax) {
  const double tx = 1e-9 * g.hx, ty = 1e-9 * g.hy;
  const int i0 = std::max(0, (int)std::ceil((xMin - tx - g.x0) / g.hx)), i1 = std::min(g.nx, (int)std::floor((xMax + tx - g.x0) / g.hx));
  const int j0 = std::max(0, (int)std::ceil((yMin - ty - g.y0) / g.hy)), j1 = std::min(g.ny, (int)std::floor((yMax + ty - g.y0) / g.hy));
  std::vector<std::pair<int, int>> nodes;
  for (int i = i0; i <= i1; ++i)
    for (int j = j0; j <= j1; ++j) nodes.emplace_back(i, j);
  return nodes;
}

NodalConstraints::NodalConstraints(const std::vector<ConstraintSpec>& specs, const GridDistribution& dist) {
  const StructuredGrid& g = dist.grid();
  const LocalNodeIndexer& owned = dist.ownedIndexer();
  std::vector<int> nodes, comps;
  for (const auto& s : specs) {
    std::vector<std::pair<int, int>> ij;
    if (s.where == "Face") ij = faceNodes(g, s.body, s.face);
    else if (s.where == "Box") ij = boxNodes(g, s.xMin, s.xMax, s.yMin, s.yMax);
    else ij.emplace_back((int)std::lround((s.x - g.x0) / g.hx), (int)std::lround((s.y - g.y0) / g.hy));
    for (auto [i, j] : ij) {
      if (!owned.contains(i, j)) continue;
      if (s.fixX) { nodes.push_back(owned(i, j)); comps.push_back(0); }
      if (s.fixY) { nodes.push_back(owned(i, j)); comps.push_back(1); }
    }
  }
  node_ = Kokkos::View<int*, DeviceType>("constraint_nodes", nodes.size());
  comp_ = Kokkos::View<int*, DeviceType>("constraint_components", comps.size());
  auto hn = Kokkos::create_mirror_view(node_); auto hc = Kokkos::create_mirror_view(comp_);
  for (size_t k = 0; k < nodes.size(); ++k) { hn(k) = nodes[k]; hc(k) = comps[k]; }
  Kokkos::deep_copy(node_, hn); Kokkos::deep_copy(comp_, hc);
}

}  // namespace impm
