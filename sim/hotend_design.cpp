// hotend-design: state-feedback + feedforward design for a hotend model. Prints the discrete
// model, the poles asked for and achieved, L (with the dead-time predictor folded in), M, the
// observer gains, the fixed-point constants (C++ initializer and the firmware's M311 upload) and
// a closed-loop check of those constants on the continuous plant.
//   hotend-design --fopdt 450,24,20.7 | --second-order 450,14.17,28.33 | --two-node |
//                 --seed002 | --seed003 | --seed004 | --seed000-4 | --seed000-5   [options, --help]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "design/seed_models.h"
#include "design/plant_sim.h"
#include "control/state_feedback.h"
#include "design/state_feedback_format.h"
#include "control/state_feedback_gcode.h"
#include "design/state_feedback_quantize.h"

namespace {

using namespace design;

const char kUsage[] =
    "usage: hotend-design MODEL [options]\n"
    "models (K in kelvin per unit duty 0..1, times in seconds):\n"
    "  --fopdt K,T,TAU            first order plus dead time (seed002: 450,24,20.7);\n"
    "                             unsure of TAU? round it up: a real dead time shorter than\n"
    "                             the model's is harmless, a longer one overshoots\n"
    "  --second-order K,T1,T2     two lags in cascade (seed003: 450,14.17,28.33)\n"
    "  --two-node                 physical 40 W hotend (16.7 J/K block, 0.068-0.097 W/K loss)\n"
    "  --seed000-4 | --seed000-5  the identified state-space models, rescaled to 450 K\n"
    "  --seed002 | --seed003 | --seed004   the simulator's bank versions of the seeds (with its\n"
    "                             assumed part-fan loss, as --seed000-4/5)\n"
    "options:\n"
    "  --poles P1,P2,...          controller poles in 1/s, one per state; RE:IM = pair RE±IM·j\n"
    "  --observer-poles P,...     observer poles in 1/s, one per state plus the input bias\n"
    "  --rise-fraction F          closed-loop T = full-power rise time / F (default 16) ...\n"
    "  --no-search                ... without lowering F until the saturated step stays below\n"
    "  --overshoot K              ... this overshoot (default 0.2 K)\n"
    "  --step K                   design set-point step (default 185 K: 25 -> 210 C)\n"
    "  --bias-tc S                input-bias estimate time constant (default: rule)\n"
    "  --decimation N             law period N x 128 ms (default: smallest that fits)\n"
    "  --fan-loss L               duty lost per kelvin at 100 % fan (two-node: 7.25e-4)\n"
    "  --name IDENT               name of the emitted C++ constant (default kStateFeedback)\n"
    "  --target C                 closed-loop check target (default 210)\n"
    "  --initializer-only         print only the C++ initializer\n";

bool parse_list(const char* text, std::vector<double>* out) {
  out->clear();
  std::string s(text);
  size_t start = 0;
  while (start <= s.size()) {
    const size_t comma = s.find(',', start);
    const std::string item =
        s.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    char* end = nullptr;
    out->push_back(std::strtod(item.c_str(), &end));
    if (item.empty() || (*end != '\0' && *end != ':')) return false;
    if (*end == ':') out->push_back(1e300), out->push_back(std::strtod(end + 1, nullptr));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return true;
}

// "a,b:c" → poles a, b+cj, b−cj (1e300 marks a pair in parse_list's output).
int poles_from_list(const std::vector<double>& v, Cplx* poles, int cap) {
  int n = 0;
  for (size_t i = 0; i < v.size() && n < cap; ++i) {
    if (i + 2 < v.size() && v[i + 1] == 1e300) {
      if (n + 2 > cap) return -1;
      poles[n++] = {v[i], v[i + 2]};
      poles[n++] = {v[i], -v[i + 2]};
      i += 2;
    } else {
      poles[n++] = {v[i], 0};
    }
  }
  return n;
}

void print_matrix(const char* name, const Mat& m) {
  std::printf("%s =\n", name);
  for (int i = 0; i < m.rows; ++i) {
    std::printf("  [");
    for (int j = 0; j < m.cols; ++j) std::printf(" %13.6g", m(i, j));
    std::printf(" ]\n");
  }
}

void sort_poles(Cplx* p, int n) {  // by real part, then imaginary, descending
  for (int i = 1; i < n; ++i)
    for (int j = i;
         j > 0 && (p[j].re > p[j - 1].re || (p[j].re == p[j - 1].re && p[j].im > p[j - 1].im));
         --j) {
      const Cplx t = p[j];
      p[j] = p[j - 1];
      p[j - 1] = t;
    }
}

void print_poles(const char* name, const Cplx* wanted, int n, const Mat& closed, double ts) {
  Cplx got[kMatCap], z[kMatCap];
  const bool ok = eigenvalues(closed, got);
  for (int i = 0; i < n; ++i) z[i] = wanted[i];
  sort_poles(z, n);
  sort_poles(got, n);
  std::printf("%s (z; s = ln z / Ts):\n", name);
  for (int i = 0; i < n; ++i) {
    const double mag = std::sqrt(cabs2(z[i]));
    std::printf("  wanted %10.6f%+10.6fj (s %9.5f)   achieved %10.6f%+10.6fj\n", z[i].re, z[i].im,
                mag > 0 ? std::log(mag) / ts : -INFINITY, ok ? got[i].re : NAN,
                ok ? got[i].im : NAN);
  }
}

// Fixed-point constants on the continuous plant: heat from 25 C to the target.
void closed_loop_check(const LtiModel& m, const control::StateFeedbackConstants& k, double target_c) {
  control::StateFeedback sf;
  if (!sf.configure(k)) {
    std::printf("check: constants rejected by the runtime\n");
    return;
  }
  PlantSim plant(m);
  const double bound = full_power_rise_time(m, target_c - m.ambient_c) + m.delay_s;
  double peak = -1e9, settle = 0, duty_sum = 0;
  const double seconds = 4 * bound + 60;
  int n = 0;
  for (double t = 0; t < seconds; t += 0.128) {
    const control::StepInput in{static_cast<int32_t>(std::lround(target_c * 256)),
                                static_cast<int32_t>(std::lround(plant.measured_c() * 256)), 0};
    const uint16_t duty = sf.step(in);
    plant.run(duty / 65535.0, 0.128);
    peak = std::fmax(peak, plant.true_c() - target_c);
    if (std::fabs(plant.true_c() - target_c) > 1.0) settle = t + 0.128;
    if (t > seconds - 30) {
      duty_sum += duty / 655.35;
      ++n;
    }
  }
  std::printf("closed-loop check (fixed point, continuous plant, 25 -> %.0f C, no noise):\n",
              target_c);
  std::printf(
      "  overshoot %.2f K, settled into +-1 K at %.1f s (full power + dead time: %.1f s, ratio "
      "%.2f),\n"
      "  final %.3f C, final duty %.1f %%\n",
      peak, settle, bound, settle / bound, plant.true_c(), n ? duty_sum / n : 0.0);
}

}  // namespace

int main(int argc, char** argv) {
  LtiModel model;
  bool have_model = false;
  DesignOptions o;
  double fan_loss = -1, target_c = 210;
  const char* name = "kStateFeedback";
  bool initializer_only = false;
  std::vector<double> v;
  for (int i = 1; i < argc; ++i) {
    const char* a = argv[i];
    const char* val = i + 1 < argc ? argv[i + 1] : nullptr;
    auto need = [&](size_t count) {
      if (!val || !parse_list(val, &v) || (count && v.size() != count)) {
        std::fprintf(stderr, "hotend-design: bad or missing value for %s\n%s", a, kUsage);
        std::exit(2);
      }
      ++i;
    };
    if (!std::strcmp(a, "--help") || !std::strcmp(a, "-h")) {
      std::printf("%s", kUsage);
      return 0;
    } else if (!std::strcmp(a, "--fopdt")) {
      need(3);
      model = fopdt(v[0], v[1], v[2]);
      have_model = true;
    } else if (!std::strcmp(a, "--second-order")) {
      need(3);
      model = second_order(v[0], v[1], v[2]);
      have_model = true;
    } else if (!std::strcmp(a, "--two-node")) {
      model = two_node();
      have_model = true;
    } else if (!std::strcmp(a, "--seed002")) {
      model = seed002();
      have_model = true;
    } else if (!std::strcmp(a, "--seed003")) {
      model = seed003();
      have_model = true;
    } else if (!std::strcmp(a, "--seed004")) {
      model = seed004();
      have_model = true;
    } else if (!std::strcmp(a, "--seed000-4")) {
      model = seed000_4();
      have_model = true;
    } else if (!std::strcmp(a, "--seed000-5")) {
      model = seed000_5();
      have_model = true;
    } else if (!std::strcmp(a, "--poles")) {
      need(0);
      o.n_ctrl_poles = poles_from_list(v, o.ctrl_poles_s, kMaxAug);
    } else if (!std::strcmp(a, "--observer-poles")) {
      need(0);
      o.n_obs_poles = poles_from_list(v, o.obs_poles_s, kMaxAug);
    } else if (!std::strcmp(a, "--rise-fraction")) {
      need(1);
      o.rise_fraction = v[0];
    } else if (!std::strcmp(a, "--no-search")) {
      o.search_speed = false;
    } else if (!std::strcmp(a, "--initializer-only")) {
      initializer_only = true;
    } else if (!std::strcmp(a, "--overshoot")) {
      need(1);
      o.overshoot_limit_k = v[0];
    } else if (!std::strcmp(a, "--step")) {
      need(1);
      o.step_k = v[0];
    } else if (!std::strcmp(a, "--bias-tc")) {
      need(1);
      o.bias_tc_s = v[0];
    } else if (!std::strcmp(a, "--decimation")) {
      need(1);
      o.decimation = static_cast<int>(v[0]);
    } else if (!std::strcmp(a, "--fan-loss")) {
      need(1);
      fan_loss = v[0];
    } else if (!std::strcmp(a, "--target")) {
      need(1);
      target_c = v[0];
    } else if (!std::strcmp(a, "--name") && val) {
      name = val;
      ++i;
    } else {
      std::fprintf(stderr, "hotend-design: unknown argument %s\n%s", a, kUsage);
      return 2;
    }
  }
  if (!have_model) {
    std::fprintf(stderr, "hotend-design: no model given\n%s", kUsage);
    return 2;
  }
  if (fan_loss >= 0) model.fan_loss_per_k = fan_loss;
  if ((o.n_ctrl_poles && o.n_ctrl_poles != model.n) ||
      (o.n_obs_poles && o.n_obs_poles != model.n + 1)) {
    std::fprintf(stderr, "hotend-design: need %d controller and %d observer poles\n", model.n,
                 model.n + 1);
    return 2;
  }

  const Design d = design_state_feedback(model, o);
  if (d.error) {
    std::fprintf(stderr, "hotend-design: %s\n", d.error);
    return 1;
  }
  control::StateFeedbackConstants k;
  if (const char* err = quantize(d, model.fan_loss_per_k, &k)) {
    std::fprintf(stderr, "hotend-design: %s\n", err);
    return 1;
  }
  if (initializer_only) {
    print_initializer(stdout, k, name);
    return 0;
  }
  const int n = d.real.model.n;
  std::printf(
      "== continuous model (x in K above %.0f C, u = duty 0..1), dead time %.3f s, DC gain %.2f "
      "K\n",
      model.ambient_c, model.delay_s, d.dc_gain);
  print_matrix("A", model.a);
  print_matrix("B", model.b);
  print_matrix("C", model.c);
  std::printf("== realisation: %s\n", model.physical_states ? "physical states kept"
                                      : d.real.modal        ? "real modal form, C = 0/1"
                                                            : "output as a state");
  print_matrix("A (realised)", d.real.model.a);
  std::printf(
      "== discrete model: law period %d x 128 ms = %.3f s, dead time D = %d periods - %.3f s\n",
      d.decimation, d.ts_s, d.zoh.delay, d.zoh.frac_s);
  print_matrix("Phi", d.zoh.phi);
  print_matrix("Gamma_a (u[k-D])", d.zoh.gamma_a);
  print_matrix("Gamma_b (u[k-D+1])", d.zoh.gamma_b);
  std::printf(
      "== pole rule: dominant T %.1f s, full-power rise %.1f s (step %.0f K), slowest RHP zero "
      "%.4f /s, closed-loop T %.2f s\n",
      d.t_dom_s, d.t_rise_s, o.step_k, d.rhp_zero_s, d.t_cl_s);
  print_poles("controller poles", d.ctrl_poles_z, d.n_aug, d.phi_aug - d.gamma_aug * d.l_aug,
              d.ts_s);
  print_matrix("L (on [x; u[k-D]] when the delay is fractional)", d.l_aug);
  print_matrix("L_D = L Phi^D (law on the observer state)", d.lx);
  std::printf("h_j (on u[k-j], j = 1..%d):", d.zoh.delay);
  for (int j = 0; j < d.zoh.delay; ++j) std::printf("%s%.5g", j % 8 ? " " : "\n  ", d.h[j]);
  std::printf("\ng_d = %.6g (bias), M = %.6g (duty per K of set point)\n", d.g_d, d.m);
  print_poles("observer poles (x and input bias)", d.obs_poles_z, n + 1,
              d.phi_obs - d.k_obs * d.c_obs * d.phi_obs, d.ts_s);
  print_matrix("K (current observer)", d.k_obs);
  std::printf("worst saturated nominal overshoot, steps of 15..100 %% of %.0f K: %.3f K\n",
              o.step_k, worst_step_overshoot(d, o.step_k));

  std::printf("== fixed-point constants (formats: control/state_feedback_constants.h)\n");
  print_initializer(stdout, k, name);
  std::printf("== upload to the firmware (M311, docs/controllers.md; W1 checks and applies)\n");
  control::write_state_feedback_mcode(k, [](const char* line) { std::printf("%s\n", line); });
  closed_loop_check(model, k, target_c);
  return 0;
}
