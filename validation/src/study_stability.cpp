// SPDX-License-Identifier: MIT
// The stability cases of the validation study (docs/validation.md, "Stability on hard cases"):
// stiff contacts at the stability limit (with the run-time guard), mass ratio 1:1000, a tower of
// 50 clumps, tunnelling, fast spin, coincident centres, and a scene translated far from the origin.
//
// Every criterion is derived from the scheme as implemented (leapfrog kick-drift with forces
// and dashpots from the start-of-step state, core/include/tumble/kernels/integrate.hpp) and
// stated in the case summary with its tolerance.
//
// The cases are in study_stability_stiff.cpp, study_stability_stack.cpp, study_stability_tunnel.cpp,
// study_stability_spin.cpp, study_stability_coincident.cpp and study_stability_far.cpp; what they
// share in study_stability_common.hpp.
#include <vector>

#include "tumble/validation/study.hpp"
#include "study_stability_common.hpp"

namespace tumble::validation::study {

using namespace stability;  // the cases (study_stability_common.hpp)

std::vector<Case> stabilityCases() {
  return {
      Case{"stiff_contact_limit", stiffContactCase}, Case{"mass_ratio_1000", massRatioCase},
      Case{"tower_50", towerCase},                   Case{"tunnelling", tunnellingCase},
      Case{"fast_spin", spinCase},                   Case{"coincident_centres", coincidentCase},
      Case{"far_from_origin", farCase},
  };
}

}  // namespace tumble::validation::study
