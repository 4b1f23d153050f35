// How a number reads in a message: the one format of the numbers that errors and
// notes quote, below every part of the solver that writes a message.
#pragma once
#include <string>

namespace rodcore {

// x with `precision` significant digits (6: the run loop's and the integrators'
// messages; 17: round-trip exact, for values read from files).
std::string message_number(double x, int precision = 6);

}  // namespace rodcore
