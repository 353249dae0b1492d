// A deterministic jitter for synthetic test data (split streams, sampled fields).
#pragma once

#include <cstdint>

namespace brittle {

/// Deterministic jitter in [-1, 1] (a fixed LCG: the same on every platform).
class Jitter {
 public:
  double operator()() {
    state_ = state_ * 6364136223846793005ULL + 1442695040888963407ULL;
    return static_cast<double>(state_ >> 11) / static_cast<double>(1ULL << 53) * 2.0 - 1.0;
  }

 private:
  std::uint64_t state_ = 12345;
};

}  // namespace brittle
