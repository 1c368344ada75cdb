#pragma once
// VolumetricModel<Volume> (OSPRay's VolumetricModel): a volume, its transfer function and
// `densityScale`, and the packet ray marcher that integrates it.
//
// The integral: along each ray, emission-absorption with extinction σ(t) = opacity(v(t))
// × densityScale per world unit; a step of length Δt absorbs α = 1 − exp(−σ Δt), which is
// the exact opacity of a constant-σ step, so images converge as the sampling rate grows
// instead of changing with it. Colour accumulates front to back; a ray stops when its
// opacity passes 0.99 (early ray termination) or at the first surface hit behind it.
// A volume placed by a transform is marched in its object space with the world ray's t
// (volume_placement.hpp): σ stays per unit of t, steps are a fraction of its cell.
//
// Empty-space skipping: the volume is cut into macrocells (volume/macrocells.hpp; 8³ cells of
// a grid) that record the range of values samples inside can take; for the
// current transfer function each macrocell knows the largest opacity it can produce. A
// lane whose sample falls in a macrocell that cannot produce any skips every step whose
// midpoint lies before the macrocell's exit, so skipping changes which samples are taken
// but never their positions. The macrocell ranges are built once per volume; changing the transfer
// function only re-derives the opacities.
//
// The path tracer instead treats the volume as a participating medium: extinction σ as
// above, single-scattering albedo from the transfer function's colour (at most 1), and a
// Henyey–Greenstein phase function of `anisotropy`. It samples where light collides by
// delta tracking and estimates transmittance by ratio tracking (Woodcock 1965; Novák et
// al. 2014). Both draw tentative collisions at a majorant of σ, the macrocell's largest
// extinction (the bound empty-space skipping uses), so they pass empty macrocells in one
// step and take no step length: no quadrature error, no bias.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/ray.hpp"
#include "sciray/scene/clipping.hpp"
#include "sciray/volume/exact_integration.hpp"
#include "sciray/volume/structured_regular.hpp"
#include "sciray/volume/transfer_function.hpp"
#include "sciray/volume/volume_placement.hpp"

namespace sciray {

/// What one packet's march through a volume produced (premultiplied colour), and where
/// it took its first visible sample: the volume's hit for the depth and id channels.
template <class Arch>
struct VolumeSample {
  Vec3<simd::Float<Arch>> color;
  simd::Float<Arch> alpha;
  /// t of the first sample whose step absorbs more than VolumeIntegration::hit_opacity
  /// and which lies inside the volume's box (infinity where none).
  simd::Float<Arch> hit_t = simd::Float<Arch>(std::numeric_limits<float>::infinity());
};

/// How a renderer asks a volume to be integrated.
struct VolumeIntegration {
  float sampling_rate = 1.f;          ///< OSPRay's volumeSamplingRate: samples per cell
  bool empty_space_skipping = true;
  const Clipping* clipping = nullptr;  ///< samples inside its volumes are skipped
  /// Integrate the transfer function over each step's value range (from the values at
  /// its ends) instead of taking it at the step's middle: coarse steps stay accurate
  /// where the transfer function has narrow features.
  bool preintegration = false;
  /// Step length from the densest extinction the macrocell can produce, so that a step
  /// absorbs about the same at any density: finer steps in dense matter, coarser in thin.
  bool adaptive_sampling = false;
  /// Integrate tetrahedral meshes cell by cell in closed form (volume/exact_integration.hpp)
  /// instead of by samples: no step, no sampling error. Applies to unstructured volumes
  /// of tetrahedra without gradient shading or clipping; others are sampled.
  bool exact = false;
  /// The opacity one step must exceed to make its sample the volume's hit (OSPRay's
  /// `minContribution`, measured with its runtime: its scivis records a volume in the
  /// depth and id channels at the first such sample).
  float hit_opacity = 0.001f;
};

/// The optical depth an adaptive step aims at, at one sample a cell (halved at two, ...).
inline constexpr float adaptive_optical_depth = 0.1f;

template <class Volume>
class VolumetricModel {
public:
  static constexpr std::int64_t macrocell_cells = 8;

