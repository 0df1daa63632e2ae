#include "physics/BodyShapes.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <stdexcept>
#include <utility>

namespace impm {

namespace {

const double kPi = std::acos(-1.0);

// A number for a message: enough digits to tell values apart, none of the %.17g noise.
std::string num(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.10g", v);
  return buf;
}

std::string point(double x, double y) { return "(" + num(x) + ", " + num(y) + ")"; }

std::string trim(const std::string& s) {
  const size_t b = s.find_first_not_of(" \t\r\n");
  if (b == std::string::npos) return "";
  const size_t e = s.find_last_not_of(" \t\r\n");
  return s.substr(b, e - b + 1);
}

std::vector<std::string> split(const std::string& s, char sep) {
  std::vector<std::string> parts;
  size_t start = 0;
  for (;;) {
    const size_t end = s.find(sep, start);
    parts.push_back(trim(s.substr(start, end == std::string::npos ? std::string::npos : end - start)));
    if (end == std::string::npos) return parts;
    start = end + 1;
  }
}

// The whole (trimmed) field must be a number; strtod reads %.17g back bit-exactly.
bool parseNumber(const std::string& field, double& value) {
  if (field.empty()) return false;
  errno = 0;
  char* end = nullptr;
  value = std::strtod(field.c_str(), &end);
  // ERANGE on underflow still gives the nearest subnormal or zero, a valid read.
  return end == field.c_str() + field.size() && !(errno == ERANGE && std::isinf(value));
}

bool finite(double v) { return std::isfinite(v); }

class Rectangle : public BodyShape {
 public:
  Rectangle(double xMin, double xMax, double yMin, double yMax) : xMin_(xMin), xMax_(xMax), yMin_(yMin), yMax_(yMax) {
    if (!finite(xMin) || !finite(xMax) || !finite(yMin) || !finite(yMax))
      throw std::invalid_argument("rectangle bounds must be finite, got " + describe());
    if (!(xMin < xMax) || !(yMin < yMax))
      throw std::invalid_argument("rectangle needs xMin < xMax and yMin < yMax, got " + describe());
  }
  bool contains(double x, double y) const override { return x >= xMin_ && x <= xMax_ && y >= yMin_ && y <= yMax_; }
  double area() const override { return (xMax_ - xMin_) * (yMax_ - yMin_); }
  void boundingBox(double& xlo, double& xhi, double& ylo, double& yhi) const override {
    xlo = xMin_, xhi = xMax_, ylo = yMin_, yhi = yMax_;
  }
  std::string describe() const override {
    return "rectangle x [" + num(xMin_) + ", " + num(xMax_) + "], y [" + num(yMin_) + ", " + num(yMax_) + "]";
  }

 private:
  double xMin_, xMax_, yMin_, yMax_;
};

class Ellipse : public BodyShape {
 public:
  Ellipse(double cx, double cy, double a, double b, double ai, double bi)
      : cx_(cx), cy_(cy), a_(a), b_(b), ai_(ai), bi_(bi) {
    if (!finite(cx) || !finite(cy)) throw std::invalid_argument("ellipse centre must be finite, got " + point(cx, cy));
    if (!(a > 0) || !(b > 0) || !finite(a) || !finite(b))
      throw std::invalid_argument("ellipse semi-axes must be positive and finite, got a = " + num(a) +
                                  ", b = " + num(b));
    // A hole needs both inner semi-axes, inside the outer ones (a ring of positive width).
    const bool hole = ai != 0.0 || bi != 0.0;
    if (hole && !(ai > 0 && bi > 0 && ai < a && bi < b))
      throw std::invalid_argument("ring inner semi-axes must be positive and below the outer ones (" + num(a) + ", " +
                                  num(b) + "), got " + num(ai) + ", " + num(bi));
  }
  bool contains(double x, double y) const override {
    const double u = (x - cx_) / a_, v = (y - cy_) / b_;
    if (u * u + v * v > 1.0) return false;
    if (ai_ == 0.0) return true;
    const double ui = (x - cx_) / ai_, vi = (y - cy_) / bi_;
    return ui * ui + vi * vi >= 1.0;
  }
  double area() const override { return kPi * (a_ * b_ - ai_ * bi_); }
  void boundingBox(double& xlo, double& xhi, double& ylo, double& yhi) const override {
    xlo = cx_ - a_, xhi = cx_ + a_, ylo = cy_ - b_, yhi = cy_ + b_;
  }
  std::string describe() const override {
    const std::string outer = "centre " + point(cx_, cy_) + ", semi-axes " + num(a_) + " x " + num(b_);
    return ai_ == 0.0 ? "ellipse " + outer : "ring " + outer + ", inner " + num(ai_) + " x " + num(bi_);
  }

