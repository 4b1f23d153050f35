// One exception type for everything a user can get wrong or that goes wrong
// numerically. The message is the whole story: what, where, what to try.
#pragma once
#include <stdexcept>
#include <string>

namespace rodcore {

struct Error : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Bad input (scene file, IC file, arguments). rodsim exits with status 2.
struct InputError : Error {
  using Error::Error;
};

// Bad numbers during a run (NaN, step underflow, drift, CFL, folding).
// rodsim exits with status 3; frames written before it remain readable.
struct NumericalError : Error {
  using Error::Error;
};

}  // namespace rodcore
