#include "solvers/History.hpp"

#include <Teuchos_CommHelpers.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <stdexcept>

#include "core/kernels/Energy.hpp"

namespace impm {

History::History(std::vector<Monitor>& monitors, const ParticleSet& particles, const Materials& materials,
                 const ExactReference* exact, bool energyAndMomentum,
                 const Teuchos::RCP<const Teuchos::Comm<int>>& comm, double firstTime, const GridConditions* conditions)
    : monitors_(monitors),
      particles_(particles),
      materials_(materials),
      exact_(exact),
      energy_(energyAndMomentum),
      comm_(comm),
      conditions_(conditions) {
  if (conditions_) {
    for (size_t c = 0; c < conditions_->names().size(); ++c) {
      std::string name = conditions_->names()[c];
      std::replace(name.begin(), name.end(), ' ', '_');
      for (int d = 0; d < particles_.dim; ++d)
        if (conditions_->prescribed()[c][d]) {
          reactionColumns_.push_back(name + "_" + conditions_->forceKinds()[c] + "_" + char('x' + d));
          reactionIndex_.push_back(int(3 * c + d));
        }
    }
  }
  for (const auto& m : monitors_) {
    const double X[3] = {m.x0, m.y0, m.z0};
    withExact_.push_back(exact_ && !std::isnan(exact_->valueAt(m.quantity, X, firstTime)));
  }
  double X[3] = {0, 0, 0}, u[3];
  field_ = exact_ && exact_->displacementAt(X, firstTime, particles_.dim, u);
}

void History::open(const std::string& path, int digits) {
  if (comm_->getRank() != 0) return;
  csv_.open(path);
  if (!csv_) throw std::runtime_error("cannot write " + path);
  csv_ << "time";
  for (size_t k = 0; k < monitors_.size(); ++k) {
    csv_ << ',' << monitors_[k].name;
    if (withExact_[k]) csv_ << ',' << monitors_[k].name << "_exact";
  }
  if (energy_)
    csv_ << ",kinetic_energy,strain_energy,total_energy,momentum_x,momentum_y"
         << (particles_.dim == 3 ? ",momentum_z" : "");
  if (field_) csv_ << ",displacement_error_rms,displacement_error_max";
  for (const auto& c : reactionColumns_) csv_ << ',' << c;
  csv_ << '\n' << std::setprecision(digits);
}

void History::close() {
  if (csv_.is_open()) csv_.close();
}

double History::monitorValue(const Monitor& mon) const {
  if (mon.owner != comm_->getRank()) return 0.0;
  const int p = mon.localIndex;
  auto read = [](const auto& view, int i, int c) {
    double v;
    Kokkos::deep_copy(v, Kokkos::subview(view, i, c));
    return v;
  };
  const std::string& q = mon.quantity;
  const bool fixed = particles_.fixedPositions();
  const double reference[3] = {mon.x0, mon.y0, mon.z0};
  for (int d = 0; d < particles_.dim; ++d) {
    const std::string axis(1, char('X' + d));
    if (q == "Displacement " + axis) return fixed ? read(particles_.u, p, d) : read(particles_.x, p, d) - reference[d];
    if (q == "Velocity " + axis) return read(particles_.v, p, d);
  }
  // Stored stress components (StressLayout): xx, yy, xy, zz, yz, xz.
  const char* stresses[] = {"Stress XX", "Stress YY", "Stress XY", "Stress ZZ", "Stress YZ", "Stress XZ"};
  for (int c = 0; c < particles_.stressCount(); ++c)
    if (q == stresses[c]) return read(particles_.stress, p, c);
  throw std::logic_error("monitor quantity '" + q + "' is not one of this dimension's");
}

void History::record(double t, RunResult& r) {
  std::vector<double> local(monitors_.size()), global(monitors_.size());
  for (size_t k = 0; k < monitors_.size(); ++k) local[k] = monitorValue(monitors_[k]);
  if (!monitors_.empty())
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, (int)local.size(), local.data(), global.data());
  r.time.push_back(t);
  for (size_t k = 0; k < monitors_.size(); ++k) {
    const Monitor& m = monitors_[k];
    r.computed[m.name].push_back(global[k]);
    if (withExact_[k]) {
      const double X[3] = {m.x0, m.y0, m.z0};
      r.exact[m.name].push_back(exact_->valueAt(m.quantity, X, t));
    }
  }
  if (energy_) {
    const ParticleTotals e = particles_.dim == 3
                                 ? particleTotals<ExecutionSpace, 3>(particles_, materials_.law(), *comm_)
                                 : particleTotals<ExecutionSpace, 2>(particles_, materials_.law(), *comm_);
    r.kinetic.push_back(e.kinetic);
    r.strain.push_back(e.strain);
    r.momentumX.push_back(e.momentum[0]);
    r.momentumY.push_back(e.momentum[1]);
    r.momentumZ.push_back(e.momentum[2]);
    if (r.time.size() == 1) momentumScale_ = e.momentumScale;
  }
  if (field_) {
    const auto [rms, max] = displacementFieldError(t);
    r.fieldErrorRms.push_back(rms);
    r.fieldErrorMax.push_back(max);
  }
  if (!reactionColumns_.empty()) {
    const std::vector<double> reaction = conditions_->reactions(*comm_);
    r.reactionColumns = reactionColumns_;
    for (size_t k = 0; k < reactionColumns_.size(); ++k)
      r.reactions[reactionColumns_[k]].push_back(reaction[reactionIndex_[k]]);
  }
  if (comm_->getRank() == 0) writeRow(r, r.time.size() - 1);
}

