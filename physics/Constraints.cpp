#include "physics/Constraints.hpp"

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

NodalConstraints::NodalConstraints(const std::vector<ConstraintSpec>& specs, const RectangularBody& body,
                                   const GridDistribution& dist) {
  const StructuredGrid& g = dist.grid();
  const LocalNodeIndexer& owned = dist.ownedIndexer();
  std::vector<int> nodes, comps;
  for (const auto& s : specs) {
    std::vector<std::pair<int, int>> ij;
    if (s.where == "Face") ij = faceNodes(g, body, s.face);
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
