// The settings M500 stores and M503 reports (besides the state-feedback constants, which the
// controller bank keeps): PID gains (M301), hotend model (M307), controller choice and
// feedforward switch (M310), fuzzy-PID configuration (M312). Hardware-free (host-tested).
#pragma once
#include <stdint.h>

#include "control/feedforward.h"
#include "control/fuzzy_pid.h"
#include "control/pid.h"

namespace firmware {

enum class ControllerId : uint8_t { kPid = 0, kStateFeedback = 1, kFuzzyPid = 2, kMarlinPid = 3 };
constexpr uint8_t kControllerCount = 4;

// Build-time default controller: `cmake -DHOTEND_DEFAULT_CONTROLLER=<n>` (both builds pass it).
constexpr uint8_t kDefaultController = HOTEND_DEFAULT_CONTROLLER;
static_assert(kDefaultController < kControllerCount, "HOTEND_DEFAULT_CONTROLLER: 0 PID, 2 fuzzy-PID, 3 Marlin PID");
static_assert(kDefaultController != static_cast<uint8_t>(ControllerId::kStateFeedback),
              "HOTEND_DEFAULT_CONTROLLER=1: state feedback needs uploaded constants (M311); select it with "
              "M310 S1 and store it with M500 instead");

constexpr uint16_t kControlPeriodMs = 128;  // brief: 128 ticks of 1 ms

// Where Settings::model came from (Settings::model_tuned; M570 S sets it as is, M503 prints it).
// Any measured model (1–4) feeds the PID family's part-fan term also with M310 F0; only a tight
// one (1) arms the model check's tight threshold (M570 T). Fuzzy-PID with F0 follows the model's
// heat-up on 1, 3 and 4, PID with F0 on 4. M303 marks a hot start's or an unsure tune's model
// loose (2; with fitted lags 4, below): its C may be
// read long, and a long C keeps full power on too long (2 is also what older firmware stored for
// any loose model, so an old EEPROM block keeps its behaviour). A lag-dominated hotend's model is
// 3: its FOPDT reaches full slope sooner than the lags do, good for a heat-up, not for a fault.
// 4 is an unsure tune whose record fit two lags (seed000): M307 is their two-point FOPDT, 3 in
// every respect, and PID F0 follows its heat-up too (docs/controllers.md: by feedback alone a PI
// on 600–1,200 s lags crept in or wound up; on heavy-slow's lag-dominated model (3) the heat-up
// overshot 16 °C, so not there). An M307 edit makes any model the user's (1): PID F0 is then
// feedback alone again, until M570 S4.
enum ModelSource : uint8_t {
  kModelDefault = 0,
  kModelMeasured = 1,
  kModelMeasuredLoose = 2,
  kModelMeasuredLag = 3,
  kModelFittedLags = 4
};

struct Settings {
  control::PidGains pid;          // M301, Marlin units Q16 (S0, S2 around them, S3)
  control::HotendModel model;     // M307 (feedforward of S0, S2, S3)
  uint8_t controller;             // M310 S: a ControllerId
  uint8_t feedforward;            // M310 F: 1 = model feedforward on
  uint8_t fuzzy_spread_pct;       // M312 S: fuzzy schedule spans M301 × (1 ∓ spread)
  uint16_t fuzzy_e_factor_q12;    // M312 E: universe units per °C, Q12
  uint16_t fuzzy_ec_factor_q12;   // M312 C: universe units per °C/s, Q12
  uint8_t model_tuned;            // a ModelSource: default, measured, loose, lag-dominated, fitted lags
  uint8_t protect_tuned_c;        // M570 T: model check's evidence threshold, °C, tuned model
  uint8_t protect_default_c;      // M570 U: the same with the default model
  uint16_t watch_period_s;        // M570 P: the model-free heating watch's window, s
};

// M570's ranges (docs/protection.md).
constexpr int32_t kProtectMinC = 2, kProtectMaxC = 60;
constexpr int32_t kWatchMinPeriodS = 20, kWatchMaxPeriodS = 600;
bool protection_valid(const Settings& s);

Settings default_settings();

// M312's limits, Q12, chosen so the Error line prints them exactly: the e factor at least 0.03
// /°C (FuzzyPid needs ≥ 0.024); the ec factor's per-period gain (× 1000/128) must fit 16 bits:
// ≤ 2.04 s/°C. The schedule spans M301 × (1 ∓ spread) with spread ≤ 100 %.
constexpr uint8_t kMaxFuzzySpreadPct = 100;
constexpr int32_t kMinEFactorQ12 = 123;     // 0.03 (prints as the bound it is)
constexpr int32_t kMaxEFactorQ12 = 65495;   // 15.99
constexpr int32_t kMinEcFactorQ12 = 41;     // 0.01
constexpr int32_t kMaxEcFactorQ12 = 8356;   // 2.04

// The per-field ranges every way settings come in shares (M301/M307/M310/M312 through the
// controller bank, M501 and boot from EEPROM): true if each field is within what its G-code
// accepts. The combined checks (gains the fixed-point PID and the fuzzy schedule can hold, S1
// needing constants) are the bank's (ControllerBank::apply).
bool settings_fields_in_range(const Settings& s);

// The fuzzy-PID configuration these settings describe (fuzzy_config_around M301).
control::FuzzyPidConfig fuzzy_config(const Settings& s);

}  // namespace firmware