void History::writeRow(const RunResult& r, size_t i) {
  csv_ << r.time[i];
  for (size_t k = 0; k < monitors_.size(); ++k) {
    csv_ << ',' << r.computed.at(monitors_[k].name)[i];
    if (withExact_[k]) csv_ << ',' << r.exact.at(monitors_[k].name)[i];
  }
  if (energy_) {
    // (kinetic + strain: ParticleTotals::total().)
    csv_ << ',' << r.kinetic[i] << ',' << r.strain[i] << ',' << r.kinetic[i] + r.strain[i] << ',' << r.momentumX[i]
         << ',' << r.momentumY[i];
    if (particles_.dim == 3) csv_ << ',' << r.momentumZ[i];
  }
  if (field_) csv_ << ',' << r.fieldErrorRms[i] << ',' << r.fieldErrorMax[i];
  for (const auto& c : reactionColumns_) csv_ << ',' << r.reactions.at(c)[i];
  csv_ << '\n';
}

void History::replay(const RunResult& r) {
  if (comm_->getRank() != 0) return;
  for (size_t i = 0; i < r.time.size(); ++i) writeRow(r, i);
}

void History::saveState(const RunResult& r, NamedArrays& state) const {
  state["history time"] = r.time;
  for (const auto& [name, values] : r.computed) state["history computed " + name] = values;
  for (const auto& [name, values] : r.exact) state["history exact " + name] = values;
  state["history kinetic"] = r.kinetic;
  state["history strain"] = r.strain;
  state["history momentum x"] = r.momentumX;
  state["history momentum y"] = r.momentumY;
  state["history momentum z"] = r.momentumZ;
  state["history field error rms"] = r.fieldErrorRms;
  state["history field error max"] = r.fieldErrorMax;
  state["history momentum scale"] = {momentumScale_};
  for (const auto& c : reactionColumns_) state["history reaction " + c] = r.reactions.at(c);
}

void History::restoreState(const NamedArrays& state, RunResult& r) {
  r.time = state.at("history time");
  for (const auto& m : monitors_) r.computed[m.name] = state.at("history computed " + m.name);
  for (size_t k = 0; k < monitors_.size(); ++k)
    if (withExact_[k]) r.exact[monitors_[k].name] = state.at("history exact " + monitors_[k].name);
  r.kinetic = state.at("history kinetic");
  r.strain = state.at("history strain");
  r.momentumX = state.at("history momentum x");
  r.momentumY = state.at("history momentum y");
  r.momentumZ = state.at("history momentum z");
  r.fieldErrorRms = state.at("history field error rms");
  r.fieldErrorMax = state.at("history field error max");
  momentumScale_ = state.at("history momentum scale").at(0);
  r.reactionColumns = reactionColumns_;
  for (const auto& c : reactionColumns_) {
    const auto it = state.find("history reaction " + c);
    // (A checkpoint that holds no reaction history for c: zeros, one per row.)
    r.reactions[c] = it != state.end() ? it->second : std::vector<double>(r.time.size(), 0.0);
  }
}

