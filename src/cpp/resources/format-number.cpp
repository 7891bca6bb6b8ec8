std::string format_number(double x) {
  if (std::isnan(x)) return "nan";
  if (std::isinf(x)) return x < 0 ? "-inf" : "inf";
  if (std::fabs(x) >= 1e16) return exponent_form(x);
  // Microseconds rounded half up, computed as Lisp computes them. |micros| < 2^74,
  // so the integral double is split at 2^32 into exact integers, then divided by 10^6.
  const double micros = std::floor(x * 1e6 + 0.5);
  const double magnitude = std::fabs(micros);
  const double high = std::floor(magnitude / 4294967296.0);
  const std::uint64_t high_part = static_cast<std::uint64_t>(high);
  const std::uint64_t low_part = static_cast<std::uint64_t>(magnitude - high * 4294967296.0);
  const std::uint64_t rest = high_part % 1000000 * 4294967296ULL + low_part;
  const std::uint64_t whole = high_part / 1000000 * 4294967296ULL + rest / 1000000;
  const std::uint64_t fraction = rest % 1000000;
  std::string text = (micros < 0 ? "-" : "") + std::to_string(whole);
  if (fraction == 0) return text;
  std::string digits = std::to_string(fraction);
  digits = std::string(6 - digits.size(), '0') + digits;
  while (digits.back() == '0') digits.pop_back();
  return text + "." + digits;
}

