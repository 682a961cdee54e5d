// M303: the autotune job (issue 7) — Marlin's command and wording, run in the timer-driven
// control step like every controller, never blocking the G-code layer:
//   M303 E0 S<target °C, 210> C<cycles 3..20, 5> U<0|1> F<0|1, 1: measure the part fan's loss>
// begin() validates and starts; the control loop calls step() every period while running();
// the main loop calls report(), which prints the cycle lines and the result and, with U1,
// applies what the board designed from the identified model (control/autotune_design.h):
// M307 model, M301 gains (the fuzzy-PID's centre), and M310 S0 F1 (PID following the model's
// heat-up) as the controller. Hardware-free: the host tests drive it through the G-code layer.
#pragma once
#include <stdint.h>

#include "control/autotune.h"
#include "control/autotune_design.h"
#include "firmware/controller_bank.h"
#include "firmware/gcode_command.h"
#include "firmware/gcode_output.h"

namespace firmware {

// Lowest and highest M303 S. The top keeps the abort threshold (S + 25 °C) below MAXTEMP
// (285 °C): a tune that runs away is stopped by its own check, with Marlin's wording.
constexpr int32_t kMinTuneTargetQ8 = 50L * 256;
constexpr int32_t kMaxTuneTargetQ8 = 255L * 256;

// How far M303 U1's model is trusted (Settings::model_tuned, controller_settings.h).
inline uint8_t tuned_model_source(const control::AutotuneResult& r) {
  return control::tune_bounds_tightly(r)     ? kModelMeasured
         : r.second_lag_q8 > 0               ? kModelFittedLags  // (an unsure tune: never tight)
         : control::tune_heat_up_trusted(r) ? kModelMeasuredLag
                                            : kModelMeasuredLoose;
}

class AutotuneJob {
 public:
  enum class Stop : uint8_t { kUser, kFault };  // M108 / M104 S0 / M112, or a latched fault

  // The engine's ~750 bytes of state live in the bank's controller storage (the controllers
  // cannot run during a tune): begin() borrows it, report() gives it back when the tune ends.
  constexpr explicit AutotuneJob(ControllerBank& bank) : bank_(bank), tune_(bank.autotune_storage()) {}

  // M303 (the command is M303): prints the Error line and returns false for bad parameters or
  // when `refusal` (the machine's reason, e.g. a latched fault) is set; else starts the tune,
  // prints "PID Autotune start", and the caller sets the heater's target to target_q8().
  // hold_gain_q8: the static gain of a steady hold just before (ControlLoop::hold_gain_q8), 0 if none.
  bool begin(const gcode::Command& cmd, gcode::Output& out, const gcode::FlashText* refusal,
             uint8_t fan_duty, int32_t hold_gain_q8);
  bool running() const { return bank_.autotuning() && tune_.state() == control::AutotuneState::kRunning; }
  // Running, or ended with lines still to print (the caller ends the heating when it turns false).
  bool busy() const { return running() || pending_ != 0; }
  // The tune has ended and report() will print its result: the machine switches the heater off
  // first, so a control step run while that text goes out (hal::uart's TX wait) cannot heat.
  bool ended() const { return (pending_ & kEnded) != 0; }
  int32_t target_q8() const { return target_q8_; }

  // Control step: the heater duty for the next period; *fan_duty the part fan the tune wants.
  uint16_t step(int32_t measured_q8, uint8_t* fan_duty);
  // Ends a running tune with the heater off (the report says why).
  void stop(Stop why);

  // Main loop: prints what the control step produced. Returns true once, when the job has
  // ended and reported (the caller switches the heater off and restores the fan).
  bool report(gcode::Output& out, const HandOver& now);
  uint8_t fan_to_restore() const { return user_fan_; }
  void set_fan_to_restore(uint8_t duty) { user_fan_ = duty; }

 private:
  enum Pending : uint8_t { kCycleLine = 1, kUltimateLine = 2, kEnded = 4 };
  void write_result(gcode::Output& out, const HandOver& now);
  void write_failure(gcode::Output& out) const;

  ControllerBank& bank_;
  control::Autotune& tune_;  // valid while bank_.autotuning()
  control::AutotuneCycle cycle_{0, 0, 0, 0};  // copied at the event: printed later
  control::AutotuneUltimate ultimate_{0, 0};
  int32_t target_q8_ = 0;
  uint8_t pending_ = 0;
  uint8_t user_fan_ = 0;
  bool apply_ = false;
  bool stopped_by_fault_ = false;
};

}  // namespace firmware
