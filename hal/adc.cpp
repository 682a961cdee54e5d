#include "hal/adc.h"

#include <avr/io.h>

#include "hal/critical_section.h"

namespace {

uint32_t g_sum;                   // ISR only: sum of this window's 10-bit codes (<= 130944)
volatile uint16_t g_window_adc_q6;  // last finished window, mean code x 64
volatile bool g_window_ready;

// ATmega2560 ADCSRB bit 3 is MUX5 (selects ADC8..15); the ATmega1284P has only ADC0..7 and
// never needs it. A constant rather than the MUX5 macro, which the 1284P header lacks.
constexpr uint8_t kMux5Bit = 3;

}  // namespace

namespace hal {
namespace adc {

void init(uint8_t channel) {
  ADMUX = static_cast<uint8_t>((1 << REFS0) | (channel & 0x07));  // AVcc reference
  if (channel >= 8) ADCSRB |= static_cast<uint8_t>(1 << kMux5Bit);
  // Enable, start, prescaler 128 (ADPS2:0 = 111).
  ADCSRA = (1 << ADEN) | (1 << ADSC) | (1 << ADPS2) | (1 << ADPS1) | (1 << ADPS0);
}

// Cycle budget ~45 (32-bit add). Reading ADC (ADCL then ADCH) before setting ADSC matters:
// simavr computes the result at the ADCL read from the selected channel; the mux never
// changes in this design, so simulator and silicon agree.
void on_tick(bool window_end) {
  g_sum += ADC;
  ADCSRA |= (1 << ADSC);
  if (window_end) {
    g_window_adc_q6 = static_cast<uint16_t>(g_sum >> 1);  // sum of 128 codes / 2 = mean x 64
    g_window_ready = true;
    g_sum = 0;
  }
}

bool window_ready() { return g_window_ready; }

bool take_window(uint16_t& adc_q6) {
  CriticalSection lock;  // 16-bit value written by the ISR
  if (!g_window_ready) return false;
  adc_q6 = g_window_adc_q6;
  g_window_ready = false;
  return true;
}

}  // namespace adc
}  // namespace hal
