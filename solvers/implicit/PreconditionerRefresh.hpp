// When the implicit step reassembles P and when its preconditioner must be refactored.
//
// Jacobian-free Newton: P only builds the preconditioner (the residual carries the physics), so
// it is reassembled every `interval` steps, or at the step after one whose mean GMRES iterations
// per Newton exceeded `krylovThreshold`, or at every Newton iterate (finite strain, on request).
// Assembled Newton: P is the Jacobian, assembled every step (and at every iterate for finite
// strain); its preconditioner is refactored when the graph changed or every `interval` assemblies.
#pragma once

#include <algorithm>
#include <vector>

namespace impm {

class PreconditionerRefresh {
 public:
  PreconditionerRefresh(bool jacobianFree, int interval, int krylovThreshold, bool everyNewton)
      : jacobianFree_(jacobianFree),
        interval_(std::max(1, interval)),
        krylovThreshold_(krylovThreshold),
        everyNewton_(everyNewton) {}

  // Whether P is the tangent at the Newton iterate (assembled anew at each one): finite strain
  // with assembled Newton, or Jacobian-free with a preconditioner per iterate.
  bool trialTangent(bool finiteStrain) const { return finiteStrain && (!jacobianFree_ || everyNewton_); }

  // Jacobian-free: whether the P of an earlier step stands for this one (counts the step).
  bool keep(bool havePreviousP, bool trialTangent) {
    if (jacobianFree_ && !trialTangent && havePreviousP && !requested_ && ++stepsSinceAssembly_ < interval_)
      return true;
    stepsSinceAssembly_ = 0;
    requested_ = false;
    return false;
  }

  // After an assembly: a new value version, and a new preconditioner version when it must be refactored.
  void assembled(bool graphChanged) {
    ++jacobianVersion_;
    if (jacobianFree_ || graphChanged || jacobianVersion_ % interval_ == 0) ++preconditionerVersion_;
  }

  // After a converged step: refresh at the next one when GMRES took too many iterations.
  void noteKrylovIterations(const std::vector<int>& perNewton) {
    if (krylovThreshold_ <= 0 || perNewton.empty()) return;
    double mean = 0.0;
    for (int k : perNewton) mean += k;
    if (mean / perNewton.size() > krylovThreshold_) requested_ = true;
  }

  long jacobianVersion() const { return jacobianVersion_; }
  long preconditionerVersion() const { return preconditionerVersion_; }

  // Checkpoint: steps since assembly, the pending request, the two versions.
  std::vector<double> state() const {
    return {double(stepsSinceAssembly_), double(requested_), double(jacobianVersion_), double(preconditionerVersion_)};
  }
  void restore(double stepsSinceAssembly, double requested, double jacobianVersion, double preconditionerVersion) {
    stepsSinceAssembly_ = int(stepsSinceAssembly);
    requested_ = requested != 0;
    jacobianVersion_ = long(jacobianVersion);
    preconditionerVersion_ = long(preconditionerVersion);
  }

 private:
  bool jacobianFree_;
  int interval_, krylovThreshold_;
  bool everyNewton_;
  int stepsSinceAssembly_ = 0;
  bool requested_ = false;
  long jacobianVersion_ = 0, preconditionerVersion_ = 0;
};

}  // namespace impm
