// The engine for avx512, compiled with its own instruction-set flags.
#include "isa_kernels.hpp"

SCIRAY_DEFINE_ISA_KERNELS(sciray_kernels_avx512, xsimd::avx512bw, sciray::simd::Isa::avx512)
