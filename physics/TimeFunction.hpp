// Scalar factors of time for loads and prescribed motion: Step, Sine, Constant, Ramp and a
// piecewise-linear Table of (t, value) pairs.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace impm {

struct TimeFunction {
  enum class Kind { Step, Sine, Constant, Ramp, Table } kind = Kind::Step;
  double omega = 0.0;      // Sine: angular frequency (rad/s)
  double startTime = 0.0;  // Step: on for t >= startTime; Ramp: starts rising at startTime
  double rampTime = 0.0;   // Ramp: from 0 to 1 linearly over [startTime, startTime + rampTime]
  // Table: (t, value) pairs, t strictly increasing; linear between them, the end values held
  // outside.
  std::vector<std::pair<double, double>> table;
  double operator()(double t) const;
  bool operator==(const TimeFunction& o) const {
    return kind == o.kind && omega == o.omega && startTime == o.startTime && rampTime == o.rampTime && table == o.table;
  }
};

// Reads "t0, v0; t1, v1; ..." (pairs separated by ";" or new lines, the two numbers by "," or blanks). Throws
// std::invalid_argument naming the problem: a pair that is not two numbers, no pair, or times that
// do not increase.
std::vector<std::pair<double, double>> parseTimeTable(const std::string& text);

}  // namespace impm
