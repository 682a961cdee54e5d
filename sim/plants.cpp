#include "sim/plants.h"

#include "design/seed_models.h"

#include <cmath>
#include <stdexcept>

namespace sim {
namespace {

std::vector<PlantSpec> make_bank() {
  using namespace design;
  std::vector<PlantSpec> bank;
  // Physical model with published E3D-V6-class defaults (issue 2); TwoNodeParams' defaults.
  bank.push_back({"hotend40w",
                  "two-node physical hotend: block 16.7 J/K, 40 W, loss 0.068 W/K (0.097 with "
                  "fan), sensor lag 0.22/s",
                  two_node()});
  // The seeds (design/seed_models.h): rescaled to a 450 K full-power rise, and given the
  // two-node hotend's relative fan loss (our assumption: the seeds identified no fan path).
  bank.push_back({"seed002", "FOPDT T 24 s, dead time 20.7 s (seed 002, fuzzy-PID patent)", seed002()});
  bank.push_back({"seed004", "FOPDT T 25.5 s, dead time 19.5 s (seed 004, Gan Xinji et al.)", seed004()});
  bank.push_back({"seed003", "second order T1 14.17 s, T2 28.33 s (seed 003, Cojuhari et al.)", seed003()});
  // Seed 000/001, identified on a Sanguinololu Prusa Mendel hotend.
  bank.push_back({"seed000-4", "4-state identified model (seed 000 eq. 1, Surmak & Piotrowski)",
                  seed000_4(), 25.0, 150.0, 3600.0});
  bank.push_back({"seed000-5", "5-state identified model (seed 000 eq. 3, Surmak & Piotrowski)",
                  seed000_5(), 25.0, 150.0, 3600.0});

  // Hotends the tune was not designed on (issue 7): heaters 30–80 W, time constants 30–300 s,
  // dead time or sensor lag 1–25 s. Two-node ones keep hotend40w's fan loss per watt of loss.
  TwoNodeParams p30;
  p30.heater_w = 30.0;
  bank.push_back({"hotend30w", "two-node hotend40w with a 30 W cartridge (441 K at 100 %)", two_node(p30)});
  TwoNodeParams p80;
  p80.heater_w = 80.0;
  bank.push_back({"hotend80w", "two-node hotend40w with an 80 W cartridge (1176 K at 100 %)", two_node(p80)});
  TwoNodeParams light;
  light.block_j_per_k = 6.0;
  light.sensor_rate_per_s = 1.0;
  bank.push_back({"light-fast", "light, fast block: 6 J/K, 40 W, sensor lag 1 s (T 88 s)", two_node(light)});
  TwoNodeParams heavy;
  heavy.block_j_per_k = 40.0;
  heavy.heater_w = 60.0;
  heavy.loss_w_per_k = 0.14;
  heavy.loss_fan_w_per_k = 0.14 * 0.097 / 0.068;  // the same relative fan loss as hotend40w
  heavy.sensor_rate_per_s = 1.0 / 25.0;
  bank.push_back({"heavy-slow", "heavy, slow block: 40 J/K, 60 W, loss 0.14 W/K (0.20 with fan), sensor lag 25 s",
                  two_node(heavy)});
  LtiModel delayed = two_node();
  delayed.delay_s = 5.0;
  bank.push_back({"hotend40w-delay5", "hotend40w with its thermistor behind a 5 s transport delay", delayed});
  bank.push_back({"fopdt-fast", "FOPDT T 30 s, dead time 1 s (450 K)", with_seed_fan(fopdt(kSeedRiseK, 30.0, 1.0))});
  bank.push_back({"fopdt-slow", "FOPDT T 300 s, dead time 10 s (450 K)", with_seed_fan(fopdt(kSeedRiseK, 300.0, 10.0))});
  bank.push_back({"fopdt-delay25", "FOPDT T 120 s, dead time 25 s (450 K)", with_seed_fan(fopdt(kSeedRiseK, 120.0, 25.0))});
  // seed002 with a 2 s thermistor lag behind the block, its dead time shortened to 18.7 s so that
  // dead time + lag is seed002's 20.7 s: its M303 used to take the lag for a longer block (C
  // +19 %) and overshoot ~20 °C after U1 (docs/autotune.md, "A dead time behind a thermistor lag").
  bank.push_back({"seed002-lag2", "seed002 with a 2 s thermistor lag: T 24 s, lag 2 s, dead time 18.7 s (450 K)",
                  with_seed_fan(second_order(kSeedRiseK, 24.0, 2.0, 18.7))});
  return bank;
}

}  // namespace

const std::vector<PlantSpec>& plant_bank() {
  static const std::vector<PlantSpec> bank = make_bank();
  return bank;
}

const PlantSpec* find_plant(const std::string& name) {
  for (const PlantSpec& p : plant_bank())
    if (p.name == name) return &p;
  return nullptr;
}

Plant::Plant(const PlantSpec& spec, double dt_s)
    : spec_(spec),
      dt_s_(dt_s),
      x_(static_cast<std::size_t>(spec.model.n), 0.0),
      x_next_(static_cast<std::size_t>(spec.model.n), 0.0),
      airflow_step_gain_(1.0 - std::exp(-dt_s / kFanSpinUpS)),
      zoh_by_fan_level_(kFanLevels + 1) {
  const double steps = spec.model.delay_s / dt_s;
  if (std::fabs(steps - std::round(steps)) > 1e-6)
    throw std::invalid_argument("plant step must divide the dead time of " + spec.name);
  delay_line_.assign(static_cast<std::size_t>(std::lround(steps)), 0.0);
}

const design::ExpIntegral& Plant::zoh_for_fan_level(int level) {
  auto& slot = zoh_by_fan_level_[static_cast<std::size_t>(level)];
  if (!slot) {
    const design::LtiModel& m = spec_.model;
    const design::Mat a = design::a_with_fan(m, double(level) / kFanLevels);
    slot = std::make_unique<design::ExpIntegral>(design::exp_and_integral(a, m.b, dt_s_));
  }
  return *slot;
}

void Plant::step(const PlantInput& in) {
  airflow_ += (in.fan_duty - airflow_) * airflow_step_gain_;
  const int fan_level = static_cast<int>(std::lround(airflow_ * kFanLevels));
  const design::ExpIntegral& d = zoh_for_fan_level(fan_level);
  const std::size_t n = x_.size();
  for (std::size_t i = 0; i < n; ++i) {
    const int r = static_cast<int>(i);
    double v = d.gamma(r, 0) * in.heater_duty;
    for (std::size_t j = 0; j < n; ++j) v += d.phi(r, static_cast<int>(j)) * x_[j];
    x_next_[i] = v;
  }
  x_.swap(x_next_);
  double rise = 0.0;
  for (std::size_t j = 0; j < n; ++j) rise += spec_.model.c(0, static_cast<int>(j)) * x_[j];
  undelayed_rise_k_ = rise;
  if (!delay_line_.empty()) {
    std::swap(rise, delay_line_[delay_index_]);  // the sensor sees C·x of `delay` ago
    delay_index_ = (delay_index_ + 1) % delay_line_.size();
  }
  rise_k_ = rise;
  ++steps_;
}

double Plant::block_temperature_c() const {
  const design::LtiModel& m = spec_.model;
  // Physical models (FOPDT, lags in cascade, two-node) take the heater into state 0.
  if (m.physical_states) return spec_.ambient_c + x_[0];
  return spec_.ambient_c + undelayed_rise_k_;
}

std::vector<double> full_power_step_response_k(const PlantSpec& spec, double dt_s, std::size_t steps) {
  Plant plant(spec, dt_s);
  std::vector<double> rise(steps);
  for (double& r : rise) {
    plant.step(PlantInput{1.0, 0.0});
    r = plant.temperature_c() - spec.ambient_c;
  }
  return rise;
}

}  // namespace sim
