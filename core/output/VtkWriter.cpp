#include "core/output/VtkWriter.hpp"

#include <charconv>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iomanip>
#include <stdexcept>
#include <vector>

namespace impm {

namespace {

// "%.10g" into [first, last), which holds at least 32 characters; returns the end of the text.
char* writeNumber(char* first, char* last, double value) {
  return std::to_chars(first, last, value, std::chars_format::general, 10).ptr;
}

// The file's text, built in a buffer and written out in pieces of about a megabyte.
class VtuText {
 public:
  explicit VtuText(std::ofstream& file) : file_(file), buffer_(kFlushBytes + kLongest) {}
  ~VtuText() { flush(); }
  VtuText& operator<<(const char* s) {
    const size_t n = std::strlen(s);
    if (used_ + n > buffer_.size()) flush();
    if (n > buffer_.size()) {
      file_.write(s, std::streamsize(n));
      return *this;
    }
    std::memcpy(buffer_.data() + used_, s, n);
    used_ += n;
    return *this;
  }
  VtuText& operator<<(char c) {
    room(1);
    buffer_[used_++] = c;
    return *this;
  }
  VtuText& operator<<(double value) {
    room(kNumber);
    used_ = size_t(writeNumber(buffer_.data() + used_, buffer_.data() + buffer_.size(), value) - buffer_.data());
    return *this;
  }
  VtuText& operator<<(long value) {
    room(kNumber);
    used_ = size_t(std::to_chars(buffer_.data() + used_, buffer_.data() + buffer_.size(), value).ptr - buffer_.data());
    return *this;
  }
  VtuText& operator<<(int value) { return *this << long(value); }
  // Ends a particle's line, writing the text out once it has grown past the piece size.
  void endLine() {
    *this << '\n';
    if (used_ >= kFlushBytes) flush();
  }
  void flush() {
    file_.write(buffer_.data(), std::streamsize(used_));
    used_ = 0;
  }

 private:
  static constexpr size_t kFlushBytes = size_t(1) << 20, kLongest = 4096, kNumber = 32;
  void room(size_t n) {
    if (used_ + n > buffer_.size()) flush();
  }
  std::ofstream& file_;
  std::vector<char> buffer_;
  size_t used_ = 0;
};

}  // namespace

void appendNumber(std::string& text, double value) {
  char digits[32];
  text.append(digits, writeNumber(digits, digits + sizeof digits, value));
}

void writeParticlesVtu(const std::string& path, const ParticleSet& ps) {
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto x0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x0);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto u = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.u);  // fixed particles only
  const bool fixed = ps.fixedPositions();
  auto a = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.a);
  auto s = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.stress);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
  auto V = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.volume);
  auto V0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.volume0);
  auto hist = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.history);  // J2 only
  const int n = ps.count, dim = ps.dim, ns = ps.stressCount();
  const std::string tmp = path + ".tmp";
  {
    std::ofstream file(tmp, std::ios::binary);
    if (!file) throw std::runtime_error("cannot write " + path);
    VtuText f(file);
    f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n";
    f << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) {
      f << x(p, 0) << ' ' << x(p, 1) << ' ' << (dim == 3 ? x(p, 2) : 0.0);
      f.endLine();
    }
    f << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) {
      f << p;
      f.endLine();
    }
    f << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) {
      f << p + 1;
      f.endLine();
    }
    f << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) {
      f << '1';  // VTK_VERTEX
      f.endLine();
    }
    f << "</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n";
    auto vec3 = [&](const char* name, auto get) {
      f << "<DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (int p = 0; p < n; ++p) {
        f << get(p, 0) << ' ' << get(p, 1) << ' ' << (dim == 3 ? get(p, 2) : 0.0);
        f.endLine();
      }
      f << "</DataArray>\n";
    };
    vec3("displacement", [&](int p, int d) { return fixed ? u(p, d) : x(p, d) - x0(p, d); });
    vec3("velocity", [&](int p, int d) { return v(p, d); });
    vec3("acceleration", [&](int p, int d) { return a(p, d); });
    // Stress. 3D: ParaView reads a 6-component array as the symmetric tensor XX, YY, ZZ, XY, YZ,
    // XZ, so the stored xx, yy, xy, zz, yz, xz are written in that order. 2D: xx, yy, xy, zz
    // (zz the out-of-plane stress). Each component is named.
    const int order3d[6] = {0, 1, 3, 2, 4, 5}, order2d[4] = {0, 1, 2, 3};
    const int* order = dim == 3 ? order3d : order2d;
    const char* names3d[6] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
    const char* names2d[4] = {"XX", "YY", "XY", "ZZ"};
    f << "<DataArray type=\"Float64\" Name=\"stress\" NumberOfComponents=\"" << ns << "\"";
    for (int c = 0; c < ns; ++c) f << " ComponentName" << c << "=\"" << (dim == 3 ? names3d[c] : names2d[c]) << "\"";
    f << " format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) {
      for (int c = 0; c < ns; ++c) f << (c ? " " : "") << s(p, order[c]);
      f.endLine();
    }
    auto scalars = [&](const char* name, auto get) {
      f << "</DataArray>\n<DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
      for (int p = 0; p < n; ++p) {
        f << get(p);
        f.endLine();
      }
    };
    scalars("mass", [&](int p) { return m(p); });
    scalars("volume", [&](int p) { return V(p); });
    // det F = V / V0 (1 for the FE reference's fixed Gauss points), and the J2 equivalent
    // plastic strain when a material has history.
    scalars("det_F", [&](int p) { return fixed ? 1.0 : V(p) / V0(p); });
    if (ps.hasHistory()) scalars("plastic_strain", [&](int p) { return hist(p, ParticleSet::kHistoryCount - 1); });
    f << "</DataArray>\n</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
    f.flush();
    if (!file) throw std::runtime_error("cannot write " + path);
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) throw std::runtime_error("cannot write " + path);
}

std::string PvdIndex::pieceName(const std::string& fileStem, int rank) {
  return fileStem + "_r" + std::to_string(rank) + ".vtu";
}

void PvdIndex::add(double time, const std::string& fileStem) {
  entries_.emplace_back(time, fileStem);
  const std::string tmp = path_ + ".tmp";
  {
    std::ofstream f(tmp);
    f << std::setprecision(12);
    f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n<Collection>\n";
    for (const auto& [t, stem] : entries_)
      for (int r = 0; r < ranks_; ++r)
        f << "  <DataSet timestep=\"" << t << "\" part=\"" << r << "\" file=\"" << pieceName(stem, r) << "\"/>\n";
    f << "</Collection>\n</VTKFile>\n";
  }
  std::rename(tmp.c_str(), path_.c_str());
}

}  // namespace impm
