// Run-time ISA selection, and the scalar reference path (compiled with baseline flags).
#include <cstdlib>
#include <string>

#include "isa_kernels.hpp"

extern "C" const sciray::shim::IsaKernels* sciray_kernels_sse42();
extern "C" const sciray::shim::IsaKernels* sciray_kernels_avx2();
extern "C" const sciray::shim::IsaKernels* sciray_kernels_avx512();

namespace sciray::shim {

const IsaKernels& kernels(simd::Isa isa) {
  if (!simd::cpu_supports(isa))
    throw Error("ISA '" + std::string(simd::isa_name(isa)) + "' is not supported by this CPU");
  switch (isa) {
    case simd::Isa::avx512: return *sciray_kernels_avx512();
    case simd::Isa::avx2: return *sciray_kernels_avx2();
    case simd::Isa::sse42: return *sciray_kernels_sse42();
    case simd::Isa::scalar: break;
  }
  static const IsaKernels scalar_kernels = make_kernels<simd::scalar>(simd::Isa::scalar);
  return scalar_kernels;
}

simd::Isa select_isa(std::string_view request) {
  if (request.empty() || request == "auto") {
    if (const char* env = std::getenv("SCIRAY_ISA"); env && *env) {
      try {
        return simd::resolve_isa(env);
      } catch (const Error& e) {
        throw Error(std::string("SCIRAY_ISA: ") + e.what());
      }
    }
  }
  return simd::resolve_isa(request);
}

}  // namespace sciray::shim
