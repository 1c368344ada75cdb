#pragma once
// OSPRay's adaptive refinement of tile errors (its TileError::refine, Dammertz et al.
// 2010's hierarchical stopping condition): the image starts as one region of tiles; after
// each frame a region with any tile above the threshold has all its tiles raised just
// above it, so that they are refined together, and a region whose mean error is within 4
// times the threshold is split in half along its longer side, or dropped once it is done
// or would hold a single tile. The C API's frame buffers use it, so that an OSPRay
// program's `varianceThreshold` renders the tiles OSPRay would.
#include <algorithm>
#include <cmath>
#include <limits>
#include <vector>

namespace sciray {

class ErrorRegions {
public:
  /// One region covering `tiles_x` by `tiles_y` tiles.
  void reset(int tiles_x, int tiles_y) {
    tiles_x_ = tiles_x;
    regions_.assign(1, Region{0, 0, tiles_x, tiles_y});
  }

  /// Refines the regions with the tiles' errors (row-major, tiles_x per row), raising
  /// those of regions still above `threshold`. Returns the frame's error as OSPRay reports
  /// it: the mean of the tiles above the threshold, or the largest error if none is.
  float refine(std::vector<float>& tile_errors, float threshold) {
    float largest = 0.f, above_sum = 0.f;
    int above = 0;
    for (float e : tile_errors) {
      largest = std::max(largest, e);
      if (e > threshold) above_sum += e, ++above;
    }
    const float frame_error = above ? above_sum / static_cast<float>(above) : largest;
    if (!(threshold > 0.f)) return frame_error;

    // Regions split in this pass are appended and not refined again until the next.
    std::size_t count = regions_.size();
    for (std::size_t i = 0; i < count;) {
      Region& r = regions_[i];
      float sum = 0.f, region_largest = 0.f;
      for (int y = r.y0; y < r.y1; ++y)
        for (int x = r.x0; x < r.x1; ++x) {
          const float e = tile_errors[static_cast<std::size_t>(y * tiles_x_ + x)];
          sum += e, region_largest = std::max(region_largest, e);
        }
      if (region_largest > threshold) {
        const float just_above = std::nextafter(threshold, std::numeric_limits<float>::infinity());
        for (int y = r.y0; y < r.y1; ++y)
          for (int x = r.x0; x < r.x1; ++x) {
            float& e = tile_errors[static_cast<std::size_t>(y * tiles_x_ + x)];
            e = std::max(e, just_above);
          }
      }
      const int w = r.x1 - r.x0, h = r.y1 - r.y0, area = w * h;
      if (sum / static_cast<float>(area) <= 4.f * threshold) {
        if (area <= 2 || region_largest <= threshold) {  // done, or one tile after a split
          --count;
          regions_[i] = regions_[count];
          regions_[count] = regions_.back();
          regions_.pop_back();
          continue;
        }
        Region half = r;
        if (w > h)
          r.x1 = half.x0 = r.x0 + w / 2;
        else
          r.y1 = half.y0 = r.y0 + h / 2;
        regions_.push_back(half);
      }
      ++i;
    }
    return frame_error;
  }

private:
  struct Region {
    int x0, y0, x1, y1;  // tiles [x0, x1) x [y0, y1)
  };
  int tiles_x_ = 0;
  std::vector<Region> regions_;
};

}  // namespace sciray
