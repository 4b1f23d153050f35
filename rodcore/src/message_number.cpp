#include "rodcore/message_number.hpp"

#include <sstream>

namespace rodcore {

std::string message_number(double x, int precision) {
  std::ostringstream o;
  o.precision(precision);
  o << x;
  return o.str();
}

}  // namespace rodcore