  VolumetricModel(std::shared_ptr<const Volume> volume, TransferFunction transfer_function, float density_scale = 1.f,
                  float anisotropy = 0.f)
      : volume_(std::move(volume)), tf_(std::move(transfer_function)), density_scale_(density_scale),
        anisotropy_(0.f) {
    if (!volume_) throw Error("volumetric model: 'volume' is missing");
    if (!(density_scale_ >= 0.f) || !std::isfinite(density_scale_))
      throw Error("volumetric model: 'densityScale' must be finite and not negative");
    set_anisotropy(anisotropy);
    build_macrocell_ranges();
    derive_macrocell_opacities();
  }

  const Volume& volume() const { return *volume_; }
  const TransferFunction& transfer_function() const { return tf_; }
  float density_scale() const { return density_scale_; }
  /// Henyey–Greenstein g of the phase function: > 0 scatters forward, < 0 back.
  float anisotropy() const { return anisotropy_; }
  /// The largest extinction σ anywhere in the volume (per unit of ray parameter t).
  float majorant() const { return majorant_; }
  Box3f bounds() const { return volume_->bounds(); }
  std::size_t owned_bytes() const { return (ranges_.size() * 2 + opacity_.size()) * sizeof(float); }

  /// OSPRay's gradientShadingScale: how much of each sample's colour is lit with the
  /// gradient as its normal, from 0 (the transfer function's colour) to 1 (fully lit).
  float gradient_shading_scale() const { return gradient_shading_scale_; }
  void set_gradient_shading_scale(float scale) {
    if (!(scale >= 0.f && scale <= 1.f))
      throw Error("volumetric model: 'gradientShadingScale' must be in [0, 1], got " + std::to_string(scale));
    gradient_shading_scale_ = scale;
  }

  void set_anisotropy(float g) {
    if (!(g >= -1.f && g <= 1.f)) throw Error("volumetric model: 'anisotropy' must be in [-1, 1], got " + std::to_string(g));
    anisotropy_ = g;
  }

  /// A new transfer function keeps the macrocell value ranges (the volume is unchanged).
  void set_transfer_function(TransferFunction tf) {
    tf_ = std::move(tf);
    derive_macrocell_opacities();
  }

  /// The step between samples in object units for `sampling_rate` samples per cell.
  float step(float sampling_rate) const {
    const Vec3f& s = volume_->cell_size();
    return std::min({s.x, s.y, s.z}) / sampling_rate;
  }

