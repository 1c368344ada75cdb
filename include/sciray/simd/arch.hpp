#pragma once
// The instruction sets sciray is compiled for, their names, and which this CPU runs.
// Each packet ISA maps to one xsimd architecture tag (simd/packet.hpp); `scalar` is the
// one-lane reference path that every packet path is tested against.
#include <array>
#include <optional>
#include <string>
#include <string_view>

#include "sciray/error.hpp"

namespace sciray::simd {

/// The one-lane architecture: plain floats, the readable reference implementation.
struct scalar {
  static constexpr const char* name() { return "scalar"; }
};

enum class Isa { scalar, sse42, avx2, avx512 };

/// Every ISA sciray knows, from the widest down.
inline constexpr std::array<Isa, 4> all_isas{Isa::avx512, Isa::avx2, Isa::sse42, Isa::scalar};

constexpr std::string_view isa_name(Isa isa) {
  switch (isa) {
    case Isa::scalar: return "scalar";
    case Isa::sse42: return "sse4.2";
    case Isa::avx2: return "avx2";
    case Isa::avx512: return "avx512";
  }
  return "unknown";
}

constexpr int isa_width(Isa isa) {
  switch (isa) {
    case Isa::scalar: return 1;
    case Isa::sse42: return 4;
    case Isa::avx2: return 8;
    case Isa::avx512: return 16;
  }
  return 1;
}

inline std::optional<Isa> parse_isa(std::string_view name) {
  for (Isa isa : all_isas)
    if (isa_name(isa) == name) return isa;
  if (name == "sse42") return Isa::sse42;
  return std::nullopt;
}

/// Whether this CPU (and the OS, which must save the wider registers) executes the
/// instructions `isa` is compiled with; libgcc's check covers both.
inline bool cpu_supports(Isa isa) {
  switch (isa) {
    case Isa::scalar: return true;
    case Isa::sse42: return __builtin_cpu_supports("sse4.2");
    case Isa::avx2: return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
    case Isa::avx512:
      return __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512cd") &&
             __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512bw") &&
             __builtin_cpu_supports("avx512vl");
  }
  return false;
}

/// The widest ISA for which `supports` holds (by default: that this CPU runs).
inline Isa best_supported_isa(bool (*supports)(Isa) = cpu_supports) {
  for (Isa isa : all_isas)
    if (supports(isa)) return isa;
  return Isa::scalar;
}

/// Resolves a user's ISA request: "auto" (or empty) picks the best the CPU runs;
/// naming one the CPU lacks, or an unknown name, is an error that says what exists.
inline Isa resolve_isa(std::string_view request, bool (*supports)(Isa) = cpu_supports) {
  if (request.empty() || request == "auto") return best_supported_isa(supports);
  const auto isa = parse_isa(request);
  if (!isa)
    throw Error("unknown ISA '" + std::string(request) + "' (expected auto, avx512, avx2, sse4.2 or scalar)");
  if (!supports(*isa))
    throw Error("ISA '" + std::string(request) + "' is not supported by this CPU (best available: " +
                std::string(isa_name(best_supported_isa(supports))) + ")");
  return *isa;
}

}  // namespace sciray::simd
