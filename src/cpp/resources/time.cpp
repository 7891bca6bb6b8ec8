// Exact times (time.hpp), by the rules of src/base/exact-times.lisp.
Time Time::from_seconds_exact(double seconds) {
  // SECONDS = WHOLE + FRACTION exactly (modf), |FRACTION| < 1.  FRACTION * 1e6 =
  // PRODUCT + ERROR exactly (fma gives the rounding error), so a product that
  // lands on a half is resolved by the exact value's side of it, as Lisp's
  // (round (* (rational x) 1000000)) does; ties to even.
  if (!(std::fabs(seconds) < 4e18)) return seconds < 0 ? Time{} - never() : never();  // NaN: never
  double whole = 0;
  const double fraction = std::modf(seconds, &whole);
  const double product = fraction * 1e6;
  const double error = std::fma(fraction, 1e6, -product);
  double nearest = std::nearbyint(product);  // ties to even, the default rounding
  if (std::fabs(product - nearest) == 0.5) {
    if (error > 0) nearest = product + 0.5;
    else if (error < 0) nearest = product - 0.5;
  }
  const std::int64_t micros = static_cast<std::int64_t>(nearest);
  return Time{static_cast<std::int64_t>(whole), 0} + from_micros(micros);
}

std::string to_string(Time t) {
  const bool negative = t.seconds < 0;
  // The magnitude, whole seconds and microseconds, without overflowing.
  std::uint64_t whole = negative ? static_cast<std::uint64_t>(-(t.seconds + 1)) : static_cast<std::uint64_t>(t.seconds);
  std::int32_t micros = t.micros;
  if (negative) {
    if (micros == 0) ++whole;
    else micros = 1000000 - micros;
  }
  std::string text = (negative ? "-" : "") + std::to_string(whole);
  if (micros == 0) return text;
  std::string digits = std::to_string(micros);
  digits = std::string(6 - digits.size(), '0') + digits;
  while (digits.back() == '0') digits.pop_back();
  return text + "." + digits;
}

bool parse_time(const std::string& text, Time& out) {
  // Sign, digits [. digits] [e|E [sign] digits]: the significant digits and
  // the power of ten they are scaled by, then the microseconds cut out of them.
  std::size_t at = 0;
  bool negative = false;
  if (at < text.size() && (text[at] == '-' || text[at] == '+')) negative = text[at++] == '-';
  std::string digits;
  long scale = 0, count = 0;
  for (; at < text.size() && text[at] >= '0' && text[at] <= '9'; ++at, ++count) digits += text[at];
  if (at < text.size() && text[at] == '.')
    for (++at; at < text.size() && text[at] >= '0' && text[at] <= '9'; ++at, ++count, ++scale) digits += text[at];
  if (count == 0) return false;
  long exponent = 0;
  if (at < text.size() && (text[at] == 'e' || text[at] == 'E' || text[at] == 'd' || text[at] == 'D')) {
    ++at;
    bool exponent_negative = false;
    if (at < text.size() && (text[at] == '-' || text[at] == '+')) exponent_negative = text[at++] == '-';
    long exponent_count = 0;
    for (; at < text.size() && text[at] >= '0' && text[at] <= '9'; ++at, ++exponent_count)
      exponent = exponent < 100000 ? exponent * 10 + (text[at] - '0') : exponent;
    if (exponent_count == 0) return false;
    if (exponent_negative) exponent = -exponent;
  }
  if (at != text.size()) return false;
  const std::size_t first = digits.find_first_not_of('0');
  if (first == std::string::npos) {
    out = Time{};
    return true;
  }
  // VALUE = DIGITS * 10^SHIFT microseconds.
  digits.erase(0, first);
  const long shift = exponent - scale + 6;
  std::string integral = digits, rest;
  if (shift >= 0) {
    if (static_cast<long>(digits.size()) + shift > 23) return false;  // beyond 1e16 s
    integral.append(static_cast<std::size_t>(shift), '0');
  } else if (static_cast<long>(digits.size()) + shift <= 0) {
    integral = "0";
    rest = std::string(static_cast<std::size_t>(-shift) - digits.size(), '0') + digits;
  } else {
    integral = digits.substr(0, digits.size() - static_cast<std::size_t>(-shift));
    rest = digits.substr(digits.size() - static_cast<std::size_t>(-shift));
  }
  if (integral.size() > 22) return false;
  // Round REST off: above a half up, a half exactly to even.
  bool up = false;
  if (!rest.empty() && rest[0] >= '5') {
    up = rest[0] > '5' || rest.find_first_not_of('0', 1) != std::string::npos ||
         (integral.back() - '0') % 2 == 1;
  }
  // INTEGRAL microseconds: the last six digits, and the seconds before them.
  const std::size_t split = integral.size() > 6 ? integral.size() - 6 : 0;
  const std::uint64_t seconds = split ? std::stoull(integral.substr(0, split)) : 0;
  const std::int64_t micros = std::stoll(integral.substr(split)) + (up ? 1 : 0);
  if (seconds > 10000000000000000ULL) return false;
  Time magnitude = Time{static_cast<std::int64_t>(seconds), 0} + Time::from_micros(micros);
  out = negative ? Time{} - magnitude : magnitude;
  return true;
}
