#pragma once
// The ISAs the tests run every check on: all that this CPU executes, scalar included.
#include <vector>

#include "sciray/simd/arch.hpp"

namespace sciray::test_support {

inline std::vector<simd::Isa> supported_isas() {
  std::vector<simd::Isa> isas;
  for (auto isa : simd::all_isas)
    if (simd::cpu_supports(isa)) isas.push_back(isa);
  return isas;
}

}  // namespace sciray::test_support
