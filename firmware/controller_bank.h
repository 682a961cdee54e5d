// Every hotend controller of issue 3, one of them active, plus the model feedforward: the one
// control::Controller the heater manager steps. Settings changes (M301/M307/M310/M312, M501,
// M502) are checked as a whole and applied at once; while heating, the active controller then
// takes over from the measured temperature and the present duty (bumpless). Hardware-free
// (the fuzzy surfaces' reader is passed in), so the host tests run it as the firmware does.
#pragma once
#include <stdint.h>

#include "control/controller.h"
#include "control/feedforward.h"
#include "control/fuzzy_pid.h"
#include "control/marlin_pid.h"
#include "control/pid.h"
#include "control/state_feedback.h"
#include "firmware/controller_settings.h"
#include "firmware/gcode_text.h"

namespace firmware {

// What a take-over starts from: the latest reading, the duty of the running period, and
// whether the heater is on (otherwise the controller simply starts afresh).
struct HandOver {
  int32_t measured_q8;
  uint16_t duty_q16;
  bool heating;
};

class ControllerBank final : public control::Controller {
 public:
  // constexpr: the global instance is constant-initialized (no start-up constructor code).
  explicit constexpr ControllerBank(fuzzy::LoadCell load) : fuzzy_(load) {}

  // Start-up with settings apply() would accept without state-feedback constants (defaults).
  void init(const Settings& settings);

  // Checks `next` entirely (gains, fuzzy schedule, model, controller; S1 needs loaded
  // constants) and applies it: nullptr, or the reason for refusing (nothing changed then).
  const gcode::FlashText* apply(const Settings& next, const HandOver& now);
  // M501/M502: settings and state-feedback constants together (sf nullptr: none), all or nothing.
  const gcode::FlashText* replace_all(const Settings& next, const control::StateFeedbackConstants* sf,
                                      const HandOver& now);
  const Settings& settings() const { return settings_; }

  // M311 W1: loads state-feedback constants; false (nothing changed) if they fail its checks.
  bool load_state_feedback(const control::StateFeedbackConstants& k, const HandOver& now);
  bool state_feedback_loaded() const { return sf_loaded_; }
  const control::StateFeedbackConstants& state_feedback_constants() const { return sf_.constants(); }

  // The model feedforward for this target and part-fan duty, computed now (~600 AVR cycles
  // of multiplies) rather than in the control step: the machine calls it on M104/M109 and
  // M106/M107 (settings changes recompute it themselves). step() recomputes it only if its
  // input differs from the last prepared one.
  void prepare_feedforward(int32_t target_q8, uint8_t fan_duty);

  // control::Controller: the active one, with the feedforward of its family.
  uint16_t step(const control::StepInput& in) override;
  void reset() override;
  void init_bumpless(int32_t measured_q8, uint16_t duty_q16) override;

  ControllerId active_id() const { return static_cast<ControllerId>(settings_.controller); }

 private:
  control::Controller* active();
  uint16_t step_pid_family(const control::StepInput& in);
  uint16_t step_model_following(const control::StepInput& in);
  uint16_t step_fuzzy(const control::StepInput& in);
  // nullptr if `next` can be applied with (sf_available) or without state-feedback constants.
  const gcode::FlashText* refusal(const Settings& next, bool sf_available) const;
  void commit(const Settings& next, const HandOver& now);
  void configure_pid_family(const Settings& s);
  void take_over(const HandOver& now);

  control::Pid pid_;
  control::FuzzyPid fuzzy_;
  control::MarlinPid marlin_;
  control::StateFeedback sf_;
  control::Feedforward feedforward_;
  control::ModelReference reference_;  // PID with F1: the model's heat-up
  Settings settings_{};
  bool sf_loaded_ = false;
  int32_t ff_target_q8_ = -1;  // input of the prepared feedforward (-1: none yet)
  uint8_t ff_fan_ = 0;
  uint16_t ff_q16_ = 0;        // prepared feedforward duty (0 when M310 F0)
  bool ff_applied_ = false;    // the active controller holds its feedforward (PID with F1: model_ff_q16_)
  uint16_t model_ff_q16_ = 0;  // the model's duty the PID holds with F1
  bool reference_started_ = false;
  bool reference_holds_ = false;  // started by a take-over: the model holds the target
};

}  // namespace firmware
