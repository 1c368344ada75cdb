#pragma once
// Image operations the frame buffer applies to the colour it outputs (never to what it
// accumulates, so they can change without losing frames).
//
// `tonemapper`, as OSPRay's: the generic filmic curve of Lottes (2016, "Advanced
// Techniques and Optimization of HDR Color Pipelines"),
//   f(x) = x^a / (x^(a d) b + c),
// with contrast a and shoulder d, and b, c solved so that f(midIn) = midOut and
// f(hdrMax) = 1 (c clamped at 0 to keep the curve continuous, b then re-solved for the
// mid point). The defaults fit the ACES 1.0 greyscale curve; with acesColor the curve
// runs in ACES AP1 space (OSPRay's input and output matrices), otherwise per channel
// in linear RGB. The result is clamped to [0, 1]; exposure scales the input first.
//
// `debug`, as OSPRay's: the red channel set to 1, a visible mark that frames pass the
// image operations.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numbers>
#include <string>
#include <type_traits>
#include <variant>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"

namespace sciray {

struct TonemapperParams {
  float exposure = 1.f;
  float contrast = 1.6773f;
  float shoulder = 0.9714f;
  float mid_in = 0.18f;    ///< midIn
  float mid_out = 0.18f;   ///< midOut
  float hdr_max = 11.0785f;  ///< hdrMax: the input that maps to 1
  bool aces_color = true;  ///< acesColor
};

class Tonemapper {
public:
  explicit Tonemapper(const TonemapperParams& p = {}) : exposure_(p.exposure), aces_(p.aces_color) {
    const auto check = [](bool ok, const char* name, const char* requirement, float value) {
      if (!ok)
        throw Error(std::string("tonemapper: '") + name + "' must be " + requirement + ", got " +
                    std::to_string(value));
    };
    check(p.exposure >= 0.f && std::isfinite(p.exposure), "exposure", "finite and not negative", p.exposure);
    check(p.contrast > 0.f && std::isfinite(p.contrast), "contrast", "positive", p.contrast);
    check(p.shoulder > 0.f && p.shoulder <= 1.f, "shoulder", "in (0, 1]", p.shoulder);
    check(p.mid_in > 0.f && p.mid_in <= 1.f, "midIn", "in (0, 1]", p.mid_in);
    check(p.mid_out > 0.f && p.mid_out <= 1.f, "midOut", "in (0, 1]", p.mid_out);
    check(p.hdr_max >= 1.f && std::isfinite(p.hdr_max), "hdrMax", "finite and at least 1", p.hdr_max);
    check(p.hdr_max > p.mid_in, "hdrMax", "greater than midIn", p.hdr_max);
    // Solved in double: the powers of hdrMax span many orders of magnitude.
    const double a = p.contrast, d = p.shoulder, m = p.mid_in, n = p.mid_out, w = p.hdr_max;
    const double m_ad = std::pow(m, a * d), m_a = std::pow(m, a), w_ad = std::pow(w, a * d), w_a = std::pow(w, a);
    const double c = std::max((m_ad * n * w_a - m_a * w_ad) / (m_ad * n - n * w_ad), 0.0);
    const double b = (m_a - n * c) / (n * m_ad);
    a_ = p.contrast;
    ad_ = p.contrast * p.shoulder;
    b_ = static_cast<float>(b);
    c_ = static_cast<float>(c);
  }

  /// Tone maps linear RGB (T = float or a packet); negative inputs count as 0.
  template <class T>
  Vec3<T> operator()(const Vec3<T>& linear) const {
    Vec3<T> x = max(linear * T(exposure_), splat(T(0.f)));
    if (aces_) x = mul(aces_input, x);
    x = {curve(x.x), curve(x.y), curve(x.z)};
    if (aces_) x = mul(aces_output, x);
    return min(max(x, splat(T(0.f))), splat(T(1.f)));
  }

  float b() const { return b_; }
  float c() const { return c_; }

private:
  // Rows of OSPRay's matrices. Input: RRT_SAT * XYZ_to_AP1 * D65_to_D60 * Rec709_to_XYZ;
  // output: XYZ_to_Rec709 * D60_to_D65 * AP1_to_XYZ * ODT_SAT.
  static constexpr float aces_input[3][3] = {{0.5972782409f, 0.3545713181f, 0.0482176639f},
                                             {0.0760130499f, 0.9083220973f, 0.0156579968f},
                                             {0.0284085382f, 0.1338243154f, 0.8375684636f}};
  static constexpr float aces_output[3][3] = {{1.6047539945f, -0.5310794927f, -0.0736720338f},
                                              {-0.1020831870f, 1.1081322801f, -0.0060518756f},
                                              {-0.0032670420f, -0.0727552477f, 1.0760219533f}};

  template <class T>
  static Vec3<T> mul(const float (&m)[3][3], const Vec3<T>& v) {
    return {T(m[0][0]) * v.x + T(m[0][1]) * v.y + T(m[0][2]) * v.z,
            T(m[1][0]) * v.x + T(m[1][1]) * v.y + T(m[1][2]) * v.z,
            T(m[2][0]) * v.x + T(m[2][1]) * v.y + T(m[2][2]) * v.z};
  }

  template <class T>
  T curve(const T& x) const {
    const T denominator = pow_positive(x, ad_) * T(b_) + T(c_);
    // 0 / 0 where x = 0 and c = 0: the curve starts at 0.
    return simd::select(x > T(0.f), pow_positive(x, a_) / denominator, T(0.f));
  }

  /// x^e for x > 0 (other lanes get a finite value the caller discards). Packets take
  /// exp2(e log2 x) with a log2 of their own: xsimd 8.1's log and pow do not compile for
  /// AVX-512BW without optimization (-O0: its integer select casts fail).
  /// log2 x = exponent + 2 atanh(t) / ln 2 with t = (m - 1) / (m + 1) for the mantissa m
  /// in [sqrt(1/2), sqrt(2)), |t| < 0.172: five odd terms leave 4e-10.
  template <class T>
  static T pow_positive(const T& x, float e) {
    if constexpr (std::is_same_v<T, float>) {
      return std::pow(x, e);
    } else {
      using I = xsimd::batch<std::int32_t, typename T::arch_type>;
      const I bits = xsimd::bitwise_cast<I>(x);
      T exponent = xsimd::to_float((bits >> 23) - I(127));
      T m = xsimd::bitwise_cast<T>((bits & I(0x007fffff)) | I(0x3f800000));
      const auto above = m > T(1.41421356f);
      m = simd::select(above, m * T(0.5f), m);
      exponent = simd::select(above, exponent + T(1.f), exponent);
      const T t = (m - T(1.f)) / (m + T(1.f)), t2 = t * t;
      const T series = t * (T(1.f) + t2 * (T(1.f / 3) + t2 * (T(1.f / 5) + t2 * (T(1.f / 7) + t2 * T(1.f / 9)))));
      const T log2_x = exponent + series * T(2.f / std::numbers::ln2_v<float>);
      return xsimd::exp2(log2_x * T(e));
    }
  }

  float exposure_;
  bool aces_;
  float a_ = 1.f, ad_ = 1.f, b_ = 1.f, c_ = 0.f;
};

/// OSPRay's `debug` image operation.
struct DebugMark {
  template <class T>
  Vec3<T> operator()(const Vec3<T>& rgb) const {
    return {T(1.f), rgb.y, rgb.z};
  }
};

/// One of the image operations a frame buffer applies, in order, to the colour it outputs.
using ImageOperation = std::variant<Tonemapper, DebugMark>;

}  // namespace sciray
