#pragma once
// Sort-last compositing for data-parallel rendering (OSPRay's `mpiDistributed` device):
// each region of the world is rendered on its own into a fragment image — premultiplied
// RGBA of what the region holds along each pixel's ray, a sort key saying where that
// ray enters the region, and the depth of its first hit — and the fragments of all
// regions are blended per pixel front to back, in key order, with the over operator,
// then the renderer's background behind. Regions are convex and disjoint (boxes), so
// along any ray all of one region lies before all of the next: ordering by where each
// ray enters them is exact, and the blend reproduces the renderer's own front-to-back
// compositing of the whole ray. Nothing here knows about MPI: the caller gathers the
// fragments of a tile from wherever they were rendered and composites that pixel range.
#include <algorithm>
#include <cstddef>
#include <limits>
#include <span>
#include <utility>
#include <string>
#include <vector>

#include "sciray/error.hpp"
#include "sciray/math/vec.hpp"

namespace sciray::distributed {

/// One region's contribution to a frame, bottom row first like a FrameBuffer.
struct FragmentImage {
  int width = 0, height = 0;
  /// Premultiplied RGBA per pixel: colour already weighted by coverage, no background.
  std::vector<float> rgba;
  /// Where the pixel's ray enters the region (the smallest over its samples, in units of
  /// the ray's direction); +inf where no sample's ray meets the region.
  std::vector<float> key;
  /// Distance to the first hit inside the region (the depth channel's); +inf where none.
  std::vector<float> depth;

  FragmentImage() = default;
  FragmentImage(int w, int h)
      : width(w), height(h), rgba(4 * pixel_count(), 0.f), key(pixel_count(), std::numeric_limits<float>::infinity()),
        depth(pixel_count(), std::numeric_limits<float>::infinity()) {}

  std::size_t pixel_count() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
};

/// The same range of pixels of one fragment image (as received from a rank, say): `rgba`
/// holds 4 floats a pixel, `key` 1, `depth` 1 or none.
struct FragmentView {
  std::span<const float> rgba;
  std::span<const float> key;
  std::span<const float> depth;

  FragmentView() = default;
  FragmentView(std::span<const float> rgba_, std::span<const float> key_, std::span<const float> depth_ = {})
      : rgba(rgba_), key(key_), depth(depth_) {}
  /// Pixels [first, first + count) of `image`.
  FragmentView(const FragmentImage& image, std::size_t first, std::size_t count)
      : rgba(std::span(image.rgba).subspan(4 * first, 4 * count)), key(std::span(image.key).subspan(first, count)),
        depth(std::span(image.depth).subspan(first, count)) {}
  explicit FragmentView(const FragmentImage& image) : FragmentView(image, 0, image.pixel_count()) {}
};

/// What lies behind every region: the renderer's backgroundColor (rgb, and alpha).
struct Background {
  Vec3f color{0.f, 0.f, 0.f};
  float alpha = 0.f;
};

/// Blends, pixel by pixel, `fragments` (views of the same pixel range) front to back in
/// order of their keys (ties in the order given) with the over operator, then
/// `background` behind what they leave uncovered — colour C + T·background.rgb, alpha
/// (1 − T) + T·background.alpha for the transmittance T left, as the renderers finish a
/// ray — into `rgba_out` (4 floats a pixel). `depth_out`, if not empty, gets the nearest
/// fragment depth. Fragments are usually few (the regions a tile overlaps), so each
/// pixel's are ordered by insertion.
inline void composite(std::span<const FragmentView> fragments, const Background& background,
                      std::span<float> rgba_out, std::span<float> depth_out = {}) {
  if (rgba_out.size() % 4 != 0)
    throw Error("composite: the output holds " + std::to_string(rgba_out.size()) + " floats, not 4 per pixel");
  const std::size_t pixels = rgba_out.size() / 4;
  if (!depth_out.empty() && depth_out.size() != pixels)
    throw Error("composite: the depth output has " + std::to_string(depth_out.size()) + " pixels, the colour output " +
                std::to_string(pixels));
  for (std::size_t f = 0; f < fragments.size(); ++f) {
    const FragmentView& v = fragments[f];
    if (v.rgba.size() != 4 * pixels || v.key.size() != pixels)
      throw Error("composite: fragment " + std::to_string(f) + " has " + std::to_string(v.rgba.size()) +
                  " colour floats and " + std::to_string(v.key.size()) + " keys for " + std::to_string(pixels) +
                  " pixels (4 and 1 per pixel)");
    if (!depth_out.empty() && !v.depth.empty() && v.depth.size() != pixels)
      throw Error("composite: fragment " + std::to_string(f) + " has " + std::to_string(v.depth.size()) +
                  " depths for " + std::to_string(pixels) + " pixels");
  }
  constexpr float inf = std::numeric_limits<float>::infinity();
  const std::size_t n = fragments.size();
  std::vector<std::pair<float, std::size_t>> order(n);  // (key, fragment), front first
  for (std::size_t p = 0; p < pixels; ++p) {
    for (std::size_t f = 0; f < n; ++f) {
      // Insertion keeps equal keys in the order given (the sort is stable), and costs one
      // comparison a fragment where neighbouring pixels see the regions in the same order.
      const float key = fragments[f].key[p];
      std::size_t at = f;
      for (; at > 0 && order[at - 1].first > key; --at) order[at] = order[at - 1];
      order[at] = {key, f};
    }
    float r = 0.f, g = 0.f, b = 0.f, transmittance = 1.f, depth = inf;
    for (std::size_t i = 0; i < n; ++i) {
      const FragmentView& v = fragments[order[i].second];
      const float* c = v.rgba.data() + 4 * p;
      r += transmittance * c[0], g += transmittance * c[1], b += transmittance * c[2];
      transmittance *= 1.f - c[3];
      if (!v.depth.empty()) depth = std::min(depth, v.depth[p]);
    }
    float* out = rgba_out.data() + 4 * p;
    out[0] = r + transmittance * background.color.x;
    out[1] = g + transmittance * background.color.y;
    out[2] = b + transmittance * background.color.z;
    out[3] = 1.f - transmittance + transmittance * background.alpha;
    if (!depth_out.empty()) depth_out[p] = depth;
  }
}

/// composite() of whole fragment images of one size into an RGBA image (and depth).
inline void composite(std::span<const FragmentImage> images, const Background& background, std::vector<float>& rgba,
                      std::vector<float>* depth = nullptr) {
  if (images.empty()) throw Error("composite: no fragment images");
  for (const FragmentImage& image : images)
    if (image.width != images[0].width || image.height != images[0].height)
      throw Error("composite: fragment images of " + std::to_string(images[0].width) + "x" +
                  std::to_string(images[0].height) + " and " + std::to_string(image.width) + "x" +
                  std::to_string(image.height) + " pixels");
  std::vector<FragmentView> views;
  views.reserve(images.size());
  for (const FragmentImage& image : images) views.emplace_back(image);
  rgba.assign(4 * images[0].pixel_count(), 0.f);
  if (depth) depth->assign(images[0].pixel_count(), 0.f);
  composite(views, background, rgba, depth ? std::span<float>(*depth) : std::span<float>());
}

}  // namespace sciray::distributed
