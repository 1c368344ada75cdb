#pragma once
// OSPRay's `mpiRaycast` renderer (modules/mpi/.../DistributedRaycast), the renderer of its
// data-parallel device, is sciray's `ao` renderer with other defaults:
//  - surfaces: an eye light, the colour (geometry colour times material kd) times |n·ω|,
//    times the unoccluded fraction of `aoSamples` cosine-weighted AO rays within
//    `aoDistance` (AO rays see all the data the rank holds, not only its region);
//    the whole colour is added (not d times it) and 1 − d of what lies behind shows
//    through, d the material's alone (the geometry colour's alpha is not opacity), as
//    OSPRay blends (colour, d); with these, OSPRay's own data-parallel scenes of
//    transparent spheres and isosurfaces match its images. No lights: OSPRay reads
//    `shadows` but its light loop is compiled out.
//  - volumes: emission-absorption along the ray, unlit, over the region's interval.
//  - defaults: aoSamples 0 (ao's is 1), aoDistance 1e20, volumeSamplingRate 1.
// What differs from OSPRay's, knowingly: OSPRay jitters each pixel's volume samples and
// aligns their grid across ranks (sciray's march starts at the region's entry and cuts
// its last step at the exit: the midpoint rule over the split interval); OSPRay's AO
// rays use its own Halton points, sciray's the renderer's per-pixel sequence.
#include "sciray/render/scivis.hpp"

namespace sciray::distributed {

/// The renderer parameters of OSPRay's `mpiRaycast` at its defaults (set the fields of
/// the common parameters — background, materials — as for any renderer).
inline AOParams mpi_raycast_params() {
  AOParams params;
  params.ao_samples = 0;
  params.ao_distance = 1e20f;
  params.ao_intensity = 1.f;
  params.color_alpha_is_opacity = false;
  params.opacity_weights_color = false;
  return params;
}

}  // namespace sciray::distributed
