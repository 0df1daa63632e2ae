#include "core/output/VtkWriter.hpp"

#include <cstdio>
#include <fstream>
#include <iomanip>
#include <stdexcept>

namespace impm {

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
    std::ofstream f(tmp);
    if (!f) throw std::runtime_error("cannot write " + path);
    f << std::setprecision(10);
    f << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << n << "\" NumberOfCells=\"" << n << "\">\n";
    f << "<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) f << x(p, 0) << ' ' << x(p, 1) << ' ' << (dim == 3 ? x(p, 2) : 0.0) << '\n';
    f << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) f << p << '\n';
    f << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) f << p + 1 << '\n';
    f << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) f << "1\n";  // VTK_VERTEX
    f << "</DataArray>\n</Cells>\n<PointData Vectors=\"displacement\">\n";
    auto vec3 = [&](const char* name, auto get) {
      f << "<DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
      for (int p = 0; p < n; ++p) f << get(p, 0) << ' ' << get(p, 1) << ' ' << (dim == 3 ? get(p, 2) : 0.0) << '\n';
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
      f << '\n';
    }
    f << "</DataArray>\n<DataArray type=\"Float64\" Name=\"mass\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) f << m(p) << '\n';
    f << "</DataArray>\n<DataArray type=\"Float64\" Name=\"volume\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) f << V(p) << '\n';
    // det F = V / V0 (1 for the FE reference's fixed Gauss points), and the J2 equivalent
    // plastic strain when a material has history.
    f << "</DataArray>\n<DataArray type=\"Float64\" Name=\"det_F\" format=\"ascii\">\n";
    for (int p = 0; p < n; ++p) f << (fixed ? 1.0 : V(p) / V0(p)) << '\n';
    if (ps.hasHistory()) {
      f << "</DataArray>\n<DataArray type=\"Float64\" Name=\"plastic_strain\" format=\"ascii\">\n";
      for (int p = 0; p < n; ++p) f << hist(p, ParticleSet::kHistoryCount - 1) << '\n';
    }
    f << "</DataArray>\n</PointData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
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
