#include "sim/hotend_rig.h"

#include <algorithm>
#include <limits>

namespace sim {
namespace {

constexpr double kStepS = HotendRig::kStepUs * 1e-6;
// One trace sample per heater PWM period of the firmware (brief: 128 ticks of 1 ms, and the
// plant steps are aligned with the ticks): per-sample means of the true temperature and the
// duty are then free of the PWM ripple a single-lag model shows (±0.3 °C on seed002).
constexpr int kStepsPerTraceSample = 128;
// A T: report may describe the mean over the last control period (128 ms), printed up to one
// more period later: it is compared with the true temperature over this window before it.
constexpr double kReportLatencyS = 0.3;
constexpr double kInf = std::numeric_limits<double>::infinity();
// A detached thermistor lying in air: first-order lag towards ambient. EPCOS's glass-bead NTCs
// give ~10-20 s in still air; 15 s (our assumption, not measured).
constexpr double kDetachedLagS = 15.0;

}  // namespace

HotendRig::HotendRig(const BoardSpec& board, const PlantSpec& plant, const std::string& elf_path, double noise_lsb,
                     uint64_t seed)
    : board_(board, elf_path),
      plant_(plant, kStepS),
      adc_(thermistor::kEpcos100k, board.thermistor_pullup_ohm, noise_lsb, seed),
      reported_c_(std::numeric_limits<double>::quiet_NaN()),
      true_min_(kInf),
      true_max_(-kInf) {
  board_.set_adc_source(board.hotend_adc_channel, [this] {
    const int code = adc_.sample_code(sensed_c());
    code_sum_ += code;
    ++code_count_;
    return simavr_mv_for_code(code, board_.adc_ref_mv());
  });
  // The bed thermistor sits at ambient, so firmware that watches it sees a sane value.
  const double bed_code =
      ThermistorAdc(thermistor::kEpcos100k, board.thermistor_pullup_ohm, 0.0, 0).mean_code(plant.ambient_c);
  const uint16_t bed_mv = simavr_mv_for_code(silicon_code(bed_code, 0.0), board_.adc_ref_mv());
  board_.set_adc_source(board.bed_adc_channel, [bed_mv] { return bed_mv; });
  board_.every(kStepUs, [this] { step(); });
}

void HotendRig::step() {
  const uint64_t now_cycle = board_.cycle();
  const double now = board_.time_s();
  double heater = board_.heater().take_duty(now_cycle);
  double fan = board_.fan().take_duty(now_cycle);
  if (fault_ == FaultKind::kHeaterDead) heater = 0.0;
  if (fault_ == FaultKind::kStuckOn) heater = 1.0;
  if (fault_ == FaultKind::kQuarterPower) heater *= 0.25;
  if (fault_ == FaultKind::kFanStuck) fan = 1.0;
  if (fault_ == FaultKind::kDetached) detached_c_ += (plant_.spec().ambient_c - detached_c_) * (kStepS / kDetachedLagS);
  plant_.step(PlantInput{heater, fan});
  if (faulted_) block_peak_c_ = std::max(block_peak_c_, plant_.block_temperature_c());

  const double true_c = plant_.temperature_c();
  recent_true_.emplace_back(now, true_c);
  while (recent_true_.front().first < now - kReportLatencyS) recent_true_.pop_front();
  heater_sum_ += heater;
  fan_sum_ += fan;
  true_sum_ += true_c;
  true_min_ = std::min(true_min_, true_c);
  true_max_ = std::max(true_max_, true_c);
  if (++trace_steps_ == kStepsPerTraceSample) record_trace(now);
  if (step_work_) step_work_(now, true_c);
}

double HotendRig::report_error_c(const TempReport& report) const {
  if (recent_true_.empty()) return 0.0;
  double lo = recent_true_.front().second, hi = lo;
  for (const auto& sample : recent_true_) {
    lo = std::min(lo, sample.second);
    hi = std::max(hi, sample.second);
  }
  return std::max({0.0, lo - report.temp_c, report.temp_c - hi});
}

void HotendRig::mark_fault(FaultKind kind) {
  faulted_ = true;
  // One plant fault at a time (serve accepts several --fault): the first stays.
  if (!is_plant_fault(kind) || fault_ != FaultKind::kNone) return;
  fault_ = kind;
  detached_c_ = plant_.temperature_c();  // a detached thermistor starts from the block's reading
}

void HotendRig::record_trace(double now_s) {
  TraceSample s;
  s.t_s = now_s;
  s.true_c = true_sum_ / trace_steps_;
  if (faulted_) true_after_fault_.emplace_back(now_s, s.true_c);
  s.true_ripple_c = true_max_ - true_min_;
  s.sensor_c = code_count_ ? adc_.temperature_for_code(code_sum_ / code_count_)
                           : std::numeric_limits<double>::quiet_NaN();
  s.reported_c = reported_c_;
  s.target_c = target_c_;
  s.heater_duty = heater_sum_ / trace_steps_;
  s.fan_duty = fan_sum_ / trace_steps_;
  trace_.push_back(s);
  trace_steps_ = 0;
  heater_sum_ = fan_sum_ = code_sum_ = true_sum_ = 0.0;
  true_min_ = kInf;
  true_max_ = -kInf;
  code_count_ = 0;
}

}  // namespace sim
