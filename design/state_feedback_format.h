// Text forms of StateFeedbackConstants for the design tool: a C++ initializer (to compile a
// default into the firmware) and the flat field walk (index, name, value) that the firmware's
// M311 upload (control/state_feedback_gcode.h) follows. Host-side (stdio), header-only.
#pragma once

#include <stdio.h>

#include "control/state_feedback_constants.h"

namespace design {

// Visits every field in struct order with a flat index (arrays at full capacity): the M311
// layout. f(index, name, value).
template <class F>
void for_each_field(const control::StateFeedbackConstants& k, F f) {
  int i = 0;
  f(i++, "n", k.n);
  f(i++, "output_mask", k.output_mask);
  f(i++, "delay", k.delay);
  f(i++, "decimation", k.decimation);
  f(i++, "input_shift", k.input_shift);
  f(i++, "ambient_q8", static_cast<long>(k.ambient_q8));
  for (int r = 0; r < control::kSfMaxStates; ++r) f(i++, "phi_diag", k.phi_diag[r]);
  for (int r = 0; r < control::kSfMaxStates; ++r) f(i++, "phi_off", k.phi_off[r]);
  for (int r = 0; r < control::kSfMaxStates; ++r) f(i++, "phi_col", k.phi_col[r]);
  for (int r = 0; r < control::kSfMaxStates; ++r) f(i++, "gamma_a", k.gamma_a[r]);
  for (int r = 0; r < control::kSfMaxStates; ++r) f(i++, "gamma_b", k.gamma_b[r]);
  for (int r = 0; r < control::kSfMaxStates; ++r) f(i++, "phi_shift", k.phi_shift[r]);
  for (int r = 0; r <= control::kSfMaxStates; ++r) f(i++, "obs_gain", k.obs_gain[r]);
  for (int r = 0; r <= control::kSfMaxStates; ++r) f(i++, "obs_shift", k.obs_shift[r]);
  for (int r = 0; r < control::kSfMaxStates; ++r) f(i++, "fb_gain", k.fb_gain[r]);
  f(i++, "ff_gain", k.ff_gain);
  f(i++, "bias_gain", k.bias_gain);
  f(i++, "ctrl_shift", k.ctrl_shift);
  for (int r = 0; r < control::kSfMaxDelay; ++r) f(i++, "fir", k.fir[r]);
  f(i++, "fir_shift", k.fir_shift);
  f(i++, "fan_gain", k.fan_gain);
  f(i++, "fan_shift", k.fan_shift);
  for (int r = 0; r < control::kSfMaxStates; ++r) f(i++, "ss_share", k.ss_share[r]);
  f(i++, "ss_share_shift", k.ss_share_shift);
  f(i++, "inv_gain", k.inv_gain);
  f(i++, "inv_gain_shift", k.inv_gain_shift);
}

inline void print_array(FILE* out, const char* name, const int16_t* v, int count) {
  fprintf(out, "    /* %s */ {", name);
  for (int i = 0; i < count; ++i) fprintf(out, "%s%d", i ? ", " : "", v[i]);
  fprintf(out, "},\n");
}

inline void print_array(FILE* out, const char* name, const uint8_t* v, int count) {
  fprintf(out, "    /* %s */ {", name);
  for (int i = 0; i < count; ++i) fprintf(out, "%s%d", i ? ", " : "", v[i]);
  fprintf(out, "},\n");
}

// Brace initializer in field order, e.g. for a constexpr default compiled into the firmware.
inline void print_initializer(FILE* out, const control::StateFeedbackConstants& k, const char* name) {
  fprintf(out, "constexpr control::StateFeedbackConstants %s = {\n", name);
  fprintf(out,
          "    /* n, output_mask, delay, decimation, input_shift, ambient_q8 */ %d, %d, %d, %d, "
          "%d, %ld,\n",
          k.n, k.output_mask, k.delay, k.decimation, k.input_shift,
          static_cast<long>(k.ambient_q8));
  print_array(out, "phi_diag", k.phi_diag, control::kSfMaxStates);
  print_array(out, "phi_off", k.phi_off, control::kSfMaxStates);
  print_array(out, "phi_col", k.phi_col, control::kSfMaxStates);
  print_array(out, "gamma_a", k.gamma_a, control::kSfMaxStates);
  print_array(out, "gamma_b", k.gamma_b, control::kSfMaxStates);
  print_array(out, "phi_shift", k.phi_shift, control::kSfMaxStates);
  print_array(out, "obs_gain", k.obs_gain, control::kSfMaxStates + 1);
  print_array(out, "obs_shift", k.obs_shift, control::kSfMaxStates + 1);
  print_array(out, "fb_gain", k.fb_gain, control::kSfMaxStates);
  fprintf(out, "    /* ff_gain, bias_gain, ctrl_shift */ %d, %d, %d,\n", k.ff_gain, k.bias_gain,
          k.ctrl_shift);
  print_array(out, "fir", k.fir, control::kSfMaxDelay);
  fprintf(out, "    /* fir_shift, fan_gain, fan_shift */ %d, %d, %d,\n", k.fir_shift, k.fan_gain,
          k.fan_shift);
  print_array(out, "ss_share", k.ss_share, control::kSfMaxStates);
  fprintf(out, "    /* ss_share_shift, inv_gain, inv_gain_shift */ %d, %d, %d};\n",
          k.ss_share_shift, k.inv_gain, k.inv_gain_shift);
}

}  // namespace design
