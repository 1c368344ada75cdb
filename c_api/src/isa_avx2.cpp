// The engine for avx2, compiled with its own instruction-set flags.
#include "isa_kernels.hpp"

SCIRAY_DEFINE_ISA_KERNELS(sciray_kernels_avx2, xsimd::avx2, sciray::simd::Isa::avx2)
