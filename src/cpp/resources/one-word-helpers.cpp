// The one-hot state's operations (here on one word; the same names serve a
// state of several words).
[[maybe_unused]] StateBits with_delta(StateBits bits, StateBits mask, StateBits values) {
  return (bits & ~mask) | values;
}
[[maybe_unused]] bool bits_meet(StateBits a, StateBits b) { return (a & b) != 0; }
[[maybe_unused]] void add_bits(StateBits& into, StateBits bits) { into |= bits; }
[[maybe_unused]] StateBits common_bits(StateBits a, StateBits b) { return a & b; }
[[maybe_unused]] StateBits differing_bits(StateBits a, StateBits b) { return a ^ b; }

[[maybe_unused]] int field_index(std::uint64_t bits, int offset, int size) {
  for (int i = 0; i < size; ++i)
    if (bits >> (offset + i) & 1u) return i;
  return 0;  // unreachable for a valid one-hot state; 0 keeps every table index in bounds
}

