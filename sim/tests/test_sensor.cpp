// The ADC injection must reproduce silicon's codes through simavr's different conversion.
#include <gtest/gtest.h>

#include <cmath>

#include "sim/sensor.h"

namespace sim {
namespace {

constexpr double kPullupOhm = 4700.0;

TEST(SimavrMillivolts, EveryCodeRoundTripsThroughSimavrsConversion) {
  for (uint32_t vref_mv : {5000u, 4997u, 3300u, 2560u, 1100u}) {
    for (int code = 0; code <= kAdcMaxCode; ++code) {
      const uint16_t mv = simavr_mv_for_code(code, vref_mv);
      ASSERT_EQ(simavr_code_for_mv(mv, vref_mv), code) << "vref " << vref_mv << " mV";
    }
  }
}

TEST(SimavrMillivolts, PicksTheMiddleOfTheBinSoNeighboursAreAtLeastOneMvAway) {
  for (int code = 1; code < kAdcMaxCode; ++code) {
    const uint16_t mv = simavr_mv_for_code(code, 5000);
    EXPECT_EQ(simavr_code_for_mv(mv - 1, 5000), code);
    EXPECT_EQ(simavr_code_for_mv(mv + 1, 5000), code);
  }
}

TEST(SiliconCode, RoundsAndClips) {
  EXPECT_EQ(silicon_code(511.49, 0.0), 511);
  EXPECT_EQ(silicon_code(511.5, 0.0), 512);
  EXPECT_EQ(silicon_code(1024.0, 0.0), 1023);  // open thermistor: V = Vref
  EXPECT_EQ(silicon_code(0.2, -3.0), 0);
}

TEST(ThermistorAdc, NoiseFreeGivesExactlySiliconsRoundedCode) {
  ThermistorAdc adc(thermistor::kEpcos100k, kPullupOhm, 0.0, 1);
  for (double t = 0.0; t <= 300.0; t += 0.37) {
    const double c = 1024.0 * thermistor::resistance_ohm(thermistor::kEpcos100k, t) /
                     (thermistor::resistance_ohm(thermistor::kEpcos100k, t) + kPullupOhm);
    const int expected = static_cast<int>(std::floor(c + 0.5));
    ASSERT_EQ(adc.sample_code(t), expected) << t << " °C";
    ASSERT_EQ(simavr_code_for_mv(adc.sample_mv(t, 5000), 5000), expected) << t << " °C";
  }
}

TEST(ThermistorAdc, NoisyCodesAverageToTheTrueMeanCode) {
  // Oversampling only gains resolution if the codes are unbiased: their mean must be c.
  const double sigma = 0.5;
  ThermistorAdc adc(thermistor::kEpcos100k, kPullupOhm, sigma, 42);
  const double t = 210.0;
  const double c = adc.mean_code(t);
  const int n = 200000;
  double sum = 0.0, sum_sq = 0.0;
  for (int i = 0; i < n; ++i) {
    const double code = adc.sample_code(t);
    sum += code;
    sum_sq += code * code;
  }
  const double mean = sum / n;
  const double sd = std::sqrt(sum_sq / n - mean * mean);
  EXPECT_NEAR(mean, c, 0.01);
  EXPECT_NEAR(sd, std::sqrt(sigma * sigma + 1.0 / 12.0), 0.02);  // noise plus quantisation
}

TEST(ThermistorAdc, FaultsPinTheCode) {
  ThermistorAdc adc(thermistor::kEpcos100k, kPullupOhm, 0.5, 3);
  adc.set_fault(SensorFault::kOpen);
  EXPECT_EQ(adc.sample_code(200.0), 1023);
  adc.set_fault(SensorFault::kShorted);
  EXPECT_LE(adc.sample_code(200.0), 2);
}

TEST(ThermistorAdc, TemperatureForCodeInvertsMeanCode) {
  ThermistorAdc adc(thermistor::kEpcos100k, kPullupOhm, 0.0, 1);
  for (double t : {25.0, 150.0, 210.0, 280.0})
    EXPECT_NEAR(adc.temperature_for_code(adc.mean_code(t)), t, 1e-6);
  EXPECT_TRUE(std::isnan(adc.temperature_for_code(0.0)));
  EXPECT_TRUE(std::isnan(adc.temperature_for_code(1024.0)));
}

}  // namespace
}  // namespace sim
