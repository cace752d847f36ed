// The engine's error types (the CLI's exit codes, app/main.cpp):
//   InputError       bad input (case file, --set): exit 2, before anything is computed;
//   SimulationError  the run cannot go on (NaN, collapsing dt, ...): exit 3;
//   IoError          output cannot be written or read (full disk, unreadable restart): exit 3.
#pragma once
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

}  // namespace sph
