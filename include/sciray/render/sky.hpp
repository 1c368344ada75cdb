#pragma once
// OSPRay's `sunSky` light: a clear sky after the Hosek-Wilkie model (RGB version, its
// coefficients in render/sky_data.hpp) as an environment map, plus the sun as a distant
// light of 0.53 degrees. As in OSPRay the sky is tabulated at 512 x 256 directions and
// read bilinearly, the sun never sets (below the horizon it stays on it, at its
// azimuth), and `horizon_extension` fades the sky out below the horizon over that
// fraction of the lower hemisphere.
//
// The sun's spectral radiance is not Hosek and Wilkie's solar model (whose spectral
// tables sciray does not ship) but a compact physical estimate: the Sun as a 5778 K
// black body, attenuated along the Kasten-Young (1989) air mass by Rayleigh scattering
// (optical depth 0.008735 um^-4.08, Leckner 1978) and aerosols (Angstrom exponent 1.3,
// turbidity coefficient 0.04608 T - 0.04586 as in Preetham et al. 1999); ozone and
// water vapour absorption are left out. It is integrated like OSPRay's over 360-720 nm
// against the CIE 1931 observer (the multi-lobe fit of Wyman, Sloan and Shirley 2013),
// then turned into linear sRGB.
#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <utility>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"
#include "sciray/render/light.hpp"
#include "sciray/render/sky_data.hpp"

namespace sciray {

/// The sky's RGB radiance at zenith angle theta, angle gamma from the sun, for a sun at
/// `solar_elevation` (radians, 0 to pi/2), turbidity 1 to 10 and ground albedo 0 to 1.
class HosekWilkieSky {
public:
  HosekWilkieSky(float turbidity, float albedo, float solar_elevation) {
    // The fit interpolates its control points in the cube root of the elevation.
    const float x = std::cbrt(std::clamp(solar_elevation / (0.5f * std::numbers::pi_v<float>), 0.f, 1.f));
    const float y = 1.f - x;
    const float bezier[6] = {y * y * y * y * y,         5.f * y * y * y * y * x, 10.f * y * y * y * x * x,
                             10.f * y * y * x * x * x, 5.f * y * x * x * x * x, x * x * x * x * x};
    const int low = std::clamp(static_cast<int>(turbidity), 1, 10), high = std::min(low + 1, 10);
    const float t = std::clamp(turbidity - static_cast<float>(low), 0.f, 1.f);
    const float a = std::clamp(albedo, 0.f, 1.f);
    // Bilinear in (albedo, turbidity) between the tabulated cases.
    const struct {
      int albedo, turbidity;
      float weight;
    } cases[4] = {{0, low, (1.f - a) * (1.f - t)}, {1, low, a * (1.f - t)}, {0, high, (1.f - a) * t}, {1, high, a * t}};
    for (int c = 0; c < 3; ++c) {
      for (float& p : shape_[c]) p = 0.f;
      scale_[c] = 0.f;
      for (const auto& k : cases) {
        const int block = k.albedo * 10 + (k.turbidity - 1);
        const float* s = &sky_data::shape[c][block * 54];
        const float* r = &sky_data::scale[c][block * 6];
        for (int cp = 0; cp < 6; ++cp) {
          for (int i = 0; i < 9; ++i) shape_[c][i] += k.weight * bezier[cp] * s[cp * 9 + i];
          scale_[c] += k.weight * bezier[cp] * r[cp];
        }
      }
    }
  }

