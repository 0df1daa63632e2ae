#include "physics/MultiFieldContact.hpp"

#include <stdexcept>

namespace impm {

MultiFieldContact::MultiFieldContact(const ContactSpec& spec, const double* spacing)
    : fields_((int)spec.bodies.size()),
      pairs_((int)spec.pairFriction.size()),
      larger_(spec.normals == ContactSpec::Normals::LargerGradient),
      screen_(spec.massScreen),
      distance_(spec.contactDistance),
      spacing_{spacing[0], spacing[1], spacing[2]} {
  if (fields_ > kMaxFields)
    throw std::invalid_argument("multi-field contact takes at most " + std::to_string(kMaxFields) + " bodies, got " +
                                std::to_string(fields_));
  if (pairs_ != fields_ * (fields_ - 1) / 2 || spec.pairNames.size() != spec.pairFriction.size())
    throw std::logic_error("ContactSpec: one friction and one name per pair of bodies");
  pairSign_ = spec.pairSign.empty() ? std::vector<double>(pairs_, 1.0) : spec.pairSign;
  if ((int)pairSign_.size() != pairs_) throw std::logic_error("ContactSpec: one sign per pair of bodies");
  fieldOfBody_ = Kokkos::View<int*, DeviceType>("contact_field_of_body", fields_);
  friction_ = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>("contact_friction", fields_, fields_);
  auto field = Kokkos::create_mirror_view(fieldOfBody_);
  auto mu = Kokkos::create_mirror_view(friction_);
  for (int a = 0; a < fields_; ++a) {
    field(a) = a;
    for (int b = 0; b < fields_; ++b)
      mu(a, b) = a == b ? 0.0 : spec.pairFriction[ContactSpec::pairIndex(a, b, fields_)];
  }
  Kokkos::deep_copy(fieldOfBody_, field);
  Kokkos::deep_copy(friction_, mu);

  rigid_ = Kokkos::View<int*, DeviceType>("contact_rigid_field", fields_);
  rigidMotion_ = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>("contact_rigid_motion", fields_, 6);
  rigidNormal_ = Kokkos::View<double**, Kokkos::LayoutRight, DeviceType>("contact_rigid_normal", fields_, 3);
  auto normal = Kokkos::create_mirror_view(rigidNormal_);
  rigidVelocity_.assign(fields_, {0.0, 0.0, 0.0});
  rigidTime_.assign(fields_, TimeFunction{});
  auto rigid = Kokkos::create_mirror_view(rigid_);
  for (int a = 0; a < fields_; ++a) {
    rigid(a) = a < (int)spec.rigid.size() && spec.rigid[a] ? 1 : 0;
    if (!rigid(a)) continue;
    hasRigid_ = true;
    if (spec.rigidVelocity.size() != spec.rigid.size() || spec.rigidTime.size() != spec.rigid.size())
      throw std::logic_error("ContactSpec: one velocity and one time function per rigid body");
    rigidVelocity_[a] = spec.rigidVelocity[a];
    rigidTime_[a] = spec.rigidTime[a];
    for (int d = 0; d < 3 && a < (int)spec.rigidNormal.size(); ++d) normal(a, d) = spec.rigidNormal[a][d];
  }
  Kokkos::deep_copy(rigid_, rigid);
  Kokkos::deep_copy(rigidNormal_, normal);
}

void MultiFieldContact::setStep(double t, double dt) {
  if (!hasRigid_) return;
  auto motion = Kokkos::create_mirror_view(rigidMotion_);
  for (int a = 0; a < fields_; ++a) {
    const double start = rigidTime_[a](t), end = rigidTime_[a](t + dt);
    for (int d = 0; d < 3; ++d) {
      motion(a, d) = rigidVelocity_[a][d] * start;
      motion(a, 3 + d) = rigidVelocity_[a][d] * end;
    }
  }
  Kokkos::deep_copy(rigidMotion_, motion);
}

}  // namespace impm
