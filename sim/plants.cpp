#include "sim/plants.h"

#include "design/seed_models.h"

#include <cmath>
#include <stdexcept>

namespace sim {
namespace {

// Every seed's heater is rescaled so that 100 % duty settles this far above ambient: a 40 W
// cartridge on a typical hotend (issue 2). The seeds' own gains are in their experiments' units.
constexpr double kFullPowerRiseK = 450.0;

// The part fan raises hotend40w's loss from 0.068 to 0.097 W/K at 100 % (issue 2's figures).
// The seeds identified no fan path; they get the same relative loss increase (our assumption,
// so that a fan step means the same thing on every plant).
constexpr double kFanLossIncrease = 0.097 / 0.068 - 1.0;

Matrix zeros_like(const Matrix& a) { return Matrix(a.rows(), a.cols()); }

// Fan as extra heat loss proportional to the (undelayed) temperature rise, fed back through the
// plant's own input path: u_eff = u − fan·Δ·C·x/K, i.e. A_fan = −Δ·B·C/K. For a FOPDT this is
// exactly a loss term on the lag (its gain drops to K/(1 + Δ) at full fan).
LtiModel with_fan_loss(LtiModel m) {
  m.a_fan = m.b * m.c * (-kFanLossIncrease / m.dc_gain_k());
  return m;
}

// K·e^(−τs)/(T·s + 1) as one state.
LtiModel fopdt(double gain_k, double lag_s, double delay_s) {
  LtiModel m;
  m.a = Matrix{{-1.0 / lag_s}};
  m.a_fan = zeros_like(m.a);
  m.b = Matrix{{gain_k / lag_s}};
  m.c = Matrix{{1.0}};
  m.delay_s = delay_s;
  m.physical_states = true;
  return m;
}

// K/((T1·s + 1)(T2·s + 1)) as two cascaded lags.
LtiModel second_order(double gain_k, double t1_s, double t2_s) {
  LtiModel m;
  m.a = Matrix{{-1.0 / t1_s, 0.0}, {1.0 / t2_s, -1.0 / t2_s}};
  m.a_fan = zeros_like(m.a);
  m.b = Matrix::column({gain_k / t1_s, 0.0});
  m.c = Matrix{{0.0, 1.0}};
  m.physical_states = true;
  return m;
}

// A seed state-space model with its input rescaled to the common full-power rise.
LtiModel rescaled_state_space(Matrix a, Matrix b, Matrix c) {
  LtiModel m;
  m.a = std::move(a);
  m.a_fan = zeros_like(m.a);
  m.b = std::move(b);
  m.c = std::move(c);
  m.b = m.b * (kFullPowerRiseK / m.dc_gain_k());
  return m;
}

// The seed's identified matrices, taken from design/seed_models.h (one copy of the
// paper's numbers for the design code and the simulator), with the input rescaled as above.
LtiModel rescaled_state_space(const design::LtiModel& seed) {
  const std::size_t n = static_cast<std::size_t>(seed.n);
  Matrix a(n, n), b(n, 1), c(1, n);
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) a(i, j) = seed.a(int(i), int(j));
    b(i, 0) = seed.b(int(i), 0);
    c(0, i) = seed.c(0, int(i));
  }
  return rescaled_state_space(std::move(a), std::move(b), std::move(c));
}


// Two thermal nodes: heater block (capacity C, heater P, loss h to ambient, h rising linearly
// with the part fan) and the thermistor, which follows the block with rate k.
LtiModel two_node(double capacity_j_per_k, double heater_w, double loss_w_per_k, double loss_fan_full_w_per_k,
                  double sensor_rate_per_s) {
  LtiModel m;
  m.a = Matrix{{-loss_w_per_k / capacity_j_per_k, 0.0}, {sensor_rate_per_s, -sensor_rate_per_s}};
  m.a_fan = Matrix{{-(loss_fan_full_w_per_k - loss_w_per_k) / capacity_j_per_k, 0.0}, {0.0, 0.0}};
  m.b = Matrix::column({heater_w / capacity_j_per_k, 0.0});
  m.c = Matrix{{0.0, 1.0}};
  m.physical_states = true;
  return m;
}

