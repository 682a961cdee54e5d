// Every hotend controller of issue 3, one of them active, plus the model feedforward: the one
// control::Controller the heater manager steps. Settings changes (M301/M307/M310/M312, M501,
// M502) are checked as a whole and applied at once; while heating, the active controller then
// takes over from the measured temperature and the present duty (bumpless). Hardware-free
// (the fuzzy surfaces' reader is passed in), so the host tests run it as the firmware does.
#pragma once
#include <stdint.h>

#include "control/autotune.h"
#include "control/controller.h"
#include "control/feedforward.h"
#include "control/fuzzy_pid.h"
#include "control/marlin_pid.h"
#include "control/pid.h"
#include "control/state_feedback.h"
#include "firmware/controller_settings.h"
#include "firmware/gcode_text.h"

namespace firmware {

// The reason the bank (and the machine) give while M303 has the controllers' storage.
const gcode::FlashText* autotune_busy_text();

// What a take-over starts from: the latest reading, the duty of the running period, and
// whether the heater is on (otherwise the controller simply starts afresh).
struct HandOver {
  int32_t measured_q8;
  uint16_t duty_q16;
  bool heating;
};

class ControllerBank final : public control::Controller {
 public:
  // constexpr: constant-initialisable (AutotuneJob binds to its engine storage at compile time);
  // the firmware builds its instance at boot all the same (main.cpp: .bss, not a .data image).
  explicit constexpr ControllerBank(fuzzy::LoadCell load) : shared_(load), load_(load) {}

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

  // The model feedforward for this target, without and with the part fan, computed now (~600
  // AVR cycles of multiplies) rather than in the control step: the machine calls it on
  // M104/M109 (settings changes recompute it themselves). step() recomputes it only if the
  // target differs from the last prepared one; the fan's share follows StepInput::fan_duty
  // (the airflow, control/fan_airflow.h) every period.
  void prepare_feedforward(int32_t target_q8);

  // control::Controller: the active one, with the feedforward of its family.
  uint16_t step(const control::StepInput& in) override;
  void reset() override;
  void init_bumpless(int32_t measured_q8, uint16_t duty_q16) override;

  ControllerId active_id() const { return static_cast<ControllerId>(settings_.controller); }

  // M303 (issue 7's 2 KB of static RAM): no controller runs while a tune does, so the tune's
  // engine lives in the controllers' storage. begin_autotune() hands it over (the controllers
  // are gone; step() returns 0); settings changes meanwhile (M501, M502) are kept and applied
  // at end_autotune(), which rebuilds the controllers from the settings in force, resets them
  // and refills the M311 staging copy. Main loop only: end_autotune() configures the PID family
  // (the cost of an M301).
  control::Autotune& begin_autotune();
  void end_autotune();
  bool autotuning() const { return autotuning_; }
  // The engine's storage (meaningful only between begin_autotune() and end_autotune()).
  constexpr control::Autotune& autotune_storage() { return shared_.tune; }
  // M311's staging copy (ControllerCommands): in the shared storage too (M311 edits are refused
  // while M303 runs), so use it only while !autotuning().
  control::StateFeedbackConstants& sf_staging() { return shared_.controllers.staging; }
  // The staging copy := the loaded state-feedback constants (zeros if none); not while M303 runs.
  void sync_staging();

 private:
  void follow_fan(uint8_t airflow);  // the feedforward's fan share for this airflow
  control::Controller* active();
  uint16_t step_pid_family(const control::StepInput& in);
  uint16_t step_model_following(const control::StepInput& in);
  uint16_t step_model_heat_up(control::Controller& c, control::Pid& pid, const control::StepInput& in);
  // nullptr if `next` can be applied with (sf_available) or without state-feedback constants.
  const gcode::FlashText* refusal(const Settings& next, bool sf_available) const;
  void commit(const Settings& next, const HandOver& now);
  void configure_pid_family(const Settings& s);
  void take_over(const HandOver& now);

  // What the settings rebuild: the PID family's state and coefficients, the model reference,
  // the M311 staging copy. State feedback keeps its constants (loaded by M311 or M501) outside.
  struct Controllers {
    explicit constexpr Controllers(fuzzy::LoadCell load) : fuzzy(load) {}
    control::Pid pid;
    control::FuzzyPid fuzzy;
    control::MarlinPid marlin;
    control::ModelReference reference;  // PID with F1: the model's heat-up
    control::StateFeedbackConstants staging{};
  };
  union Shared {
    explicit constexpr Shared(fuzzy::LoadCell load) : controllers(load) {}
    Controllers controllers;  // ~590 bytes on AVR
    control::Autotune tune;   // ~750 bytes
  };
  control::Pid& pid() { return shared_.controllers.pid; }
  control::FuzzyPid& fuzzy() { return shared_.controllers.fuzzy; }
  control::MarlinPid& marlin() { return shared_.controllers.marlin; }
  control::ModelReference& reference() { return shared_.controllers.reference; }

  Shared shared_;
  fuzzy::LoadCell load_;  // to rebuild the fuzzy-PID after a tune
  control::StateFeedback sf_;
  control::Feedforward feedforward_;
  Settings settings_{};
  bool autotuning_ = false;
  bool sf_loaded_ = false;
  int32_t ff_target_q8_ = -1;  // input of the prepared feedforward (-1: none yet)
  uint16_t base_q16_ = 0;     // F0 with a measured model: its steady duty at ff_target_q8_, no fan
  uint16_t ff_no_fan_q16_ = 0;    // feedforward at ff_target_q8_ without the fan (0 when F0)
  uint16_t ff_fan_span_q16_ = 0;  // what the fan adds at 100 % airflow
  uint8_t ff_fan_ = 0;            // airflow ff_q16_ is for
  uint16_t ff_q16_ = 0;        // prepared feedforward duty (0 when M310 F0)
  bool ff_applied_ = false;    // the active controller holds its feedforward (PID with F1: model_ff_q16_)
  uint16_t model_ff_q16_ = 0;  // the model's duty the PID holds with F1
  bool reference_started_ = false;
  bool reference_holds_ = false;  // started by a take-over: the model holds the target
};

}  // namespace firmware