  /// Marches the active lanes from where they enter the volume to where they leave it or
  /// reach `t_end` (the nearest surface). With a gradient shading scale above 0, `shade`
  /// lights the samples: shade(p, n, color, lanes) returns `color` lit at positions p
  /// with unit normals n (the renderer's lights); without one, samples are not lit.
  template <class Arch, class Shade = std::nullptr_t>
  VolumeSample<Arch> integrate(const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                               const simd::Float<Arch>& t_end, const VolumeIntegration& how,
                               const Shade& shade = nullptr) const {
    return integrate<Arch>(VolumeRay<Arch>{ray, active}, t_end, how, shade);
  }
  /// integrate() of a placed volume: `placed` holds the rays in object space (positions
  /// and normals go back to the world for clipping and lighting).
  template <class Arch, class Shade = std::nullptr_t>
  VolumeSample<Arch> integrate(const VolumeRay<Arch>& placed, const simd::Float<Arch>& t_end,
                               const VolumeIntegration& how, const Shade& shade = nullptr) const {
    using F = simd::Float<Arch>;
    if constexpr (std::is_same_v<Volume, Unstructured>)
      if (how.exact && volume_->tetrahedral() && gradient_shading_scale_ == 0.f && !how.clipping)
        return integrate_exactly<Arch>(placed, t_end, how);
    const Ray<F>& ray = placed.ray;
    auto sample = sampler<Arch>();
    VolumeSample<Arch> out{Vec3<F>(Vec3f{0.f, 0.f, 0.f}), F(0.f)};
    const Vec3<F> inv{F(1.f) / ray.dir.x, F(1.f) / ray.dir.y, F(1.f) / ray.dir.z};
    const auto [enter, box_exit] = span<Arch>(ray, inv);
    const F leave = simd::min(box_exit, t_end);
    auto live = placed.active & (enter < leave);
    if (!simd::any(live)) return out;

    // The step in t: a fraction of an object-space cell, however the volume is placed.
    const F dt = F(step(how.sampling_rate)) * placed.t_per_unit();
    // Sample k stands for the step [enter + k·dt, enter + (k+1)·dt] cut at `leave`, and
    // sits at its middle (the midpoint rule, exact for a linearly varying extinction).
    F t = enter;
    const F neg_density(-density_scale_);
    // The volume's hit for the depth and id channels, as OSPRay's scivis finds it: its
    // first sample that absorbs more than `hit_opacity` over one of OSPRay's steps (Open
    // VKL's: a cell along the axis the ray crosses fastest). OSPRay samples at
    // start + (k + jitter)·step inside the box only, so a crossing shorter than a step is
    // seen with probability length/step; at the mean jitter, where there is half a step
    // of the box left.
    const Vec3f& spacing = volume_->cell_size();
    const F ospray_step = simd::min(simd::min(F(spacing.x) * simd::abs(inv.x), F(spacing.y) * simd::abs(inv.y)),
                                    F(spacing.z) * simd::abs(inv.z)) *
                          F(1.f / how.sampling_rate);
    const F half_ospray_step = F(0.5f) * ospray_step;
    const F visible_sigma = F(-std::log1p(-how.hit_opacity)) / (F(density_scale_) * ospray_step);
    F previous_end(0.f);
    auto have_previous = simd::Mask<Arch>(false);
    const Vec3f& cell_size = macrocells_.size;
    const Vec3f& grid_lower = macrocells_.lower;
    while (simd::any(live)) {
      F step = dt;
      auto sampled = live;
      // The lane's macrocell: whether the transfer function can show anything there and,
      // for adaptive sampling, how dense it can get. Plain steps ask at their midpoint,
      // adaptive ones (whose length depends on the answer) at their start.
      if (how.empty_space_skipping || how.adaptive_sampling) {
        const F probe_t = how.adaptive_sampling ? t : simd::min(t + F(0.5f) * dt, leave);
        const auto [cx, cy, cz, densest] = macrocell<Arch>(ray.org + ray.dir * probe_t);
        if (how.adaptive_sampling)
          // At most `adaptive_optical_depth` absorbed a step, between 4× finer and 4× coarser
          // than the base rate: fine where the medium is dense, coarse where it is thin.
          step = simd::min(simd::max(F(adaptive_optical_depth / how.sampling_rate) / densest, F(0.25f) * dt),
                           F(4.f) * dt);
        const auto empty = live & (densest <= F(0.f));
        if (how.empty_space_skipping && simd::any(empty)) {
          const Vec3<F> lower{F(grid_lower.x) + simd::to_float(cx) * F(cell_size.x),
                              F(grid_lower.y) + simd::to_float(cy) * F(cell_size.y),
                              F(grid_lower.z) + simd::to_float(cz) * F(cell_size.z)};
          const Vec3<F> upper = lower + Vec3<F>(cell_size);
          const Vec3<F> exit_planes = select_positive(ray.dir, upper, lower);
          const Vec3<F> te = (exit_planes - ray.org) * inv;
          const F exit = simd::min(simd::min(te.x, te.y), te.z);
          // Plain steps skip those whose midpoints lie before the exit (keeping the sample
          // grid); adaptive ones, which have no grid, go straight to the exit.
          const F skip = how.adaptive_sampling ? simd::max(exit - t, F(1e-3f) * dt)
                                               : simd::max(xsimd_ceil((exit - t) / dt - F(0.5f)), F(1.f)) * dt;
          step = simd::select(empty, skip, step);
          sampled = sampled & !empty;
        }
      }
      const F step_end = simd::min(t + step, leave);
      const F next = t + step;
      const Vec3<F> p = ray.org + ray.dir * ((t + step_end) * F(0.5f));
      if (how.clipping && simd::any(sampled))
        sampled = sampled &
                  !clipped<Arch>(placed.world_point((t + step_end) * F(0.5f)), placed.ray.time, sampled, *how.clipping);
      if (simd::any(sampled)) {
        F sigma;
        Vec3<F> color;
        if (how.preintegration) {
          // The value at the step's start is the previous step's end where there was one.
          F start = previous_end;
          if (simd::any(sampled & !have_previous))
            start = simd::select(have_previous, previous_end, sample(ray.org + ray.dir * t));
          const F end = sample(ray.org + ray.dir * step_end);
          tf_.template segment<Arch>(start, end, sigma, color);
          const simd::Mask<Arch> inside_cells = (start == start) & (end == end);  // NaN: outside them
          sigma = simd::select(inside_cells, sigma, F(0.f));
          previous_end = end;
        } else {
          const F value = sample(p);
          sigma = tf_.template opacity<Arch>(value);
          color = tf_.template color<Arch>(value);
        }
        const F alpha = F(1.f) - exp(sigma * neg_density * (step_end - t));
        const auto visible = sampled & (sigma > visible_sigma) & (t + half_ospray_step <= box_exit);
        out.hit_t = simd::select(visible, simd::min(out.hit_t, (t + step_end) * F(0.5f)), out.hit_t);
        if constexpr (!std::is_null_pointer_v<Shade>)
          if (gradient_shading_scale_ > 0.f)
            color = gradient_shaded<Arch>(placed, p, (t + step_end) * F(0.5f), color, sampled, shade);
        const F weight = simd::select(sampled, (F(1.f) - out.alpha) * alpha, F(0.f));
        out.color = out.color + color * weight;
        out.alpha = out.alpha + weight;
      }
      // A lane continues from its last end value only if it took the step just before.
      have_previous = sampled & (next == step_end);
      t = next;
      live = live & (t < leave) & (out.alpha < F(0.99f));
    }
    return out;
  }