 private:
  double cx_, cy_, a_, b_, ai_, bi_;
};

using Vertex = std::array<double, 2>;

// Twice the signed area of the triangle (p, q, r): > 0 when r is left of p -> q.
double orient(const Vertex& p, const Vertex& q, const Vertex& r) {
  return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0]);
}

// r, collinear with p and q, lies on the segment p-q.
bool onSegment(const Vertex& p, const Vertex& q, const Vertex& r) {
  return std::min(p[0], q[0]) <= r[0] && r[0] <= std::max(p[0], q[0]) && std::min(p[1], q[1]) <= r[1] &&
         r[1] <= std::max(p[1], q[1]);
}

// Closed segments p1-p2 and q1-q2 share at least one point (crossing or touching).
bool segmentsIntersect(const Vertex& p1, const Vertex& p2, const Vertex& q1, const Vertex& q2) {
  const double d1 = orient(q1, q2, p1), d2 = orient(q1, q2, p2);
  const double d3 = orient(p1, p2, q1), d4 = orient(p1, p2, q2);
  if (((d1 > 0 && d2 < 0) || (d1 < 0 && d2 > 0)) && ((d3 > 0 && d4 < 0) || (d3 < 0 && d4 > 0))) return true;
  return (d1 == 0 && onSegment(q1, q2, p1)) || (d2 == 0 && onSegment(q1, q2, p2)) ||
         (d3 == 0 && onSegment(p1, p2, q1)) || (d4 == 0 && onSegment(p1, p2, q2));
}

class Polygon : public BodyShape {
 public:
  explicit Polygon(std::vector<Vertex> v) : v_(std::move(v)) {
    const size_t n = v_.size();
    if (n < 3) throw std::invalid_argument("polygon needs at least 3 vertices, got " + std::to_string(n));
    for (size_t i = 0; i < n; ++i)
      if (!finite(v_[i][0]) || !finite(v_[i][1]))
        throw std::invalid_argument("polygon vertex " + std::to_string(i + 1) +
                                    " is not finite: " + point(v_[i][0], v_[i][1]));
    for (size_t i = 0; i < n; ++i) {
      const size_t j = (i + 1) % n;
      if (v_[i] == v_[j])
        throw std::invalid_argument("polygon vertices " + label(i) + " and " + label(j) + " repeat " +
                                    point(v_[i][0], v_[i][1]) +
                                    (j == 0 ? " (do not close the polygon by repeating the first vertex)" : ""));
    }

    // Before the area, since a self-crossing polygon (a bow-tie) can have zero signed area. An
    // edge folding back onto its neighbour is caught here too (its end touches the edge after
    // next) or, in a triangle, by the zero area.
    for (size_t i = 0; i < n; ++i)
      for (size_t j = i + 2; j < n; ++j) {
        if (i == 0 && j == n - 1) continue;  // the closing edge is adjacent to the first
        if (segmentsIntersect(v_[i], v_[(i + 1) % n], v_[j], v_[(j + 1) % n]))
          throw std::invalid_argument("polygon edges " + edge(i) + " and " + edge(j) + " cross or touch");
      }

    xlo_ = xhi_ = v_[0][0], ylo_ = yhi_ = v_[0][1];
    double twiceSigned = 0;  // shoelace
    for (size_t i = 0; i < n; ++i) {
      const Vertex &p = v_[i], &q = v_[(i + 1) % n];
      twiceSigned += p[0] * q[1] - q[0] * p[1];
      xlo_ = std::min(xlo_, p[0]), xhi_ = std::max(xhi_, p[0]);
      ylo_ = std::min(ylo_, p[1]), yhi_ = std::max(yhi_, p[1]);
    }
    area_ = 0.5 * std::abs(twiceSigned);
    // Relative to the extent, so that units do not matter; collinear vertices give rounding only.
    const double extent = std::max(xhi_ - xlo_, yhi_ - ylo_);
    if (!(area_ > 1e-13 * extent * extent))
      throw std::invalid_argument("polygon area is zero (collinear vertices?): " + describe());
  }

