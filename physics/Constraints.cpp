#include "physics/Constraints.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace impm {

std::vector<NodeIndex> faceNodes(const StructuredGrid& g, const RectangularBody& body, const std::string& face) {
  if (face.size() != 2 || (face[1] != '-' && face[1] != '+') || face[0] < 'x' || face[0] >= 'x' + g.dim)
    throw std::invalid_argument("unknown face '" + face + "'");
  const int normal = face[0] - 'x';
  const bool high = face[1] == '+';
  auto index = [&](int d, double c) { return (int)std::lround((c - g.origin(d)) / g.spacing(d)); };
  int lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
  for (int d = 0; d < g.dim; ++d) {
    lo[d] = index(d, body.lo(d));
    hi[d] = index(d, body.hi(d));
  }
  lo[normal] = hi[normal] = high ? hi[normal] : lo[normal];
  std::vector<NodeIndex> nodes;
  for (int i = lo[0]; i <= hi[0]; ++i)
    for (int j = lo[1]; j <= hi[1]; ++j)
      for (int k = lo[2]; k <= hi[2]; ++k) nodes.push_back({i, j, k});
  return nodes;
}

std::vector<NodeIndex> boxNodes(const StructuredGrid& g, double xMin, double xMax, double yMin, double yMax,
                                double zMin, double zMax) {
  const double lo[3] = {xMin, yMin, zMin}, hi[3] = {xMax, yMax, zMax};
  int first[3] = {0, 0, 0}, last[3] = {0, 0, 0};
  for (int d = 0; d < g.dim; ++d) {
    const double h = g.spacing(d), t = 1e-9 * h;
    // Clamped in double before the conversion: the 3D default box (+-1e300 in z) overflows an int.
    const double cells = g.cells(d);
    first[d] = (int)std::min(cells + 1.0, std::max(0.0, std::ceil((lo[d] - t - g.origin(d)) / h)));
    last[d] = (int)std::max(-1.0, std::min(cells, std::floor((hi[d] + t - g.origin(d)) / h)));
  }
  std::vector<NodeIndex> nodes;
  for (int i = first[0]; i <= last[0]; ++i)
    for (int j = first[1]; j <= last[1]; ++j)
      for (int k = first[2]; k <= last[2]; ++k) nodes.push_back({i, j, k});
  return nodes;
}

std::vector<NodeIndex> constraintNodes(const ConstraintSpec& s, const StructuredGrid& g) {
  if (s.where == "Face") return faceNodes(g, s.body, s.face);
  if (s.where == "Box") return boxNodes(g, s.xMin, s.xMax, s.yMin, s.yMax, s.zMin, s.zMax);
  return {{(int)std::lround((s.x - g.x0) / g.hx), (int)std::lround((s.y - g.y0) / g.hy),
           g.dim == 3 ? (int)std::lround((s.z - g.z0) / g.hz) : 0}};
}

}  // namespace impm
