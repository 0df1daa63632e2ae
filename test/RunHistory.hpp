// Test helper: run a deck in-process and read back its history.csv by column name (the
// integration tests compare monitor and energy histories).
#pragma once

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_TestForException.hpp>
#include <Tpetra_Core.hpp>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/InputDeck.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/Simulation.hpp"

namespace impm_test {

// Columns of history.csv, by header name ("time", monitor names, "total_energy", ...).
using History = std::map<std::string, std::vector<double>>;

// A value of summary.yaml by its key (the first line holding "key:"); NaN when absent.
inline double summaryValue(const std::string& dir, const std::string& key) {
  std::ifstream summary(dir + "/summary.yaml");
  for (std::string line; std::getline(summary, line);)
    if (line.find(key + ":") != std::string::npos) return std::stod(line.substr(line.find(key + ":") + key.size() + 1));
  return std::nan("");
}

inline History readHistory(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::vector<std::string> names;
  if (std::getline(in, line)) {
    std::istringstream head(line);
    for (std::string name; std::getline(head, name, ',');) names.push_back(name);
  }
  History h;
  while (std::getline(in, line)) {
    std::istringstream row(line);
    std::string cell;
    for (size_t k = 0; k < names.size() && std::getline(row, cell, ','); ++k) h[names[k]].push_back(std::stod(cell));
  }
  return h;
}

// Runs `sim` and requires it to complete: a run that stops early (diverged, Newton failure, ...)
// throws, with `what` and the run's status in the message. Returns the run's result.
inline impm::RunResult runToCompletion(impm::Simulation& sim, const std::string& what) {
  std::ostringstream log;
  const impm::RunResult r = sim.run(log);
  TEUCHOS_TEST_FOR_EXCEPTION(r.status != "completed", std::runtime_error, what + " run: " + r.status);
  return r;
}

// Validates and runs `deck` on the default communicator; returns its history.csv.
inline History runDeck(Teuchos::ParameterList deck) {
  impm::validateDeck(deck);
  impm::Simulation sim(deck, Tpetra::getDefaultComm());
  std::ostringstream log;
  sim.run(log);
  return readHistory(sim.outputDirectory() + "/history.csv");
}

// Largest difference over a history, relative to the largest magnitude of the reference; a
// history of another length counts as infinitely different.
inline double historyRelativeDifference(const std::vector<double>& values, const std::vector<double>& reference) {
  if (values.size() != reference.size()) return INFINITY;
  double diff = 0, scale = 0;
  for (size_t i = 0; i < values.size(); ++i) {
    diff = std::max(diff, std::abs(values[i] - reference[i]));
    scale = std::max(scale, std::abs(reference[i]));
  }
  return scale > 0 ? diff / scale : diff;
}

// Rank-count independence of a run's monitored histories. At np > 1 each rank reruns `deck` alone
// (its own communicator, its own output directory), and the result is the largest difference
// between any monitor's history in `all` (the run on every rank) and in the one-rank run, relative
// to that monitor's largest magnitude, as seen by every rank. At np 1 there is nothing to compare:
// -1.
inline double rankCountDifference(Teuchos::ParameterList deck, const impm::RunResult& all, const std::string& outdir) {
  auto comm = Tpetra::getDefaultComm();
  if (comm->getSize() == 1) return -1.0;
  deck.sublist("Output").set("Plot", false).set("Progress", false).set("VTK Interval", 0);
  impm::validateDeck(deck);
  auto self = comm->split(comm->getRank(), 0);
  impm::Simulation sim(deck, self, outdir + "_alone_rank" + std::to_string(comm->getRank()));
  const impm::RunResult one = runToCompletion(sim, "one-rank");
  // (Every rank reaches the reduction below: no early return.)
  double worst = all.computed.empty() ? INFINITY : 0.0;
  for (const auto& [monitor, values] : all.computed)
    worst = std::max(worst, historyRelativeDifference(values, one.computed.at(monitor)));
  double worstAll = worst;
  Teuchos::reduceAll(*comm, Teuchos::REDUCE_MAX, worst, Teuchos::outArg(worstAll));
  return worstAll;
}

}  // namespace impm_test
