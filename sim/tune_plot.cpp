#include "sim/tune_plot.h"

#include "design/lti_model.h"
#include "design/plant_sim.h"

namespace sim {

std::vector<PlotSeries> tune_plot_series(const RunResult& r) {
  if (!r.tune || !r.tune->finished || r.tune->a <= 0 || r.tune->c <= 0) return {};
  const TuneOutcome& t = *r.tune;
  const double ambient = r.config.plant.ambient_c;
  design::LtiModel m = design::fopdt(t.a, t.c, t.d);
  m.fan_loss_per_k = t.f / 100.0 / t.a;  // K_fan = K / (1 + F/100)
  m.ambient_c = ambient;
  design::PlantSim model(m);
  PlotSeries plant{"hotend (true)", {}, {}, {}, {}};
  PlotSeries fit{"identified model M307 A" + std::to_string(int(t.a + 0.5)) + " C" + std::to_string(int(t.c + 0.5)) +
                     " D" + std::to_string(int(t.d + 0.5)),
                 {}, {}, {}, {}};
  bool started = false;
  for (const TraceSample& s : r.trace) {
    if (s.t_s < t.start_s) continue;
    if (!started) {  // the model starts at rest where the hotend is (hot starts too)
      const double hold = (s.true_c - ambient) / t.a;
      if (hold > 0) model.run(hold, 20.0 * t.c);
      started = true;
    }
    const double time = s.t_s - t.start_s;
    plant.time_s.push_back(time);
    plant.true_c.push_back(s.true_c);
    plant.target_c.push_back(s.target_c);
    plant.heater_duty.push_back(s.heater_duty);
    fit.time_s.push_back(time);
    fit.true_c.push_back(model.true_c());
    fit.target_c.push_back(s.target_c);
    fit.heater_duty.push_back(s.heater_duty);
    model.set_fan(s.fan_duty);
    model.run(s.heater_duty, 0.128);
  }
  return {plant, fit};
}

}  // namespace sim
