// Shared by the contact tests: the implicit step's assembled P against a finite difference of its
// residual, after a run in contact.
#pragma once

#include <Teuchos_FancyOStream.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Tpetra_Core.hpp>

#include <sstream>
#include <string>

#include "solvers/Simulation.hpp"
#include "solvers/build/Deck.hpp"
#include "solvers/implicit/ImplicitNewmark.hpp"

namespace impm_test {

// Runs the deck (an implicit 2D contact deck with linear MPM, whose c1 M + K is the exact
// derivative of a body's residual) and sets up the next step; returns
// || FD(R) v - P v || / || P v || for random u and v there (1 when the run fails). Frictional
// contact's active set is held in the residual, so that R is linear in u within the step.
inline double contactJacobianMismatch(Teuchos::ParameterList deck, const std::string& outputDirectory,
                                      Teuchos::FancyOStream& out) {
  impm::validateDeck(deck);
  const double dt = deck.sublist("Integrator").get<double>("Time Step");
  const int steps = deck.sublist("Integrator").get<int>("Number of Steps");
  impm::Simulation sim(deck, Tpetra::getDefaultComm(), outputDirectory);
  std::ostringstream log;
  if (sim.run(log).status != "completed") return 1.0;
  auto* model = dynamic_cast<impm::ImplicitNewmark<impm::LinearMpm, 2>*>(&sim.integrator());
  if (!model) return 1.0;
  model->prepareStep(steps * dt, dt);
  const auto map = model->unknownMap();
  impm::Vector u(map), v(map), up(map), R0(map), R1(map), Pv(map), diff(map);
  u.randomize(-1e-9, 1e-9);
  v.randomize(-1.0, 1.0);
  model->residual(u, R0);
  const double eps = 1e-9;
  up.update(1.0, u, eps, v, 0.0);
  model->residual(up, R1);
  diff.update(1.0 / eps, R1, -1.0 / eps, R0, 0.0);
  model->jacobianMatrix(u)->apply(v, Pv);
  diff.update(-1.0, Pv, 1.0);
  const double mismatch = diff.norm2() / Pv.norm2();
  out << "after " << steps << " steps: ||FD(R) v - P v|| / ||P v|| = " << mismatch << "\n";
  return mismatch;
}

}  // namespace impm_test