  /// Where light travelling along each active lane first collides with the medium
  /// before `t_end`, by delta tracking: tentative collisions at the macrocell's majorant
  /// rate, each real with probability σ/majorant. `uniform()` returns a packet of
  /// independent uniform numbers in [0, 1).
  template <class Arch>
  struct Collision {
    simd::Mask<Arch> hit;
    simd::Float<Arch> t;
    Vec3<simd::Float<Arch>> albedo;  ///< the transfer function's colour there, at most 1
  };
  template <class Arch, class Uniform>
  Collision<Arch> sample_collision(const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                                   const simd::Float<Arch>& t_end, const Clipping* clipping, Uniform&& uniform) const {
    return sample_collision<Arch>(VolumeRay<Arch>{ray, active}, t_end, clipping, uniform);
  }
  /// sample_collision() of a placed volume (`placed`: the rays in object space).
  template <class Arch, class Uniform>
  Collision<Arch> sample_collision(const VolumeRay<Arch>& placed, const simd::Float<Arch>& t_end,
                                   const Clipping* clipping, Uniform&& uniform) const {
    using F = simd::Float<Arch>;
    using M = simd::Mask<Arch>;
    const Ray<F>& ray = placed.ray;
    Collision<Arch> out{M(false), F(std::numeric_limits<float>::infinity()), Vec3<F>(Vec3f{0.f, 0.f, 0.f})};
    auto sample = sampler<Arch>();
    track<Arch>(placed, t_end, uniform, [&](const M& lanes, const F& t, const F& majorant) {
      const F value = sample(ray.org + ray.dir * t);
      const M real = lanes & (uniform() * majorant < extinction<Arch>(value, placed, t, lanes, clipping));
      if (simd::any(real)) {
        const Vec3<F> c = tf_.template color<Arch>(value);
        out.hit = out.hit | real;
        out.t = simd::select(real, t, out.t);
        out.albedo = select(real, Vec3<F>{simd::min(c.x, F(1.f)), simd::min(c.y, F(1.f)), simd::min(c.z, F(1.f))},
                            out.albedo);
      }
      return lanes & !real;
    });
    return out;
  }

