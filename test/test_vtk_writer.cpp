// The particle VTU files: numbers are printf's "%.10g" text (appendNumber, std::to_chars), and a
// written file holds every particle's position, velocity and stress in ParaView's layout.
#include <Teuchos_UnitTestHarness.hpp>
#include <Teuchos_DefaultSerialComm.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "core/output/VtkWriter.hpp"
#include "physics/Body.hpp"

namespace {

using namespace impm;

std::string printfText(double value) {
  char buffer[64];
  std::snprintf(buffer, sizeof buffer, "%.10g", value);
  return buffer;
}

std::string appendedText(double value) {
  std::string text;
  appendNumber(text, value);
  return text;
}

// From the bits: with subnormals flushed, the FPU's own tests (std::fpclassify) see a zero.
bool isSubnormal(double value) {
  std::uint64_t bits;
  std::memcpy(&bits, &value, sizeof bits);
  return ((bits >> 52) & 0x7ff) == 0 && (bits & ((std::uint64_t(1) << 52) - 1)) != 0;
}

TEUCHOS_UNIT_TEST(VtkWriter, NumbersAreWhatPrintfWrites) {
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> values = {0.0,
                                -0.0,
                                1.0,
                                -1.0,
                                0.1,
                                1.0 / 3.0,
                                2.0 / 3.0,
                                1e10,
                                1e-5,
                                9.9999999995e-5,
                                123456789012.0,
                                1234567890.5,
                                0.5e-323,
                                std::numeric_limits<double>::min(),
                                std::numeric_limits<double>::max(),
                                std::numeric_limits<double>::denorm_min(),
                                inf,
                                -inf,
                                9.99999999995,
                                99999.999995,
                                1e15,
                                1e16,
                                1e17};
  // Random bit patterns over every exponent, and decimal values near rounding ties.
  std::mt19937_64 random(20261127);
  for (int k = 0; k < 200000; ++k) {
    const std::uint64_t bits = random();
    double value;
    std::memcpy(&value, &bits, sizeof value);
    if (std::isnan(value)) continue;
    values.push_back(value);
  }
  for (int k = 0; k < 20000; ++k) values.push_back(double(k) * 1e-10 + 0.05 * k);
  // Subnormal numbers: impm, like this test's main, flushes them to zero (core/FloatingPoint.hpp),
  // so its state holds none, and std::to_chars, which reads its argument with the FPU, writes one as
  // a signed zero where printf, which reads the bits, writes its digits.
  int differ = 0, subnormals = 0, subnormalsNotZero = 0;
  for (double value : values) {
    if (isSubnormal(value)) {
      ++subnormals;
      if (appendedText(value) != (std::signbit(value) ? "-0" : "0")) ++subnormalsNotZero;
      continue;
    }
    if (printfText(value) == appendedText(value)) continue;
    if (++differ <= 5) out << "printf '" << printfText(value) << "' appendNumber '" << appendedText(value) << "'\n";
  }
  out << values.size() << " values, " << differ << " differ; " << subnormals << " subnormal, " << subnormalsNotZero
      << " of them not written as a signed zero\n";
  TEST_EQUALITY(differ, 0);
  TEST_ASSERT(subnormals > 10);
  TEST_EQUALITY(subnormalsNotZero, 0);
}

// Reads the numbers of the DataArray whose opening tag contains `header` (or, for "<Points>\n<DataArray",
// begins with it), up to its "</DataArray>".
std::vector<double> dataArray(const std::string& file, const std::string& header) {
  const size_t at = file.find(header);
  if (at == std::string::npos) return {};
  const size_t begin = file.find('>', at + header.size()) + 1, end = file.find("</DataArray>", begin);
  std::istringstream in(file.substr(begin, end - begin));
  std::vector<double> values;
  for (double v; in >> v;) values.push_back(v);
  return values;
}

TEUCHOS_UNIT_TEST(VtkWriter, FileHoldsEveryParticle) {
  StructuredGrid g;
  g.nx = 6;
  g.ny = 3;
  g.hx = 0.5;
  g.hy = 0.5;
  GridDistribution dist(g, Teuchos::rcp(new Teuchos::SerialComm<int>()));
  ParticleSet ps = createParticles(RectangularBody{0.5, 2.5, 0.0, 1.5, 2, 2, 0.1}, Materials{1e6, 0.25, 1000.0}, dist);
  auto psv = ps;
  Kokkos::parallel_for(
      "fill", Kokkos::RangePolicy<ExecutionSpace>(0, ps.count), KOKKOS_LAMBDA(int p) {
        psv.v(p, 0) = 0.1 * p + 1.0 / 3.0;
        psv.v(p, 1) = -1e-7 * p;
        for (int i = 0; i < 4; ++i) psv.stress(p, i) = 1e3 * p + i + 0.123456789012;
      });
  const std::string path = "test_vtk_writer_particles.vtu";
  writeParticlesVtu(path, ps);
  std::ifstream in(path);
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string file = buffer.str();
  const int n = ps.count;
  TEST_ASSERT(file.find("NumberOfPoints=\"" + std::to_string(n) + "\"") != std::string::npos);
  TEST_ASSERT(file.rfind("</VTKFile>\n") == file.size() - 11);
  const auto points = dataArray(file, "<Points>\n<DataArray");
  const auto velocity = dataArray(file, "Name=\"velocity\"");
  const auto stress = dataArray(file, "Name=\"stress\"");
  const auto mass = dataArray(file, "Name=\"mass\"");
  TEST_EQUALITY(points.size(), size_t(3 * n));
  TEST_EQUALITY(velocity.size(), size_t(3 * n));
  TEST_EQUALITY(stress.size(), size_t(4 * n));
  TEST_EQUALITY(mass.size(), size_t(n));
  if (!success) return;  // a short array: the comparisons below would read past it
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.x);
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto s = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.stress);
  double worst = 0.0;  // relative, against the 10 significant digits written
  auto compare = [&](double written, double value) {
    worst = std::max(worst, std::abs(written - value) / std::max(std::abs(value), 1e-300));
  };
  for (int p = 0; p < n; ++p) {
    for (int d = 0; d < 2; ++d) {
      compare(points[3 * p + d], x(p, d));
      compare(velocity[3 * p + d], v(p, d));
    }
    TEST_EQUALITY(points[3 * p + 2], 0.0);
    for (int c = 0; c < 4; ++c) compare(stress[4 * p + c], s(p, c));
  }
  out << "largest relative difference " << worst << "\n";
  TEST_ASSERT(worst <= 5e-10);
  std::remove(path.c_str());
}

}  // namespace
