// The seed papers' hotend models as design inputs (facts from /work/shared/seeds/README.md).
// The seeds' gains are in their own experiments' units, so every model here is rescaled to the
// plant bank's convention: 100 % duty settles 450 K above a 25 °C ambient (a 40 W cartridge).
#pragma once

#include "design/lti_model.h"

namespace design {

constexpr double kSeedRiseK = 450.0;
// The seeds identified no fan path. The simulator's plant bank (sim/plants.cpp) gives them the
// two-node hotend's relative loss increase at 100 % fan (0.097/0.068 − 1), acting on the output
// rise through the input path: in heater-duty terms (0.097/0.068 − 1) / 450 per kelvin.
constexpr double kSeedFanLossPerK = (0.097 / 0.068 - 1.0) / kSeedRiseK;

inline LtiModel with_seed_fan(LtiModel m) {
  m.fan_loss_per_k = kSeedFanLossPerK;
  return m;
}

// Surmak & Piotrowski (seed 000/001), eq. (1): 4 states, data set 1, time in seconds.
inline LtiModel seed000_4_raw() {
  static const double a[16] = {0.0008825, -0.002625, 0.001638, -0.004195,  //
                               0.006013,  0.01268,   0.2325,   -0.4324,    //
                               0.001642,  -0.1009,   -0.07618, 1.912,      //
                               0.001088,  0.01527,   -1.538,   -0.07442};
  static const double b[4] = {-2.87e-7, -5.262e-6, 5.458e-5, -9.529e-5};
  static const double c[4] = {1107, -0.4442, -0.3671, -0.5748};
  return state_space(4, a, b, c);
}

// Eq. (3): 5 states.
inline LtiModel seed000_5_raw() {
  static const double a[25] = {0.000889,  -0.00239, 0.00281, 0.004382, -0.001348,  //
                               0.007245,  -0.00519, 0.2566,  0.1581,   -0.2902,    //
                               -0.000451, -0.09917, -0.2531, -2.621,   1.16,       //
                               0.000709,  0.01095,  2.238,   -0.2162,  -0.7223,    //
                               -0.00246,  -0.05437, 0.4936,  0.6984,   -7.359};
  static const double b[5] = {1.919e-7, 1.336e-4, -2.284e-4, 6.544e-4, 3.081e-3};
  static const double c[5] = {1098, 0.808, -2.372, -1.776, -1.297};
  return state_space(5, a, b, c);
}

inline LtiModel seed000_4() { return with_seed_fan(with_dc_gain(seed000_4_raw(), kSeedRiseK)); }
inline LtiModel seed000_5() { return with_seed_fan(with_dc_gain(seed000_5_raw(), kSeedRiseK)); }

// Seed 002 (patent): FOPDT T 24 s, τ 20.7 s. Seed 004 (Gan et al.): T 25.5 s, τ 19.5 s.
inline LtiModel seed002() { return with_seed_fan(fopdt(kSeedRiseK, 24.0, 20.7)); }
inline LtiModel seed004() { return with_seed_fan(fopdt(kSeedRiseK, 25.5, 19.5)); }
// Seed 003 (Cojuhari et al.): second order T1 = 0.32·T, T2 = 0.64·T with T = 44.2696 s.
inline LtiModel seed003() {
  return with_seed_fan(second_order(kSeedRiseK, 0.32 * 44.2696, 0.64 * 44.2696));
}

}  // namespace design
