// issue 2's `hotend40w` plant for closed-loop host tests: heater block 16.7 J/K, 40 W, loss
// 0.068 W/K to a 25 °C ambient rising to 0.097 W/K with the part fan at 100 %; the sensor lags
// the block at 0.22 /s. RK4, 8 sub-steps per control period. Shared by the issue-3 controller
// tests (Marlin-style PID, feedforward, the controller bank).
#pragma once

#include <stdint.h>

namespace test_plant {

constexpr double kAmbientC = 25.0;
constexpr double kPeriodS = 0.128;

class Hotend40w {
 public:
  double sensor_c() const { return sensor_c_; }
  double block_c() const { return block_c_; }
  void set_fan(double fraction) { fan_ = fraction; }
  // Starts at a steady temperature (both nodes equal).
  void settle_at(double temp_c) { block_c_ = sensor_c_ = temp_c; }

  void advance(double duty, double seconds = kPeriodS) {
    const int n = 8;
    const double dt = seconds / n;
    const double loss = 0.068 + (0.097 - 0.068) * fan_;
    auto f = [&](double b, double s, double& db, double& ds) {
      db = (40.0 * duty - loss * (b - kAmbientC)) / 16.7;
      ds = 0.22 * (b - s);
    };
    for (int i = 0; i < n; ++i) {
      double b1, s1, b2, s2, b3, s3, b4, s4;
      f(block_c_, sensor_c_, b1, s1);
      f(block_c_ + dt / 2 * b1, sensor_c_ + dt / 2 * s1, b2, s2);
      f(block_c_ + dt / 2 * b2, sensor_c_ + dt / 2 * s2, b3, s3);
      f(block_c_ + dt * b3, sensor_c_ + dt * s3, b4, s4);
      block_c_ += dt / 6 * (b1 + 2 * b2 + 2 * b3 + b4);
      sensor_c_ += dt / 6 * (s1 + 2 * s2 + 2 * s3 + s4);
    }
  }

 private:
  double block_c_ = kAmbientC;
  double sensor_c_ = kAmbientC;
  double fan_ = 0;
};

// °C → temp_q8 as the firmware's conversion rounds it.
inline int32_t to_q8(double temp_c) { return static_cast<int32_t>(temp_c * 256.0 + (temp_c < 0 ? -0.5 : 0.5)); }

}  // namespace test_plant
