// The one-hot state's operations, word by word.
[[maybe_unused]] StateBits with_delta(const StateBits& bits, const StateBits& mask, const StateBits& values) {
  StateBits result;
  for (int i = 0; i < kStateWords; ++i) result[i] = (bits[i] & ~mask[i]) | values[i];
  return result;
}
[[maybe_unused]] bool bits_meet(const StateBits& a, const StateBits& b) {
  for (int i = 0; i < kStateWords; ++i)
    if ((a[i] & b[i]) != 0) return true;
  return false;
}
[[maybe_unused]] void add_bits(StateBits& into, const StateBits& bits) {
  for (int i = 0; i < kStateWords; ++i) into[i] |= bits[i];
}
[[maybe_unused]] StateBits common_bits(const StateBits& a, const StateBits& b) {
  StateBits result;
  for (int i = 0; i < kStateWords; ++i) result[i] = a[i] & b[i];
  return result;
}
[[maybe_unused]] StateBits differing_bits(const StateBits& a, const StateBits& b) {
  StateBits result;
  for (int i = 0; i < kStateWords; ++i) result[i] = a[i] ^ b[i];
  return result;
}

[[maybe_unused]] int field_index(const StateBits& bits, int offset, int size) {
  for (int i = offset; i < offset + size; ++i)
    if (bits[i / 64] >> (i % 64) & 1u) return i - offset;
  return 0;  // unreachable for a valid one-hot state; 0 keeps every table index in bounds
}

