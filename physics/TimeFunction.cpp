#include "physics/TimeFunction.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace impm {

double TimeFunction::operator()(double t) const {
  switch (kind) {
    case Kind::Step:
      return t >= startTime ? 1.0 : 0.0;
    case Kind::Sine:
      return std::sin(omega * t);
    case Kind::Constant:
      return 1.0;
    case Kind::Ramp:
      return t >= startTime + rampTime ? 1.0 : t > startTime ? (t - startTime) / rampTime : 0.0;
    case Kind::Table: {
      if (table.empty()) return 0.0;
      if (t <= table.front().first) return table.front().second;
      if (t >= table.back().first) return table.back().second;
      const auto next =
          std::upper_bound(table.begin(), table.end(), t,
                           [](double time, const std::pair<double, double>& row) { return time < row.first; });
      const auto& [t1, v1] = *next;
      const auto& [t0, v0] = *(next - 1);
      return v0 + (v1 - v0) * (t - t0) / (t1 - t0);
    }
  }
  return 0.0;
}

std::vector<std::pair<double, double>> parseTimeTable(const std::string& text) {
  std::string normalised = text;
  std::replace(normalised.begin(), normalised.end(), '\n', ';');
  std::replace(normalised.begin(), normalised.end(), ',', ' ');
  std::vector<std::pair<double, double>> rows;
  std::istringstream pairs(normalised);
  std::string pair;
  while (std::getline(pairs, pair, ';')) {
    if (pair.find_first_not_of(" \t\r") == std::string::npos) continue;
    std::istringstream in(pair);
    double t, v;
    std::string extra;
    if (!(in >> t >> v) || (in >> extra)) throw std::invalid_argument("'" + pair + "' is not a pair 't, value'");
    if (!rows.empty() && !(t > rows.back().first)) {
      std::ostringstream msg;
      msg << "the times must increase, but " << t << " follows " << rows.back().first;
      throw std::invalid_argument(msg.str());
    }
    rows.emplace_back(t, v);
  }
  if (rows.empty()) throw std::invalid_argument("no (t, value) pair");
  return rows;
}

}  // namespace impm
