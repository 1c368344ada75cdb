// The engine for sse42, compiled with its own instruction-set flags.
#include "isa_kernels.hpp"

SCIRAY_DEFINE_ISA_KERNELS(sciray_kernels_sse42, xsimd::sse4_2, sciray::simd::Isa::sse42)
