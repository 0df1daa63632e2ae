// Failures that must end every rank. A check or a write done by some ranks only (rank 0 creating
// the output directory, each rank writing its VTU piece) must not leave the other ranks waiting
// in the next collective call: its failure is agreed on by all ranks and rethrown on each.
#pragma once

#include <Teuchos_Comm.hpp>
#include <Teuchos_CommHelpers.hpp>

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include "core/InputDeck.hpp"

namespace impm {

// Runs `action` on the ranks where `here` is true; if it throws on any rank, every rank throws
// the same error: the message of the lowest failing rank, a DeckError if it was one (exit 2),
// std::runtime_error otherwise (exit 1). Collective: every rank must call it.
inline void rethrowOnEveryRank(const Teuchos::Comm<int>& comm, bool here, const std::function<void()>& action) {
  enum : int { Ok = 0, RunFailure = 1, DeckFailure = 2 };
  int kind = Ok;
  std::string message;
  if (here) {
    try {
      action();
    } catch (const DeckError& e) {
      kind = DeckFailure;
      message = e.what();
    } catch (const std::exception& e) {
      kind = RunFailure;
      message = e.what();
    }
  }
  const int size = comm.getSize();
  const int failing = kind != Ok ? comm.getRank() : size;
  int firstFailing = size;
  Teuchos::reduceAll(comm, Teuchos::REDUCE_MIN, failing, Teuchos::outArg(firstFailing));
  if (firstFailing == size) return;
  int header[2] = {kind, (int)message.size()};
  Teuchos::broadcast(comm, firstFailing, 2, header);
  std::vector<char> text(message.begin(), message.end());
  text.resize(header[1]);
  if (header[1] > 0) Teuchos::broadcast(comm, firstFailing, header[1], text.data());
  const std::string agreed(text.begin(), text.end());
  if (header[0] == DeckFailure) throw DeckError(agreed);
  throw std::runtime_error(agreed);
}

}  // namespace impm
