// Runtime values compare as Lisp's EQL does: 0.0 and -0.0 differ.
[[maybe_unused]] bool same_value(long long a, long long b) { return a == b; }
[[maybe_unused]] bool same_value(double a, double b) {
  return a == b && std::signbit(a) == std::signbit(b);
}

// X (finite, |X| >= 1e16) as Lisp prints a double: the shortest digits that
// read back as X, in exponent form with at least one decimal: 1.0e16, -2.5e20.
std::string exponent_form(double x) {
  char buffer[32];
  const std::to_chars_result written =
      std::to_chars(buffer, buffer + sizeof buffer, x, std::chars_format::scientific);
  const std::string text(buffer, written.ptr);
  const std::size_t e = text.find('e');
  std::string mantissa = text.substr(0, e);
  if (mantissa.find('.') == std::string::npos) mantissa += ".0";
  std::string exponent = text.substr(e + 1);
  if (exponent[0] == '+') exponent.erase(0, 1);
  return mantissa + "e" + exponent;
}

