#pragma once
// sciray reports bad input with one exception type whose message names the object,
// the parameter and the offending value ("mesh: index 7 of face 3 refers to vertex 9
// but there are 8 vertices"). The C API turns it into an error-callback call.
#include <stdexcept>
#include <string>

namespace sciray {

class Error : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

}  // namespace sciray
