// The simulated printer without its host: the firmware image on a board, the hotend plant on its
// heater and fan pins, the thermistor on its ADC channel (the bed's at ambient), stepped every
// simulated millisecond, and the trace the metrics and CSV are made from. `run` drives it with a
// scripted host, `serve` with a real one over a pseudo-terminal.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "sim/avr_board.h"
#include "sim/board_spec.h"
#include "sim/fault_outcome.h"
#include "sim/host_session.h"
#include "sim/metrics.h"
#include "sim/plant_model.h"
#include "sim/plants.h"
#include "sim/sensor.h"

namespace sim {

class HotendRig {
 public:
  static constexpr uint32_t kStepUs = 1000;  // the plant (and the host's work) every simulated ms

  HotendRig(const BoardSpec& board, const PlantSpec& plant, const std::string& elf_path, double noise_lsb,
            uint64_t seed);
  HotendRig(const HotendRig&) = delete;
  HotendRig& operator=(const HotendRig&) = delete;

  // Work after each plant step (simulated seconds since power-on, the true temperature).
  void on_step(std::function<void(double now_s, double true_c)> work) { step_work_ = std::move(work); }

  // What the trace records beside the plant: the host's last target and the last T: value.
  void set_target(double target_c) { target_c_ = target_c; }
  void set_reported(double reported_c) { reported_c_ = reported_c; }
  // |reported − true| beyond the true range over the report's latency window (0 inside it).
  double report_error_c(const TempReport& report) const;

  // A fault from now on (issue 8's hardware faults act on the plant: a detached thermistor cools
  // in air, a dead / stuck-on / quarter-power heater, a stuck fan); the block's peak and the
  // true temperature are recorded from here for the fault's outcome.
  void mark_fault(FaultKind kind);
  double block_peak_c() const { return block_peak_c_; }
  const std::vector<std::pair<double, double>>& true_after_fault() const { return true_after_fault_; }

  AvrBoard& board() { return board_; }
  const AvrBoard& board() const { return board_; }
  ThermistorAdc& sensor() { return adc_; }
  const std::vector<TraceSample>& trace() const { return trace_; }

 private:
  void step();
  void record_trace(double now_s);
  // What the thermistor sees: the plant's sensor node, or its own temperature once detached.
  double sensed_c() const { return fault_ == FaultKind::kDetached ? detached_c_ : plant_.temperature_c(); }

  AvrBoard board_;
  Plant plant_;
  ThermistorAdc adc_;
  std::function<void(double, double)> step_work_;
  std::vector<TraceSample> trace_;
  std::deque<std::pair<double, double>> recent_true_;  // (t, true °C) over the report latency
  double target_c_ = 0.0;
  double reported_c_;
  bool faulted_ = false;
  FaultKind fault_ = FaultKind::kNone;  // the plant fault acting (kNone: none, or not a plant fault)
  double detached_c_ = 0.0;             // the detached thermistor's own temperature
  double block_peak_c_ = -1e9;
  std::vector<std::pair<double, double>> true_after_fault_;  // (t, true °C) per trace sample
  // Accumulators over one trace sample.
  int trace_steps_ = 0;
  double heater_sum_ = 0.0, fan_sum_ = 0.0, true_sum_ = 0.0, true_min_, true_max_;
  double code_sum_ = 0.0;
  int code_count_ = 0;
};

}  // namespace sim
