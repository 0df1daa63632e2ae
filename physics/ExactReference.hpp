// The exact solution a run is compared with, chosen once from the deck's `Exact Solution`
// section by makeExactReference (a factory): the seed's bar and beam, the standing wave and
// the layered bar. The run loop asks only for the value of a monitored quantity at a
// particle's reference position and a time.
#pragma once

#include <Teuchos_ParameterList.hpp>

#include <memory>
#include <string>
#include <vector>

#include "physics/Body.hpp"
#include "physics/Constraints.hpp"
#include "physics/Materials.hpp"
#include "physics/Loads.hpp"
#include "physics/ManufacturedSolution.hpp"

namespace impm {

class ExactReference {
 public:
  virtual ~ExactReference() = default;
  virtual std::string type() const = 0;
  // The exact value of a monitor quantity ("Displacement X", "Stress XX", ...) at reference
  // position (x0, y0) and time t; NaN when this solution has no such quantity.
  virtual double value(const std::string& quantity, double x0, double y0, double t) const = 0;
  // The same at a reference position X (x0, y0[, z0]): solutions that depend on z override it.
  virtual double valueAt(const std::string& quantity, const double* X, double t) const {
    return value(quantity, X[0], X[1], t);
  }
  // The whole displacement field, for solutions that know it everywhere in their body: u(X, t)
  // into u[0..dim) and true, or false. History compares every particle with it.
  virtual bool displacementAt(const double* /*X*/, double /*t*/, int /*dim*/, double* /*u*/) const { return false; }
  // The body whose particles the field describes (displacementAt), or -1 for every body.
  int fieldBody() const { return fieldBody_; }
  // The modulus the comparison uses (E or the plane-strain bar modulus E/(1 - nu^2)).
  double modulus() const { return modulus_; }
  // Entries of summary.yaml beyond Exact Solution and Exact Modulus.
  virtual void addSummary(Teuchos::ParameterList& /*summary*/) const {}

 protected:
  double modulus_ = 0;
  int fieldBody_ = -1;
};

// What the factory needs of the built model.
struct ExactContext {
  std::vector<BodySpec> bodies;  // in deck order
  const Materials* materials = nullptr;
  double thickness = 1;  // 2D: out of plane
  int dimension = 2;     // 3D: a body's cross-section is its height x depth
  // The out-of-plane width of a rectangular body: the thickness in 2D, its z extent in 3D.
  double width(const RectangularBody& r) const { return dimension == 3 ? r.depth() : thickness; }
  std::vector<LoadSpec> loads;
  std::vector<ConstraintSpec> constraints;
  std::string initialCondition;  // Initial Conditions/Type
  double initialAmplitude = 0;
  int initialMode = 1;
  double dt = 0;
  int steps = 0;
  // Exact Solution/Type = Axis-Aligned Manufactured Solution: the field (see axisAlignedManufactured).
  const AxisAlignedManufactured* manufactured = nullptr;
};

// The manufactured solution the deck's Exact Solution section describes (Type = Axis-Aligned
// Manufactured Solution): Amplitude, the square (cube) Rectangle body named by Body, made of a
// Neo-Hookean material. Needs only the context's bodies, materials and dimension (the builder
// calls it before the loads and initial conditions, which use it). Throws DeckError naming the key.
AxisAlignedManufactured axisAlignedManufactured(const Teuchos::ParameterList& exactSection,
                                                const ExactContext& context);

// Null for Type = None. Throws DeckError naming the key when the deck does not fit the solution.
std::unique_ptr<ExactReference> makeExactReference(const Teuchos::ParameterList& exactSection,
                                                   const ExactContext& context);

}  // namespace impm
