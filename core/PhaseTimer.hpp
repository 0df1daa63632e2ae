// Timers on the main phases of a run (p2g, grid update, g2p, stress update, residual,
// preconditioner set-up, Newton solve), through Teuchos::TimeMonitor. Off unless enabled
// (`impm --timers`), so that the hot loops pay one branch when nobody is looking.
//
//   { PhaseTimer phase("p2g"); ... }   // counts as "impm: p2g"
#pragma once

#include <Teuchos_TimeMonitor.hpp>

#include <map>
#include <optional>
#include <string>

namespace impm {

class PhaseTimer {
 public:
  explicit PhaseTimer(const char* phase) {
    if (!enabled()) return;
    auto& timer = timers()[phase];
    if (timer.is_null()) timer = Teuchos::TimeMonitor::getNewCounter(std::string("impm: ") + phase);
    monitor_.emplace(*timer);
  }
  static bool& enabled() {
    static bool on = false;
    return on;
  }
  // Every phase timed so far, by phase name.
  static std::map<std::string, Teuchos::RCP<Teuchos::Time>>& timers() {
    static std::map<std::string, Teuchos::RCP<Teuchos::Time>> all;
    return all;
  }

 private:
  std::optional<Teuchos::TimeMonitor> monitor_;
};

}  // namespace impm
