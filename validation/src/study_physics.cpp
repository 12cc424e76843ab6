// SPDX-License-Identifier: MIT
// The analytic physics cases of the validation study (docs/validation.md): each compares the
// model as implemented (core/include/tumble/kernels/contact.hpp) with a formula derived for that
// model, at a stated dt and tolerance, and sweeps dt × rotation scheme for speed against error.
//
// The cases are in study_physics_impact.cpp, study_physics_motion.cpp, study_physics_spin.cpp,
// study_physics_oblique.cpp and study_physics_granular.cpp; what they share in
// study_physics_common.hpp.
#include <vector>

#include "tumble/validation/study.hpp"
#include "study_physics_common.hpp"

namespace tumble::validation::study {

using namespace physics;  // the cases (study_physics_common.hpp)

std::vector<Case> physicsCases() {
  return {
      {"ground_restitution", groundRestitution}, {"sphere_sphere", sphereSphere}, {"free_fall", freeFallCase},
      {"resting_penetration", restingCase},     {"block_sliding", blockSliding},  {"slope", slopeCase},
      {"sphere_slope", sphereSlope},            {"torque_free", torqueFreeCase},  {"chung_ooi", chungOoi},
      {"hooke_oblique", hookeOblique},          {"hertz_chung_ooi", hertzChungOoi},
      {"angle_of_repose", angleOfRepose},       {"beverloo", beverloo},       {"column_stress", columnStress},
      {"janssen", janssen},                     {"energy_balance", energyBalance},
      {"jkr_sticking", jkrSticking},
  };
}

}  // namespace tumble::validation::study
