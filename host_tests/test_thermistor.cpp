// The compile-time thermistor table and its interpolated lookup, against the exact double model.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "control/thermistor.h"

namespace {

using thermistor::Entry;
using thermistor::Sensor;
using thermistor::Table;
constexpr int kN = thermistor::kDefaultTableSize;
constexpr uint32_t kPullupOhm = 4700;  // both boards (issue 2)

template <int N>
int32_t lookup(const Table<N>& t, uint16_t adc_q6) {
  return thermistor::adc_q6_to_temp_q8([&t](uint8_t i) { return t.entry[i]; }, N, adc_q6);
}

double exact_c(const Sensor& s, double adc_q6) {
  return thermistor::temperature_c(s, thermistor::divider_resistance_ohm(adc_q6 / 64.0, kPullupOhm));
}

// Worst |lookup − exact| (°C) over every adc_q6 whose exact temperature lies in 0–300 °C.
template <int N>
double worst_error_c(const Table<N>& t, const Sensor& s) {
  const double q_cold = 64 * thermistor::divider_adc_code(thermistor::resistance_ohm(s, 0.0), kPullupOhm);
  const double q_hot = 64 * thermistor::divider_adc_code(thermistor::resistance_ohm(s, 300.0), kPullupOhm);
  double worst = 0;
  for (int q = int(std::ceil(q_hot)); q <= int(std::floor(q_cold)); ++q) {
    worst = std::fmax(worst, std::fabs(lookup(t, uint16_t(q)) / 256.0 - exact_c(s, q)));
  }
  return worst;
}

// The firmware's tables, as the compiler builds them (constexpr: no run-time code).
constexpr Table<kN> kEpcosTable = thermistor::make_table<kN>(thermistor::kEpcos100k, kPullupOhm);
constexpr Table<kN> kSemitecTable = thermistor::make_table<kN>(thermistor::kSemitec104gt2, kPullupOhm);
// The same tables computed in 32-bit float, as avr-gcc 5.4 (double = IEEE single) computes them.
// Checked once: bit-identical to the tables in an avr-g++ -mmcu=atmega2560 image (see report).
constexpr Table<kN> kEpcosTableAvr = thermistor::make_table<kN>(thermistor::epcos100k<float>(), kPullupOhm);
constexpr Table<kN> kSemitecTableAvr =
    thermistor::make_table<kN>(thermistor::semitec104gt2<float>(), kPullupOhm);

static_assert(kEpcosTable.entry[0].adc_q6 < kEpcosTable.entry[kN - 1].adc_q6, "hottest entry first");

TEST(Thermistor, EpcosWithinATenthOfADegreeFrom0To300C) {
  const double worst = worst_error_c(kEpcosTable, thermistor::kEpcos100k);
  std::printf("EPCOS B57560G104F, %d entries: max |error| %.4f °C\n", kN, worst);
  EXPECT_LE(worst, 0.1);
  EXPECT_LE(worst_error_c(kEpcosTableAvr, thermistor::kEpcos100k), 0.1);
}

TEST(Thermistor, SemitecWithinATenthOfADegreeFrom0To300C) {
  const double worst = worst_error_c(kSemitecTable, thermistor::kSemitec104gt2);
  std::printf("Semitec 104GT-2, %d entries: max |error| %.4f °C\n", kN, worst);
  EXPECT_LE(worst, 0.1);
  EXPECT_LE(worst_error_c(kSemitecTableAvr, thermistor::kSemitec104gt2), 0.1);
}

TEST(Thermistor, TheAccuracyCheckCanFail) {
  // 16 entries cannot follow the curve to 0.1 °C: if this passed, the measurement would be blind.
  constexpr Table<16> coarse = thermistor::make_table<16>(thermistor::kEpcos100k, kPullupOhm);
  EXPECT_GT(worst_error_c(coarse, thermistor::kEpcos100k), 0.1);
  // The wrong sensor's table is off by degrees.
  EXPECT_GT(worst_error_c(kSemitecTable, thermistor::kEpcos100k), 1.0);
}

void expect_exact_at_keys(const Table<kN>& t, const Sensor& s) {
  for (int i = 0; i < kN; ++i) {
    const Entry& e = t.entry[i];
    EXPECT_NEAR(e.temp_q8 / 256.0, exact_c(s, e.adc_q6), 0.5 / 256 + 1e-9) << i;
    EXPECT_EQ(lookup(t, e.adc_q6), e.temp_q8) << i;
    if (i > 0) {
      EXPECT_GT(e.adc_q6, t.entry[i - 1].adc_q6) << i;
    }
  }
}

TEST(Thermistor, EntriesAreExactAtTheirKeys) {
  expect_exact_at_keys(kEpcosTable, thermistor::kEpcos100k);
  expect_exact_at_keys(kSemitecTable, thermistor::kSemitec104gt2);
}

TEST(Thermistor, LookupIsMonotonicOverEveryCode) {
  for (const auto* table : {&kEpcosTable, &kSemitecTable}) {
    int32_t previous = INT32_MAX;
    for (uint32_t q = 0; q <= 0xFFFF; ++q) {
      const int32_t t = lookup(*table, uint16_t(q));
      ASSERT_LE(t, previous) << "adc_q6 " << q;
      previous = t;
    }
  }
}

TEST(Thermistor, ReadingsBeyondTheTableClampToItsEnds) {
  // Shorted thermistor (code ≈ 0) reads as the hot end, open (code ≈ 1023) as the cold end.
  EXPECT_EQ(lookup(kEpcosTable, 0), kEpcosTable.entry[0].temp_q8);
  EXPECT_EQ(lookup(kEpcosTable, 0xFFFF), kEpcosTable.entry[kN - 1].temp_q8);
  EXPECT_NEAR(lookup(kEpcosTable, 0) / 256.0, thermistor::kTableHotC, 0.05);
  EXPECT_NEAR(lookup(kEpcosTable, 0xFFFF) / 256.0, thermistor::kTableColdC, 0.05);
  EXPECT_EQ(lookup(kSemitecTable, 65472), kSemitecTable.entry[kN - 1].temp_q8);  // 1023 × 64
}

}  // namespace
