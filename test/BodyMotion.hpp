// Shared by the contact tests: an app deck made quiet for a test run, and each body's mean velocity.
#pragma once

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Tpetra_Core.hpp>

#include <array>
#include <string>
#include <vector>

#include "core/InputDeck.hpp"
#include "solvers/Simulation.hpp"

namespace impm_test {

// apps/<name> without plot, progress line or VTU files.
inline Teuchos::ParameterList quietAppDeck(const std::string& name) {
  Teuchos::ParameterList d = *impm::readDeck(std::string(IMPM_SOURCE_DIR) + "/apps/" + name);
  d.sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
  return d;
}

// The mass-weighted mean velocity (x, y) of each body's particles over all ranks.
inline std::vector<std::array<double, 2>> bodyVelocities(const impm::Simulation& sim) {
  const impm::ParticleSet& ps = sim.particles();
  auto v = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.v);
  auto m = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.mass);
  auto body = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), ps.body);
  const int bodies = (int)sim.bodies().size();
  std::vector<double> local(3 * bodies, 0.0), global(3 * bodies, 0.0);
  for (int p = 0; p < ps.count; ++p) {
    local[3 * body(p)] += m(p);
    for (int d = 0; d < 2; ++d) local[3 * body(p) + 1 + d] += m(p) * v(p, d);
  }
  Teuchos::reduceAll(*Tpetra::getDefaultComm(), Teuchos::REDUCE_SUM, 3 * bodies, local.data(), global.data());
  std::vector<std::array<double, 2>> out(bodies);
  for (int b = 0; b < bodies; ++b) out[b] = {global[3 * b + 1] / global[3 * b], global[3 * b + 2] / global[3 * b]};
  return out;
}

// The mean of a history column over the samples at t >= t0.
inline double meanFrom(const impm::RunResult& r, const std::string& column, double t0) {
  const std::vector<double>& values = r.reactions.at(column);
  double sum = 0;
  int n = 0;
  for (size_t i = 0; i < r.time.size(); ++i)
    if (r.time[i] >= t0) {
      sum += values[i];
      ++n;
    }
  return sum / n;
}

}  // namespace impm_test