  /// An unbiased estimate of the transmittance exp(-∫σ) along each active lane up to
  /// `t_end`, by ratio tracking: the product of (1 − σ/majorant) over tentative
  /// collisions, ended by Russian roulette once it is small.
  template <class Arch, class Uniform>
  simd::Float<Arch> transmittance(const Ray<simd::Float<Arch>>& ray, const simd::Mask<Arch>& active,
                                  const simd::Float<Arch>& t_end, const Clipping* clipping, Uniform&& uniform) const {
    return transmittance<Arch>(VolumeRay<Arch>{ray, active}, t_end, clipping, uniform);
  }
  /// transmittance() of a placed volume (`placed`: the rays in object space).
  template <class Arch, class Uniform>
  simd::Float<Arch> transmittance(const VolumeRay<Arch>& placed, const simd::Float<Arch>& t_end,
                                  const Clipping* clipping, Uniform&& uniform) const {
    using F = simd::Float<Arch>;
    using M = simd::Mask<Arch>;
    const Ray<F>& ray = placed.ray;
    constexpr float roulette_below = 0.1f;
    F estimate(1.f);
    auto sample = sampler<Arch>();
    track<Arch>(placed, t_end, uniform, [&](const M& lanes, const F& t, const F& majorant) {
      const F value = sample(ray.org + ray.dir * t);
      const F sigma = extinction<Arch>(value, placed, t, lanes, clipping);
      estimate = simd::select(lanes, estimate * simd::max(F(1.f) - sigma / majorant, F(0.f)), estimate);
      // Small estimates survive with probability 1/2 at twice their value.
      const M small = lanes & (estimate < F(roulette_below));
      if (simd::any(small)) {
        const M killed = small & (uniform() < F(0.5f));
        estimate = simd::select(killed, F(0.f), simd::select(small, estimate * F(2.f), estimate));
      }
      return lanes & (estimate > F(0.f));
    });
    return estimate;
  }

private:
  /// integrate() in closed form through a tetrahedral mesh, ray by ray (integrate_tetrahedra).
  template <class Arch>
  VolumeSample<Arch> integrate_exactly(const VolumeRay<Arch>& placed, const simd::Float<Arch>& t_end,
                                       const VolumeIntegration& how) const {
    using F = simd::Float<Arch>;
    constexpr int W = simd::width<Arch>;
    const Ray<F>& ray = placed.ray;
    const Vec3<F> inv{F(1.f) / ray.dir.x, F(1.f) / ray.dir.y, F(1.f) / ray.dir.z};
    const auto [enter, box_exit] = span<Arch>(ray, inv);
    const F leave = simd::min(box_exit, t_end);
    alignas(64) float r[W], g[W], b[W], a[W], hit[W];
    for (int i = 0; i < W; ++i) {
      r[i] = g[i] = b[i] = a[i] = 0.f;
      hit[i] = std::numeric_limits<float>::infinity();
      const float t0 = simd::lane(enter, i), t1 = simd::lane(leave, i);
      if (!simd::lane(placed.active, i) || !(t0 < t1)) continue;
      const Vec3f org{simd::lane(ray.org.x, i), simd::lane(ray.org.y, i), simd::lane(ray.org.z, i)};
      const Vec3f dir{simd::lane(ray.dir.x, i), simd::lane(ray.dir.y, i), simd::lane(ray.dir.z, i)};
      // Marching stops at opacity 0.99 (early ray termination): so does this.
      const ExactAccumulator acc =
          integrate_tetrahedra(*volume_, tf_, density_scale_, org, dir, t0, t1, 0.01, how.hit_opacity, hit[i]);
      r[i] = acc.color.x, g[i] = acc.color.y, b[i] = acc.color.z;
      a[i] = static_cast<float>(1. - acc.transmittance);
    }
    VolumeSample<Arch> out{{simd::load<Arch>(r), simd::load<Arch>(g), simd::load<Arch>(b)}, simd::load<Arch>(a)};
    out.hit_t = simd::load<Arch>(hit);
    return out;
  }

