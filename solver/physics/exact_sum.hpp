// An exact sum of doubles (docs/parallel.md, "Sums"): every double is a multiple of 2^-1074,
// so a sum of doubles is an integer multiple of 2^-1074 that fits in about 2,100 bits. It is
// kept exactly, in 32-bit digits held in 64-bit words (carries are settled only now and then),
// and rounded once when read. The result does not depend on the order of the additions: the
// energy budget has the same bits on any number of threads and of MPI ranks.
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>

namespace brittle {

class ExactSum {
 public:
  ExactSum() = default;
  explicit ExactSum(double x) { add(x); }

  /// Adds x exactly (a NaN, or infinities of both signs, make the sum NaN).
  void add(double x) {
    if (x == 0.0) return;
    if (!std::isfinite(x)) {
      special_ |= std::isnan(x) ? kNan : (x > 0 ? kPlusInf : kMinusInf);
      return;
    }
    std::uint64_t bits;
    std::memcpy(&bits, &x, sizeof bits);
    const bool negative = bits >> 63;
    int exponent = static_cast<int>((bits >> 52) & 0x7ff);
    std::uint64_t mantissa = bits & ((std::uint64_t(1) << 52) - 1);
    if (exponent != 0)
      mantissa |= std::uint64_t(1) << 52;
    else
      exponent = 1;  // subnormal: mantissa x 2^-1074
    // x = mantissa x 2^(exponent - 1075): its lowest bit is bit (exponent - 1) above 2^-1074.
    const int position = exponent - 1, word = position >> 5, shift = position & 31;
    const unsigned __int128 shifted = static_cast<unsigned __int128>(mantissa) << shift;
    const std::int64_t d0 = static_cast<std::int64_t>(shifted & 0xffffffffu),
                       d1 = static_cast<std::int64_t>((shifted >> 32) & 0xffffffffu),
                       d2 = static_cast<std::int64_t>(shifted >> 64);
    if (negative) {
      words_[word] -= d0, words_[word + 1] -= d1, words_[word + 2] -= d2;
    } else {
      words_[word] += d0, words_[word + 1] += d1, words_[word + 2] += d2;
    }
    if (++pending_ >= kSettleEvery) settle();
  }

  /// Adds another exact sum (exactly).
  void add(const ExactSum& other) {
    ExactSum o = other;
    o.settle();
    settle();
    for (int i = 0; i < kWords; ++i) words_[i] += o.words_[i];
    special_ |= o.special_;
    pending_ = 1;
  }

  ExactSum& operator+=(double x) {
    add(x);
    return *this;
  }
  ExactSum& operator+=(const ExactSum& o) {
    add(o);
    return *this;
  }

  /// The sum, rounded to a double (within an ulp; always the same double for the same sum).
  double value() const {
    if (special_ & kNan || (special_ & kPlusInf && special_ & kMinusInf))
      return std::numeric_limits<double>::quiet_NaN();
    if (special_ & kPlusInf) return std::numeric_limits<double>::infinity();
    if (special_ & kMinusInf) return -std::numeric_limits<double>::infinity();
    ExactSum s = *this;
    s.settle();
    const bool negative = s.words_[kWords - 1] < 0;
    if (negative) {
      for (std::int64_t& w : s.words_) w = -w;
      s.settle();
    }
    int top = kWords - 1;
    while (top >= 0 && s.words_[top] == 0) --top;
    if (top < 0) return 0.0;
    double r = 0.0;
    for (int i = top; i >= 0 && i >= top - 2; --i)
      r += std::ldexp(static_cast<double>(s.words_[i]), 32 * i - 1074);
    return negative ? -r : r;
  }

  /// Digits in [0, 2^32) below the top word, which keeps the sign; the same value.
  void settle() {
    for (int i = 0; i + 1 < kWords; ++i) {
      const std::int64_t carry = words_[i] >> 32;  // floor division by 2^32
      words_[i] -= carry * (std::int64_t(1) << 32);
      words_[i + 1] += carry;
    }
    pending_ = 0;
  }

  /// The settled words, for sending (MPI) and checkpoints; from_words undoes it.
  static constexpr int kWords = 68;
  using Words = std::array<std::int64_t, kWords + 1>;
  Words words() const {
    ExactSum s = *this;
    s.settle();
    Words w;
    std::copy(s.words_.begin(), s.words_.end(), w.begin());
    w[kWords] = s.special_;
    return w;
  }
  static ExactSum from_words(const Words& w) {
    ExactSum s;
    std::copy(w.begin(), w.begin() + kWords, s.words_.begin());
    s.special_ = static_cast<int>(w[kWords]);
    s.pending_ = 1;
    return s;
  }

 private:
  // 2^-1074 .. 2^1024 is 2,098 bits: 66 digits, +2 for the span of one addition and carries.
  std::array<std::int64_t, kWords> words_{};
  int pending_ = 0;  ///< additions since the last settle (each adds < 2^32 to a word)
  int special_ = 0;
  static constexpr int kSettleEvery = 1 << 30;
  static constexpr int kNan = 1, kPlusInf = 2, kMinusInf = 4;
};

}  // namespace brittle