  Vec3f radiance(float theta, float gamma) const {
    const float cos_theta = std::max(std::cos(theta), 0.f), cos_gamma = std::cos(gamma);
    float rgb[3];
    for (int c = 0; c < 3; ++c) {
      // The model's order is A, B, C, D, E, F, G, I, H.
      const float* p = shape_[c];
      const float h = p[8];
      const float mie = (1.f + cos_gamma * cos_gamma) / std::pow(1.f + h * h - 2.f * h * cos_gamma, 1.5f);
      const float f = (1.f + p[0] * std::exp(p[1] / (cos_theta + 0.01f))) *
                      (p[2] + p[3] * std::exp(p[4] * gamma) + p[5] * cos_gamma * cos_gamma + p[6] * mie +
                       p[7] * std::sqrt(cos_theta));
      rgb[c] = f * scale_[c];
    }
    return {rgb[0], rgb[1], rgb[2]};
  }

private:
  float shape_[3][9];
  float scale_[3];
};

namespace detail {

/// The CIE 1931 2-degree observer, Wyman, Sloan and Shirley's multi-lobe Gaussian fit.
inline Vec3f cie_observer(float nm) {
  const auto g = [nm](float mu, float below, float above) {
    const float s = (nm - mu) / (nm < mu ? below : above);
    return std::exp(-0.5f * s * s);
  };
  return {1.056f * g(599.8f, 37.9f, 31.0f) + 0.362f * g(442.0f, 16.0f, 26.7f) - 0.065f * g(501.1f, 20.4f, 26.2f),
          0.821f * g(568.8f, 46.9f, 40.5f) + 0.286f * g(530.9f, 16.3f, 31.1f),
          1.217f * g(437.0f, 11.8f, 36.0f) + 0.681f * g(459.0f, 26.0f, 13.8f)};
}

inline Vec3f xyz_to_linear_srgb(const Vec3f& c) {
  return {3.2404542f * c.x - 1.5371385f * c.y - 0.4985314f * c.z, -0.9692660f * c.x + 1.8760108f * c.y + 0.0415560f * c.z,
          0.0556434f * c.x - 0.2040259f * c.y + 1.0572252f * c.z};
}

}  // namespace detail

/// The sun's radiance (linear sRGB, W m^-2 sr^-1, summed over 1 nm bins as OSPRay does)
/// at `elevation` radians through an atmosphere of `turbidity` (see the file comment).
inline Vec3f solar_radiance(float elevation, float turbidity) {
  constexpr double h = 6.62607015e-34, c = 2.99792458e8, k = 1.380649e-23, sun_kelvin = 5778.0;
  const double zenith_deg = 90.0 - std::clamp(static_cast<double>(elevation), 0.0, std::numbers::pi / 2) * 180.0 / std::numbers::pi;
  const double air_mass =
      1.0 / (std::cos(zenith_deg * std::numbers::pi / 180.0) + 0.50572 * std::pow(96.07995 - zenith_deg, -1.6364));
  const double aerosol = std::max(0.04608 * turbidity - 0.04586, 0.0);
  Vec3f xyz{0.f, 0.f, 0.f};
  for (int nm = 360; nm <= 720; ++nm) {
    const double m = nm * 1e-9, um = nm * 1e-3;
    const double planck = 2.0 * h * c * c / std::pow(m, 5) / std::expm1(h * c / (m * k * sun_kelvin)) * 1e-9;  // per nm
    const double depth = 0.008735 * std::pow(um, -4.08) + aerosol * std::pow(um, -1.3);
    xyz = xyz + detail::cie_observer(static_cast<float>(nm)) * static_cast<float>(planck * std::exp(-air_mass * depth));
  }
  return detail::xyz_to_linear_srgb(xyz);
}

/// OSPRay's `sunSky` parameters. `scale` multiplies the model's radiance (OSPRay 3.1's
/// `intensity`, whose only quantity is scale), and `color` both the sky and the sun.
struct SunSky {
  Vec3f up{0.f, 1.f, 0.f};
  Vec3f direction{0.f, -1.f, 0.f};  ///< where the sunlight travels
  float turbidity = 3.f;
  float albedo = 0.3f;
  float horizon_extension = 0.01f;
  Vec3f color{1.f, 1.f, 1.f};
  float scale = 0.025f;
  bool visible = true;
};

/// Throws an Error naming the first bad parameter of `s`.
inline void validate(const SunSky& s) {
  const auto finite = [](const Vec3f& v) { return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z); };
  const auto fail = [](const char* parameter, const char* what) {
    throw Error(std::string("sunSky light: parameter '") + parameter + "' " + what);
  };
  if (!finite(s.up) || length(s.up) == 0.f) fail("up", "must be a finite non-zero vector");
  if (!finite(s.direction) || length(s.direction) == 0.f) fail("direction", "must be a finite non-zero vector");
  if (!(s.turbidity >= 1.f && s.turbidity <= 10.f)) fail("turbidity", "must be in [1, 10]");
  if (!(s.albedo >= 0.f && s.albedo <= 1.f)) fail("albedo", "must be in [0, 1]");
  if (!(s.horizon_extension >= 0.f && s.horizon_extension <= 1.f)) fail("horizonExtension", "must be in [0, 1]");
  if (!finite(s.color) || s.color.x < 0.f || s.color.y < 0.f || s.color.z < 0.f)
    fail("color", "must be finite and not negative");
  if (!(s.scale >= 0.f) || !std::isfinite(s.scale)) fail("intensity", "must be finite and not negative");
}

