#pragma once
// A number of the tool's JSON inputs as the float the engine keeps. nlohmann's get<float>()
// turns a double beyond float's range into an infinity (a conversion C++ leaves undefined),
// which would reach the scene as a silently wrong value: such a number is refused instead.
#include <cmath>
#include <limits>
#include <sstream>
#include <string>

#include <nlohmann/json.hpp>

#include "sciray/error.hpp"

namespace sciray_tool {

/// `v`, a JSON number that fits a float; `what` names it in the error otherwise.
inline float json_float(const nlohmann::json& v, const std::string& what) {
  if (!v.is_number()) throw sciray::Error(what + " must be a number");
  const double d = v.get<double>();
  if (!(std::abs(d) <= std::numeric_limits<float>::max())) {
    std::ostringstream shown;
    shown << d;
    throw sciray::Error(what + ": " + shown.str() + " does not fit a float");
  }
  return static_cast<float>(d);
}

}  // namespace sciray_tool