  /// What reads the volume along one packet's rays: the volume's own sampler where it has
  /// one (which may keep where the last samples were, as Unstructured's cells), else its
  /// sample().
  template <class Arch>
  auto sampler() const {
    if constexpr (requires { volume_->template sampler<Arch>(); })
      return volume_->template sampler<Arch>();
    else
      return [volume = volume_.get()](const Vec3<simd::Float<Arch>>& p) { return volume->template sample<Arch>(p); };
  }

  /// The macrocell holding world positions `p` (clamped to the grid) and the largest σ
  /// it can give.
  template <class Arch>
  struct MacrocellAt {
    simd::Int<Arch> x, y, z;
    simd::Float<Arch> densest;
  };
  template <class Arch>
  MacrocellAt<Arch> macrocell(const Vec3<simd::Float<Arch>>& p) const {
    using F = simd::Float<Arch>;
    using I = simd::Int<Arch>;
    const auto& counts = macrocells_.counts;
    const Vec3<F> m = (p - Vec3<F>(macrocells_.lower)) * Vec3<F>(inv_macrocell_size_);
    const auto cell_index = [&](const F& v, int axis) {
      return simd::to_int(simd::min(simd::max(v, F(0.f)), F(static_cast<float>(counts[axis] - 1))));
    };
    const I x = cell_index(m.x, 0), y = cell_index(m.y, 1), z = cell_index(m.z, 2);
    const I index = (z * I(static_cast<std::int32_t>(counts[1])) + y) * I(static_cast<std::int32_t>(counts[0])) + x;
    return {x, y, z, simd::gather<Arch>(opacity_.data(), index)};
  }

  /// Where each ray enters and leaves the volume's box, within [tnear, tfar]. A ray
  /// parallel to an axis is inside that axis's slab everywhere or nowhere (also when it
  /// lies in one of its planes, where the slab test would take 0 × ∞).
  template <class Arch>
  std::pair<simd::Float<Arch>, simd::Float<Arch>> span(const Ray<simd::Float<Arch>>& ray,
                                                       const Vec3<simd::Float<Arch>>& inv) const {
    using F = simd::Float<Arch>;
    constexpr float inf = std::numeric_limits<float>::infinity();
    const Box3f box = bounds();
    F near = ray.tnear, far = ray.tfar;
    for (int k = 0; k < 3; ++k) {
      const F o = k == 0 ? ray.org.x : k == 1 ? ray.org.y : ray.org.z;
      const F d = k == 0 ? ray.dir.x : k == 1 ? ray.dir.y : ray.dir.z;
      const F i = k == 0 ? inv.x : k == 1 ? inv.y : inv.z;
      const F t0 = (F(box.lower[k]) - o) * i, t1 = (F(box.upper[k]) - o) * i;
      const auto parallel = d == F(0.f);
      const auto in_slab = (o >= F(box.lower[k])) & (o <= F(box.upper[k]));
      near = simd::max(near, simd::select(parallel, simd::select(in_slab, F(-inf), F(inf)), simd::min(t0, t1)));
      far = simd::min(far, simd::select(parallel, simd::select(in_slab, F(inf), F(-inf)), simd::max(t0, t1)));
    }
    return {near, far};
  }

