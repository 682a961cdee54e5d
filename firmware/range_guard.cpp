#include "firmware/range_guard.h"

namespace firmware {

static_assert(RangeLimits::kMaxTempAdcQ6 < RangeLimits::kMinTempAdcQ6, "NTC: hot reads low");

Fault RangeGuard::classify(uint16_t adc_q6, int32_t temp_q8) {
  if (adc_q6 >= RangeLimits::kMinTempAdcQ6 || temp_q8 < RangeLimits::kMinTempQ8) return Fault::kMinTemp;
  if (adc_q6 <= RangeLimits::kMaxTempAdcQ6 || temp_q8 > RangeLimits::kMaxTempQ8) return Fault::kMaxTemp;
  return Fault::kNone;
}

Fault RangeGuard::update(uint16_t adc_q6, int32_t temp_q8) {
  last_ = classify(adc_q6, temp_q8);
  if (last_ == Fault::kNone) {
    bad_count_ = 0;
    return Fault::kNone;
  }
  if (bad_count_ < RangeLimits::kBadReadingsToTrip) ++bad_count_;
  return bad_count_ >= RangeLimits::kBadReadingsToTrip ? last_ : Fault::kNone;
}

}  // namespace firmware
