// The engine's error types (the CLI's exit codes, app/main.cpp):
//   InputError       bad input (case file, --set): exit 2, before anything is computed;
//   SimulationError  the run cannot go on (NaN, collapsing dt, ...): exit 3;
//   IoError          output cannot be written or read (full disk, unreadable restart): exit 3.
#pragma once
#include <bit>
#include <cstdint>
#include <stdexcept>

namespace sph {

class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class SimulationError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class IoError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// x is neither NaN nor infinite, read from its bits: stays a real test in files compiled
/// with -ffinite-math-only (the float pair passes), where std::isfinite may fold to true.
inline bool finite_bits(double x) {
  return (std::bit_cast<std::uint64_t>(x) & 0x7ff0000000000000ULL) != 0x7ff0000000000000ULL;
}

}  // namespace sph