  // Even-odd ray casting towards +x. Each edge is taken lower end first, so that the crossing
  // abscissa, and hence the answer, does not depend on the polygon's orientation bit for bit.
  bool contains(double x, double y) const override {
    bool inside = false;
    const size_t n = v_.size();
    for (size_t i = 0; i < n; ++i) {
      Vertex p = v_[i], q = v_[(i + 1) % n];
      if (p[1] > q[1]) std::swap(p, q);
      if (p[1] <= y && y < q[1]) {  // half-open, so a vertex at height y is counted once
        const double xCross = p[0] + (y - p[1]) * (q[0] - p[0]) / (q[1] - p[1]);
        if (x < xCross) inside = !inside;
      }
    }
    return inside;
  }
  double area() const override { return area_; }
  void boundingBox(double& xlo, double& xhi, double& ylo, double& yhi) const override {
    xlo = xlo_, xhi = xhi_, ylo = ylo_, yhi = yhi_;
  }
  std::string describe() const override {
    std::string s = "polygon of " + std::to_string(v_.size()) + " vertices";
    for (size_t i = 0; i < v_.size() && i < 8; ++i) s += (i ? " " : ": ") + point(v_[i][0], v_[i][1]);
    return v_.size() > 8 ? s + " ..." : s;
  }

 private:
  std::string label(size_t i) const { return std::to_string(i + 1); }
  std::string edge(size_t i) const { return label(i) + "-" + label((i + 1) % v_.size()); }

  std::vector<Vertex> v_;
  double area_ = 0, xlo_ = 0, xhi_ = 0, ylo_ = 0, yhi_ = 0;
};

}  // namespace

std::unique_ptr<BodyShape> makeRectangle(double xMin, double xMax, double yMin, double yMax) {
  return std::make_unique<Rectangle>(xMin, xMax, yMin, yMax);
}

std::unique_ptr<BodyShape> makeEllipse(double cx, double cy, double a, double b, double innerA, double innerB) {
  return std::make_unique<Ellipse>(cx, cy, a, b, innerA, innerB);
}

std::unique_ptr<BodyShape> makePolygon(const std::vector<std::array<double, 2>>& vertices) {
  return std::make_unique<Polygon>(vertices);
}

std::vector<std::array<double, 2>> parsePolygonVertices(const std::string& text) {
  std::vector<std::string> items = split(text, ';');
  if (items.size() > 1 && items.back().empty()) items.pop_back();  // trailing ';'
  std::vector<std::array<double, 2>> vertices;
  for (size_t k = 0; k < items.size(); ++k) {
    const std::string& item = items[k];
    std::vector<std::string> coords;
    if (item.find(',') != std::string::npos) {
      coords = split(item, ',');
    } else {
      const size_t gap = item.find_first_of(" \t");
      coords.push_back(trim(item.substr(0, gap)));
      if (gap != std::string::npos) coords.push_back(trim(item.substr(gap)));
    }
    std::array<double, 2> v{};
    if (coords.size() != 2 || !parseNumber(coords[0], v[0]) || !parseNumber(coords[1], v[1]) || !finite(v[0]) ||
        !finite(v[1]))
      throw std::invalid_argument("polygon vertex " + std::to_string(k + 1) + " '" + item +
                                  "' is not two numbers x, y (vertices are separated by ';')");
    vertices.push_back(v);
  }
  return vertices;
}

