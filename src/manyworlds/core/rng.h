// A small, fast, portable random number generator.
//
// std::uniform_real_distribution and friends are implementation-defined, so
// the same seed can give different numbers with another standard library.
// Rng defines every distribution itself: a seed gives the same stream on
// every platform and compiler.
#ifndef MANYWORLDS_CORE_RNG_H_
#define MANYWORLDS_CORE_RNG_H_

#include <array>
#include <cstdint>

namespace manyworlds {

// xoshiro256** seeded through SplitMix64.
class Rng {
 public:
  using State = std::array<uint64_t, 4>;

  explicit Rng(uint64_t seed = 0) { Seed(seed); }

  void Seed(uint64_t seed);

  // Full generator state, for checkpoints.
  const State& state() const { return s_; }
  void set_state(const State& state) { s_ = state; }

  uint64_t NextU64();
  // Uniform in [0, 1) with 53 random bits.
  double Uniform();
  // Uniform in [low, high).
  double Uniform(double low, double high) { return low + (high - low) * Uniform(); }
  // Uniform integer in [0, n); n must be positive. Unbiased (Lemire's method).
  uint64_t UniformInt(uint64_t n);
  // Standard normal (Box-Muller; one value per call so no hidden state).
  double Normal();
  double Normal(double mean, double stddev) { return mean + stddev * Normal(); }
  bool Bernoulli(double p) { return Uniform() < p; }

  // Derives an independent child seed from this generator (for sub-streams).
  uint64_t DeriveSeed() { return NextU64(); }

 private:
  State s_{};
};

// Mixes a base seed and an index into a new seed (SplitMix64 finaliser), so
// that env i of a batch gets a seed independent of env i+1.
uint64_t MixSeed(uint64_t seed, uint64_t index);

}  // namespace manyworlds

#endif  // MANYWORLDS_CORE_RNG_H_
