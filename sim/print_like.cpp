#include "sim/print_like.h"

#include <random>

#include "sim/gcode_format.h"

namespace sim {

std::vector<TimedCommand> print_like_gcode(double seconds, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> target_c(190.0, 250.0), target_gap_s(120.0, 300.0);
  std::uniform_int_distribution<int> fan_pwm(0, 255);
  std::uniform_real_distribution<double> fan_gap_s(30.0, 120.0);
  std::vector<TimedCommand> out;
  for (double t = target_gap_s(rng); t < seconds; t += target_gap_s(rng))
    out.push_back(TimedCommand{"M104 S" + format_decimal(std::round(target_c(rng))), t});
  for (double t = fan_gap_s(rng); t < seconds; t += fan_gap_s(rng))
    out.push_back(TimedCommand{"M106 S" + std::to_string(fan_pwm(rng)), t});
  return out;
}

}  // namespace sim
