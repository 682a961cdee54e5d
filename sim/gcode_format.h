// Numbers as hosts type them in G-code: plain decimals (G-code parsers need not accept
// exponents), trailing zeros dropped.
#pragma once

#include <cstdio>
#include <string>

namespace sim {

// 6 places by default: finer than any Q-format the firmware stores (gains Q16, model Q8).
inline std::string format_decimal(double value, int places = 6) {
  char text[48];
  std::snprintf(text, sizeof text, "%.*f", places, value);
  std::string s = text;
  if (s.find('.') != std::string::npos) {
    while (s.back() == '0') s.pop_back();
    if (s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

}  // namespace sim
