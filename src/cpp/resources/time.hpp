/// A time or a duration, exact to the microsecond over Player's whole range:
/// |t| <= 1e15 s is 1e21 us, past a 64-bit integer, so whole SECONDS (the
/// floor) and MICROS in [0, 1000000) are kept apart (-0.25 s is {-1, 750000}).
/// Player's Lisp keeps the same integer microseconds, so both print alike.
struct Time {
  std::int64_t seconds = 0;
  std::int32_t micros = 0;
  /// US microseconds (any sign).
  static constexpr Time from_micros(std::int64_t us) {
    std::int64_t whole = us / 1000000, rest = us % 1000000;
    if (rest < 0) { rest += 1000000; --whole; }
    return Time{whole, static_cast<std::int32_t>(rest)};
  }
  /// SECONDS (finite) as the nearest microsecond of its exact binary value, ties to even.
  /// Inline for the usual case (a duration a presenter returns, per op): under 1e9 s
  /// the product with 1e6 is within 1/16 of the exact one, so when it lies within
  /// 1/4 of a whole microsecond that is the nearest; the rest go the exact way.
  static Time from_seconds(double seconds) {
    const double product = seconds * 1e6;
    if (product > -1e15 && product < 1e15) {
      const std::int64_t nearest = static_cast<std::int64_t>(product + (product < 0 ? -0.5 : 0.5));
      const double off = product - static_cast<double>(nearest);
      if (off < 0.25 && off > -0.25) return from_micros(nearest);
    }
    return from_seconds_exact(seconds);
  }
  /// FROM_SECONDS the exact way: modf and fma, for large values and near-ties.
  static Time from_seconds_exact(double seconds);
  /// Later than any time a controller reaches.
  static constexpr Time never() { return Time{INT64_C(4000000000000000000), 0}; }
  /// Seconds as a double: whole seconds plus micros / 1e6, as Player's Lisp converts them.
  double to_double() const { return static_cast<double>(seconds) + static_cast<double>(micros) / 1e6; }
  explicit operator double() const { return to_double(); }
};
constexpr Time operator+(Time a, Time b) {
  Time sum{a.seconds + b.seconds, a.micros + b.micros};
  if (sum.micros >= 1000000) { sum.micros -= 1000000; ++sum.seconds; }
  return sum;
}
constexpr Time operator-(Time a, Time b) {
  Time difference{a.seconds - b.seconds, a.micros - b.micros};
  if (difference.micros < 0) { difference.micros += 1000000; --difference.seconds; }
  return difference;
}
constexpr bool operator==(Time a, Time b) { return a.seconds == b.seconds && a.micros == b.micros; }
constexpr bool operator!=(Time a, Time b) { return !(a == b); }
constexpr bool operator<(Time a, Time b) {
  return a.seconds < b.seconds || (a.seconds == b.seconds && a.micros < b.micros);
}
constexpr bool operator>(Time a, Time b) { return b < a; }
constexpr bool operator<=(Time a, Time b) { return !(b < a); }
constexpr bool operator>=(Time a, Time b) { return !(a < b); }
/// T as Player's trace prints a time: whole seconds, then up to six decimals,
/// trailing zeros dropped (1.5, 123456789012.000001, -0.25).
std::string to_string(Time t);
/// TEXT, an exact decimal (digits, an optional fraction, an optional exponent:
/// 1e15, 1.5E-3), into OUT to the nearest microsecond, ties to even, never
/// through a double; false when TEXT is not one or lies beyond 1e16 s.
bool parse_time(const std::string& text, Time& out);