std::pair<double, double> History::displacementFieldError(double t) const {
  const int dim = particles_.dim;
  auto x = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(),
                                               particles_.fixedPositions() ? particles_.u : particles_.x);
  auto x0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.x0);
  auto v0 = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.volume0);
  auto body = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.body);
  const bool fixed = particles_.fixedPositions();
  double local[2] = {0, 0}, global[2];  // sum V0 |e|^2, sum V0
  double localMax = 0, globalMax = 0;
  for (int p = 0; p < particles_.count; ++p) {
    if (exact_->fieldBody() >= 0 && body(p) != exact_->fieldBody()) continue;
    double X[3] = {0, 0, 0}, u[3];
    for (int d = 0; d < dim; ++d) X[d] = x0(p, d);
    exact_->displacementAt(X, t, dim, u);
    double e2 = 0;
    for (int d = 0; d < dim; ++d) {
      const double computed = fixed ? x(p, d) : x(p, d) - x0(p, d);
      e2 += (computed - u[d]) * (computed - u[d]);
    }
    local[0] += v0(p) * e2;
    local[1] += v0(p);
    localMax = std::max(localMax, std::sqrt(e2));
  }
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_SUM, 2, local, global);
  Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MAX, localMax, Teuchos::outArg(globalMax));
  return {global[1] > 0 ? std::sqrt(global[0] / global[1]) : 0.0, globalMax};
}

void History::finish(RunResult& r) const {
  for (size_t k = 0; k < monitors_.size(); ++k) {
    if (!withExact_[k]) continue;
    const auto& c = r.computed[monitors_[k].name];
    const auto& e = r.exact[monitors_[k].name];
    double num = 0, den = 0;
    for (size_t i = 0; i < c.size(); ++i) {
      num += (c[i] - e[i]) * (c[i] - e[i]);
      den += e[i] * e[i];
    }
    r.relativeL2[monitors_[k].name] = den > 0 ? std::sqrt(num / den) : std::sqrt(num);
  }
  if (!r.fieldErrorRms.empty()) {
    r.fieldErrorRmsEnd = r.fieldErrorRms.back();
    r.fieldErrorMaxEnd = r.fieldErrorMax.back();
    r.fieldErrorRmsPeak = *std::max_element(r.fieldErrorRms.begin(), r.fieldErrorRms.end());
    r.fieldErrorMaxPeak = *std::max_element(r.fieldErrorMax.begin(), r.fieldErrorMax.end());
  }
  if (energy_ && !r.time.empty()) {
    const double e0 = r.kinetic.front() + r.strain.front();
    const double scale = e0 != 0 ? std::abs(e0) : 1.0;
    r.energyRelativeDrift = (r.kinetic.back() + r.strain.back() - e0) / scale;
    const double p0x = r.momentumX.front(), p0y = r.momentumY.front(), p0z = r.momentumZ.front();
    // Bodies at rest: the change is absolute.
    const double pscale = momentumScale_ > 0 ? momentumScale_ : 1.0;
    for (size_t i = 0; i < r.time.size(); ++i) {
      r.energyMaxRelativeDeviation =
          std::max(r.energyMaxRelativeDeviation, std::abs(r.kinetic[i] + r.strain[i] - e0) / scale);
      r.momentumMaxRelativeChange = std::max(
          r.momentumMaxRelativeChange, std::sqrt(std::pow(r.momentumX[i] - p0x, 2) + std::pow(r.momentumY[i] - p0y, 2) +
                                                 std::pow(r.momentumZ[i] - p0z, 2)) /
                                           pscale);
    }
  }
}

void History::locateMonitors() {
  auto id = Kokkos::create_mirror_view_and_copy(Kokkos::HostSpace(), particles_.id);
  for (auto& m : monitors_) {
    m.localIndex = -1;
    for (int p = 0; p < particles_.count && m.localIndex < 0; ++p)
      if (id(p) == m.particleId) m.localIndex = p;
    const int here = m.localIndex >= 0 ? comm_->getRank() : comm_->getSize();
    Teuchos::reduceAll(*comm_, Teuchos::REDUCE_MIN, here, Teuchos::outArg(m.owner));
  }
}

}  // namespace impm