std::vector<ParticlePoint> fillShape(const BodyShape& shape, const GridBox& g, int ppx, int ppy, double thickness,
                                     int colBegin, int colEnd, bool scaleToExactArea, LatticePoints points) {
  if (!(g.hx > 0) || !(g.hy > 0) || g.nx < 1 || g.ny < 1)
    throw std::invalid_argument("grid needs positive cell sizes and counts, got hx = " + num(g.hx) + ", hy = " +
                                num(g.hy) + ", nx = " + std::to_string(g.nx) + ", ny = " + std::to_string(g.ny));
  if (ppx < 1 || ppy < 1)
    throw std::invalid_argument("particles per cell must be at least 1, got " + std::to_string(ppx) + " x " +
                                std::to_string(ppy));
  if (!(thickness > 0) || !finite(thickness))
    throw std::invalid_argument("thickness must be positive, got " + num(thickness));
  if (colBegin < 0 || colEnd > g.nx || colBegin > colEnd)
    throw std::invalid_argument("cell columns [" + std::to_string(colBegin) + ", " + std::to_string(colEnd) +
                                ") are not within [0, " + std::to_string(g.nx) + "]");

  // A shape sticking out of the grid would lose particles, and the scaling would pile their
  // volume onto the others.
  double xlo, xhi, ylo, yhi;
  shape.boundingBox(xlo, xhi, ylo, yhi);
  const double gxHi = g.x0 + g.nx * g.hx, gyHi = g.y0 + g.ny * g.hy;
  const double tolX = 1e-9 * g.hx, tolY = 1e-9 * g.hy;
  if (xlo < g.x0 - tolX || xhi > gxHi + tolX || ylo < g.y0 - tolY || yhi > gyHi + tolY)
    throw std::invalid_argument(shape.describe() + " extends beyond the grid: bounding box x [" + num(xlo) + ", " +
                                num(xhi) + "], y [" + num(ylo) + ", " + num(yhi) + "], grid x [" + num(g.x0) + ", " +
                                num(gxHi) + "], y [" + num(g.y0) + ", " + num(gyHi) + "]");

  // Only cells meeting the bounding box can hold a centre inside; one cell of margin so that
  // rounding in the index never drops one.
  auto cellRange = [](double lo, double hi, double origin, double h, int n, int& begin, int& end) {
    begin = std::max(0, (int)std::floor((lo - origin) / h) - 1);
    end = std::min(n, (int)std::floor((hi - origin) / h) + 2);
  };
  int i0, i1, j0, j1;
  cellRange(xlo, xhi, g.x0, g.hx, g.nx, i0, i1);
  cellRange(ylo, yhi, g.y0, g.hy, g.ny, j0, j1);

  const std::vector<double> ox = latticeOffsets(points, ppx), oy = latticeOffsets(points, ppy);
  const double dx = g.hx / ppx, dy = g.hy / ppy;
  // Node positions as StructuredGrid::nodeX/nodeY compute them, so that a rectangle on grid lines
  // gets bit for bit the particles of the rectangle-only lattice this fill replaces.
  auto forEachInside = [&](int iBegin, int iEnd, auto&& visit) {
    for (int i = iBegin; i < iEnd; ++i)
      for (int j = j0; j < j1; ++j)
        for (int a = 0; a < ppx; ++a)
          for (int b = 0; b < ppy; ++b) {
            const double x = (g.x0 + i * g.hx) + ox[a] * dx, y = (g.y0 + j * g.hy) + oy[b] * dy;
            if (shape.contains(x, y)) visit(x, y);
          }
  };

  // Count over the whole grid, so that every rank computes the same factor.
  long long total = 0;
  forEachInside(i0, i1, [&](double, double) { ++total; });
  if (total == 0)
    throw std::invalid_argument(shape.describe() + " contains no particle of the " + std::to_string(ppx) + " x " +
                                std::to_string(ppy) + " per cell lattice: refine the grid or the particles per cell");
  double factor = 1.0;
  if (scaleToExactArea) {
    factor = shape.area() / ((double)total * dx * dy);
    if (std::abs(factor - 1.0) <= 1e-12) factor = 1.0;
  }
  const double volume = dx * dy * thickness * factor;

  std::vector<ParticlePoint> kept;
  forEachInside(std::max(i0, colBegin), std::min(i1, colEnd), [&](double x, double y) {
    ParticlePoint p;
    p.x = x, p.y = y, p.lx = 0.5 * dx, p.ly = 0.5 * dy, p.volume = volume;
    kept.push_back(p);
  });
  return kept;
}

