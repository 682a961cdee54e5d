// The exact (double) thermistor and divider models, and the constexpr ln/exp under them.
#include <gtest/gtest.h>

#include <cmath>

#include "control/thermistor_math.h"

namespace {

using thermistor::kEpcos100k;
using thermistor::kSemitec104gt2;

TEST(ConstexprMath, LnMatchesStdLogToDoublePrecision) {
  double worst = 0;
  for (double x = 1e-9; x < 1e9; x *= 1.0007) {
    worst = std::fmax(worst, std::fabs(cxmath::ln(x) - std::log(x)) / std::fmax(1.0, std::fabs(std::log(x))));
  }
  EXPECT_LT(worst, 1e-14);
  EXPECT_TRUE(std::isinf(cxmath::ln(0.0)));
  EXPECT_TRUE(std::isnan(cxmath::ln(-1.0)));
}

TEST(ConstexprMath, ExpMatchesStdExpToDoublePrecision) {
  double worst = 0;
  for (double x = -40; x < 40; x += 0.0013) {
    worst = std::fmax(worst, std::fabs(cxmath::exp(x) / std::exp(x) - 1.0));
  }
  EXPECT_LT(worst, 1e-13);
}

TEST(ConstexprMath, EvaluatesAtCompileTime) {
  constexpr double ln10 = cxmath::ln(10.0);
  static_assert(ln10 > 2.302585092994 && ln10 < 2.302585092995, "ln 10");
  constexpr double e = cxmath::exp(1.0);
  static_assert(e > 2.718281828459 && e < 2.718281828460, "e");
}

TEST(ThermistorMath, EpcosFitPassesThroughItsThreeDatasheetPoints) {
  EXPECT_NEAR(thermistor::temperature_c(kEpcos100k, 100000.0), 25.0, 1e-9);
  EXPECT_NEAR(thermistor::temperature_c(kEpcos100k, 1641.9), 150.0, 1e-9);
  EXPECT_NEAR(thermistor::temperature_c(kEpcos100k, 226.15), 250.0, 1e-9);
  EXPECT_GT(kEpcos100k.c, 0.0);  // resistance_ohm's monotonicity argument needs c ≥ 0
}

TEST(ThermistorMath, SemitecIsTheBetaModel) {
  for (double t_c = 0; t_c <= 300; t_c += 7.5) {
    const double t_k = t_c + 273.15;
    const double beta_r = 100000.0 * std::exp(4267.0 * (1.0 / t_k - 1.0 / 298.15));
    EXPECT_NEAR(thermistor::resistance_ohm(kSemitec104gt2, t_c) / beta_r, 1.0, 1e-12) << t_c;
  }
}

TEST(ThermistorMath, ResistanceIsTheExactInverseOfTemperature) {
  for (const thermistor::Sensor* s : {&kEpcos100k, &kSemitec104gt2}) {
    double prev_r = 1e300;
    for (double t_c = -40; t_c <= 400; t_c += 0.37) {
      const double r = thermistor::resistance_ohm(*s, t_c);
      EXPECT_NEAR(thermistor::temperature_c(*s, r), t_c, 1e-10) << t_c;
      EXPECT_LT(r, prev_r) << "NTC: resistance must fall as temperature rises, " << t_c;
      prev_r = r;
    }
  }
}

TEST(ThermistorMath, DividerCodeAndItsInverse) {
  // 100 kΩ against a 4.7 kΩ pull-up: 1024·100/104.7.
  EXPECT_NEAR(thermistor::divider_adc_code(100000.0, 4700.0), 978.0324737, 1e-6);
  for (double code = 0.5; code < 1023.6; code += 0.25) {
    const double r = thermistor::divider_resistance_ohm(code, 4700.0);
    EXPECT_NEAR(thermistor::divider_adc_code(r, 4700.0), code, 1e-9);
  }
}

}  // namespace