/// The horizontal direction the sky's azimuth is measured from and a sun below the horizon
/// is put at: towards the sun; for a sun at the zenith or nadir, which has no azimuth,
/// OSPRay 3.1's fixed choice (measured with its runtime: up (0,-1,0) and a sun at the
/// nadir put the sun on the horizon at +z, up (0,0,1) at -x).
inline Vec3f sky_azimuth_origin(const Vec3f& up, const Vec3f& to_sun) {
  const Vec3f across = to_sun - up * dot(to_sun, up);
  if (length(across) > 1e-3f) return normalize(across);
  return normalize(std::abs(up.x) < std::abs(up.y) ? Vec3f{0.f, up.z, -up.y} : Vec3f{-up.z, 0.f, up.x});
}

/// The sky (an environment map) and the sun (a distant light) of `s`.
inline std::pair<HdriLight, DistantLight> sun_sky_lights(const SunSky& s) {
  validate(s);
  constexpr float pi = std::numbers::pi_v<float>;
  constexpr int width = 512, height = 256;
  const Vec3f up = normalize(s.up), to_sun = -normalize(s.direction);
  const Vec3f forward = sky_azimuth_origin(up, to_sun);
  const float cos_sun = dot(up, to_sun);
  const float sun_theta = std::min(std::acos(std::clamp(cos_sun, -1.f, 1.f)), 0.999f * 0.5f * pi);
  // OSPRay's model holds the sky for a sun a little above the horizon at least.
  const float ospray_albedo = std::max(s.albedo, 0.1f);
  const HosekWilkieSky model(s.turbidity, ospray_albedo, 0.5f * pi - sun_theta);

  const float max_theta = 0.999f * 0.5f * pi, horizon_theta = (1.f + s.horizon_extension) * 0.5f * pi;
  std::vector<Vec3f> texels(static_cast<std::size_t>(width) * height, Vec3f{0.f, 0.f, 0.f});
  for (int y = 0; y < height; ++y) {
    // HdriLight's v = 1 is `up`: row y looks at zenith angle pi (1 - v).
    const float theta = pi * (1.f - (static_cast<float>(y) + 0.5f) / static_cast<float>(height));
    if (theta > horizon_theta) continue;
    const float fade = s.horizon_extension > 0.f ? std::clamp((horizon_theta - theta) / (horizon_theta - max_theta), 0.f, 1.f) : 1.f;
    const float t = std::min(theta, max_theta);
    for (int x = 0; x < width; ++x) {
      const float phi = 2.f * pi * ((static_cast<float>(x) + 0.5f) / static_cast<float>(width) - 0.5f);
      const float cos_gamma = std::cos(t) * std::cos(sun_theta) + std::sin(t) * std::sin(sun_theta) * std::cos(phi);
      const Vec3f l = model.radiance(t, std::acos(std::clamp(cos_gamma, -1.f, 1.f))) * (fade * s.scale);
      texels[static_cast<std::size_t>(y) * width + x] = {std::max(l.x, 0.f), std::max(l.y, 0.f), std::max(l.z, 0.f)};
    }
  }
  HdriLight sky(std::make_shared<const Texture2D>(width, height, std::move(texels)), up, forward);
  sky.color = s.color;
  sky.visible = s.visible;

  DistantLight sun;
  constexpr float sun_diameter = 0.53f;
  sun.angular_diameter = sun_diameter;
  sun.direction = -(cos_sun < 0.f ? forward : to_sun);
  const float solid_angle = 2.f * pi * (1.f - std::cos(detail::radians(0.5f * sun_diameter)));
  const Vec3f sun_rgb = solar_radiance(0.5f * pi - sun_theta, s.turbidity);  // a deep red sun can leave sRGB's gamut
  sun.color = s.color * Vec3f{std::max(sun_rgb.x, 0.f), std::max(sun_rgb.y, 0.f), std::max(sun_rgb.z, 0.f)} *
              (solid_angle * s.scale);
  sun.intensity = 1.f;
  sun.visible = s.visible;
  return {std::move(sky), sun};
}

}  // namespace sciray