  /// Walks each active lane through the macrocells from where it enters the volume to
  /// `t_end`, drawing tentative collisions at each macrocell's majorant (the largest σ
  /// its values can give): none in macrocells that cannot absorb, few where the medium is
  /// thin. At a macrocell's exit a lane starts afresh with the next one's majorant (the
  /// exponential distribution has no memory). `at_tentative(lanes, t, majorant)` returns
  /// the lanes that go on.
  template <class Arch, class Uniform, class AtTentative>
  void track(const VolumeRay<Arch>& placed, const simd::Float<Arch>& t_end, Uniform& uniform,
             AtTentative&& at_tentative) const {
    using F = simd::Float<Arch>;
    const Ray<F>& ray = placed.ray;
    const auto& active = placed.active;
    using I = simd::Int<Arch>;
    constexpr float inf = std::numeric_limits<float>::infinity();
    const Vec3<F> inv{F(1.f) / ray.dir.x, F(1.f) / ray.dir.y, F(1.f) / ray.dir.z};
    auto [t, box_exit] = span<Arch>(ray, inv);
    const F leave = simd::min(box_exit, t_end);
    auto tracking = active & (t < leave);
    if (!(majorant_ > 0.f)) return;
    const Vec3f& cell_size = macrocells_.size;
    const Vec3f& grid_lower = macrocells_.lower;
    // Probing a little past t finds the macrocell a lane is entering, not the one it leaves.
    const Vec3f& spacing = volume_->cell_size();
    const F nudge = F(1e-4f * std::min({spacing.x, spacing.y, spacing.z})) * placed.t_per_unit();
    while (simd::any(tracking)) {
      const auto [cx, cy, cz, majorant] = macrocell<Arch>(ray.org + ray.dir * (t + nudge));
      // The outermost macrocells reach on to the box's faces (and past them: `leave` stops
      // the lane there), so that no lane is left outside every macrocell.
      const auto planes = [&](const I& c, int axis, float origin, float size, F& lo, F& hi) {
        const F cf = simd::to_float(c);
        lo = simd::select(cf == F(0.f), F(-inf), F(origin) + cf * F(size));
        hi = simd::select(cf == F(static_cast<float>(macrocells_.counts[axis] - 1)), F(inf),
                          F(origin) + (cf + F(1.f)) * F(size));
      };
      Vec3<F> lower, upper;
      planes(cx, 0, grid_lower.x, cell_size.x, lower.x, upper.x);
      planes(cy, 1, grid_lower.y, cell_size.y, lower.y, upper.y);
      planes(cz, 2, grid_lower.z, cell_size.z, lower.z, upper.z);
      // By the sign of inv, not of dir: a direction of -0 has inv = -inf and leaves by lower.
      const Vec3<F> te = (select_positive(inv, upper, lower) - ray.org) * inv;
      // At least a nudge on (also where a plane is parallel to the ray and te is NaN).
      const F exit = simd::max(simd::min(simd::min(te.x, te.y), te.z), t + nudge);
      const F flight = simd::select(majorant > F(0.f), -log(F(1.f) - uniform()) / majorant, F(inf));
      const F next = t + flight;
      const auto tentative = tracking & (next < exit) & (next < leave);
      t = simd::select(tracking, simd::min(next, exit), t);
      tracking = tracking & (t < leave);
      if (simd::any(tentative)) tracking = (tracking & !tentative) | at_tentative(tentative, t, majorant);
    }
  }

  /// σ at ray parameters `t` whose filtered values are `value`; none inside clipped
  /// regions (which are in world space).
  template <class Arch>
  simd::Float<Arch> extinction(const simd::Float<Arch>& value, const VolumeRay<Arch>& placed,
                               const simd::Float<Arch>& t, const simd::Mask<Arch>& lanes,
                               const Clipping* clipping) const {
    using F = simd::Float<Arch>;
    const F sigma = tf_.template opacity<Arch>(value) * F(density_scale_);
    if (!clipping) return sigma;
    return simd::select(clipped<Arch>(placed.world_point(t), placed.ray.time, lanes, *clipping), F(0.f), sigma);
  }