std::vector<ParticlePoint> readParticlesFile(const std::string& path, int dim, double thickness) {
  const std::string where = "particles file '" + path + "'";
  if (dim != 2 && dim != 3)
    throw std::invalid_argument(where + ": dimension must be 2 or 3, got " + std::to_string(dim));
  if (dim == 2 && (!(thickness > 0) || !finite(thickness)))
    throw std::invalid_argument(where + ": thickness must be positive, got " + num(thickness));
  std::ifstream in(path);
  if (!in) throw std::invalid_argument(where + ": cannot be opened");

  const char* columns = dim == 2 ? "(x, y, volume)" : "(x, y, z, volume)";
  const char* names[] = {"x", "y", dim == 2 ? "volume" : "z", "volume"};
  std::vector<ParticlePoint> points;
  std::string line;
  bool firstContent = true;
  for (int lineNo = 1; std::getline(in, line); ++lineNo) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    const std::vector<std::string> fields = split(line, ',');
    std::vector<double> values(fields.size());
    bool anyNumber = false;
    for (size_t k = 0; k < fields.size(); ++k) anyNumber = parseNumber(fields[k], values[k]) || anyNumber;
    const bool header = firstContent && !anyNumber;
    firstContent = false;
    if (header) continue;

    const std::string at = where + ", line " + std::to_string(lineNo) + ": ";
    if ((int)fields.size() != dim + 1)
      throw std::invalid_argument(at + "expected " + std::to_string(dim + 1) + " columns " + columns + ", got " +
                                  std::to_string(fields.size()));
    for (int k = 0; k <= dim; ++k)
      if (!parseNumber(fields[k], values[k]) || !finite(values[k]))
        throw std::invalid_argument(at + "column " + std::to_string(k + 1) + " (" + names[k] + ") '" + fields[k] +
                                    "' is not a finite number");
    ParticlePoint p;
    p.x = values[0], p.y = values[1];
    p.volume = values[dim];
    if (!(p.volume > 0)) throw std::invalid_argument(at + "volume must be positive, got " + fields[dim]);
    if (dim == 2) {
      p.lx = p.ly = 0.5 * std::sqrt(p.volume / thickness);  // square of the particle's own area
    } else {
      p.z = values[2];
      p.lx = p.ly = p.lz = 0.5 * std::cbrt(p.volume);  // cube of its own volume
    }
    points.push_back(p);
  }
  if (in.bad()) throw std::invalid_argument(where + ": read error");
  if (points.empty()) throw std::invalid_argument(where + ": no particles");
  return points;
}

void writeParticlesFile(const std::string& path, const std::vector<ParticlePoint>& points, int dim) {
  if (dim != 2 && dim != 3)
    throw std::invalid_argument("particles file dimension must be 2 or 3, got " + std::to_string(dim));
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (!f) throw std::runtime_error("particles file '" + path + "': cannot be opened for writing");
  std::fputs(dim == 2 ? "x,y,volume\n" : "x,y,z,volume\n", f);
  for (const ParticlePoint& p : points) {
    if (dim == 2)
      std::fprintf(f, "%.17g,%.17g,%.17g\n", p.x, p.y, p.volume);
    else
      std::fprintf(f, "%.17g,%.17g,%.17g,%.17g\n", p.x, p.y, p.z, p.volume);
  }
  const bool failed = std::ferror(f) != 0;
  if (std::fclose(f) != 0 || failed) throw std::runtime_error("particles file '" + path + "': write failed");
}

}  // namespace impm