std::vector<PlantSpec> make_bank() {
  std::vector<PlantSpec> bank;
  // Physical model with published E3D-V6-class defaults (issue 2).
  bank.push_back({"hotend40w",
                  "two-node physical hotend: block 16.7 J/K, 40 W, loss 0.068 W/K (0.097 with "
                  "fan), sensor lag 0.22/s",
                  two_node(16.7, 40.0, 0.068, 0.097, 0.22)});
  // Seed 002 (FOPDT by the two-point method): T 24 s, τ 20.7 s.
  bank.push_back({"seed002", "FOPDT T 24 s, dead time 20.7 s (seed 002, fuzzy-PID patent)",
                  with_fan_loss(fopdt(kFullPowerRiseK, 24.0, 20.7))});
  // Seed 004: K·e^(−19.5 s)/(25.5 s + 1).
  bank.push_back({"seed004", "FOPDT T 25.5 s, dead time 19.5 s (seed 004, Gan Xinji et al.)",
                  with_fan_loss(fopdt(kFullPowerRiseK, 25.5, 19.5))});
  // Seed 003, graph method: T2 = 0.64·T, T1 = 0.5·T2 with T = 44.2696 s.
  bank.push_back({"seed003", "second order T1 14.17 s, T2 28.33 s (seed 003, Cojuhari et al.)",
                  with_fan_loss(second_order(kFullPowerRiseK, 14.1663, 28.3325))});
  // Seed 000/001 eq. (1): 4 states, identified on a Sanguinololu Prusa Mendel hotend.
  bank.push_back(
      {"seed000-4", "4-state identified model (seed 000 eq. 1, Surmak & Piotrowski)",
       with_fan_loss(rescaled_state_space(design::seed000_4_raw())),
       25.0, 150.0, 3600.0});
  // Seed 000/001 eq. (3): 5 states.
  bank.push_back(
      {"seed000-5", "5-state identified model (seed 000 eq. 3, Surmak & Piotrowski)",
       with_fan_loss(rescaled_state_space(design::seed000_5_raw())),
       25.0, 150.0, 3600.0});
  return bank;
}

}  // namespace

double LtiModel::dc_gain_k(double fan_duty) const {
  const Matrix x_ss = solve(a + a_fan * fan_duty, b);  // A·x = B, so x_ss = −A⁻¹B·u has sign −
  return -(c * x_ss)(0, 0);
}

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
      x_(spec.model.order(), 0.0),
      x_next_(spec.model.order(), 0.0),
      airflow_step_gain_(1.0 - std::exp(-dt_s / kFanSpinUpS)),
      zoh_by_fan_level_(kFanLevels + 1) {
  const double steps = spec.model.delay_s / dt_s;
  if (std::fabs(steps - std::round(steps)) > 1e-6)
    throw std::invalid_argument("plant step must divide the dead time of " + spec.name);
  delay_line_.assign(static_cast<std::size_t>(std::lround(steps)), 0.0);
}

const Discretised& Plant::zoh_for_fan_level(int level) {
  auto& slot = zoh_by_fan_level_[static_cast<std::size_t>(level)];
  if (!slot) {
    const LtiModel& m = spec_.model;
    const Matrix a = m.a + m.a_fan * (double(level) / kFanLevels);
    slot = std::make_unique<Discretised>(discretise_zoh(a, m.b, dt_s_));
  }
  return *slot;
}

void Plant::step(const PlantInput& in) {
  airflow_ += (in.fan_duty - airflow_) * airflow_step_gain_;
  const int fan_level = static_cast<int>(std::lround(airflow_ * kFanLevels));
  const Discretised& d = zoh_for_fan_level(fan_level);
  const std::size_t n = x_.size();
  for (std::size_t i = 0; i < n; ++i) {
    double v = d.gamma(i, 0) * in.heater_duty;
    for (std::size_t j = 0; j < n; ++j) v += d.phi(i, j) * x_[j];
    x_next_[i] = v;
  }
  x_.swap(x_next_);
  double rise = 0.0;
  for (std::size_t j = 0; j < n; ++j) rise += spec_.model.c(0, j) * x_[j];
  if (!delay_line_.empty()) {
    std::swap(rise, delay_line_[delay_index_]);  // the sensor sees C·x of `delay` ago
    delay_index_ = (delay_index_ + 1) % delay_line_.size();
  }
  rise_k_ = rise;
  ++steps_;
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