  template <class F>
  static Vec3<F> select_positive(const Vec3<F>& dir, const Vec3<F>& a, const Vec3<F>& b) {
    return {simd::select(dir.x >= F(0.f), a.x, b.x), simd::select(dir.y >= F(0.f), a.y, b.y),
            simd::select(dir.z >= F(0.f), a.z, b.z)};
  }
  template <class F>
  static F xsimd_ceil(const F& x) {
    if constexpr (std::is_same_v<F, float>)
      return std::ceil(x);
    else
      return xsimd::ceil(x);
  }
  template <class F>
  static F exp(const F& x) {
    if constexpr (std::is_same_v<F, float>)
      return std::exp(x);
    else
      return xsimd::exp(x);
  }
  template <class F>
  static F log(const F& x) {
    if constexpr (std::is_same_v<F, float>)
      return std::log(x);
    else
      return xsimd::log(x);
  }

  /// Which lanes' positions lie in a clipped region at their rays' `time` (tested lane
  /// by lane: clipping meshes answer by tracing).
  template <class Arch>
  static simd::Mask<Arch> clipped(const Vec3<simd::Float<Arch>>& p, const simd::Float<Arch>& time,
                                  const simd::Mask<Arch>& lanes, const Clipping& clipping) {
    using F = simd::Float<Arch>;
    constexpr int W = simd::width<Arch>;
    alignas(64) float out[W];
    for (int i = 0; i < W; ++i)
      out[i] = simd::lane(lanes, i) && clipping.clipped({simd::lane(p.x, i), simd::lane(p.y, i), simd::lane(p.z, i)},
                                                        simd::lane(time, i))
                   ? 1.f
                   : 0.f;
    return simd::load<Arch>(out) != F(0.f);
  }

  /// OSPRay's gradient shading: the colour lerped towards the colour lit with the
  /// negated gradient as the normal (values are taken to rise inwards, so it points out),
  /// by the gradient shading scale. Where the field is flat there is no normal: the
  /// sample keeps its colour.
  template <class Arch, class Shade>
  Vec3<simd::Float<Arch>> gradient_shaded(const VolumeRay<Arch>& placed, const Vec3<simd::Float<Arch>>& p,
                                          const simd::Float<Arch>& t, const Vec3<simd::Float<Arch>>& color,
                                          const simd::Mask<Arch>& lanes, const Shade& shade) const {
    using F = simd::Float<Arch>;
    // Flat in object space (as OSPRay asks), else the gradient as a world normal.
    const Vec3<F> object_g = volume_->template shading_gradient<Arch>(p);
    const auto lit_lanes = lanes & (dot(object_g, object_g) > F(1e-6f));
    if (!simd::any(lit_lanes)) return color;
    const Vec3<F> g = placed.world_normal(object_g);
    const Vec3<F> n = -g / simd::sqrt(simd::select(lit_lanes, dot(g, g), F(1.f)));
    const Vec3<F> lit = shade(placed.world_point(t), n, color, lit_lanes);
    const F s(gradient_shading_scale_);
    return select(lit_lanes, color + (lit - color) * s, color);
  }

  void build_macrocell_ranges() {
    macrocells_ = volume_->macrocell_grid(macrocell_cells);
    inv_macrocell_size_ = {1.f / macrocells_.size.x, 1.f / macrocells_.size.y, 1.f / macrocells_.size.z};
    ranges_ = macrocells_.empty_ranges();
    volume_->widen_macrocell_ranges(macrocells_, macrocell_cells, ranges_);
  }

  void derive_macrocell_opacities() {
    opacity_.resize(ranges_.size() / 2);
    majorant_ = 0.f;
    for (std::size_t i = 0; i < opacity_.size(); ++i) {
      opacity_[i] = density_scale_ * tf_.max_opacity(ranges_[2 * i], ranges_[2 * i + 1]);
      majorant_ = std::max(majorant_, opacity_[i]);
    }
  }

  std::shared_ptr<const Volume> volume_;
  TransferFunction tf_;
  float density_scale_;
  float anisotropy_;
  float gradient_shading_scale_ = 0.f;
  float majorant_ = 0.f;
  MacrocellGrid macrocells_;
  Vec3f inv_macrocell_size_;
  std::vector<float> ranges_;   ///< min, max per macrocell
  std::vector<float> opacity_;  ///< the largest σ the transfer function gives inside
};

}  // namespace sciray
