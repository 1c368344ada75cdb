// sciray's OSPRay C++ wrapper: glm's vector and matrix types as OSPRay types, so that they
// can be passed to setParam and Data directly. glm's matrices are column-major like
// OSPRay's: mat3x2 and mat4x3 are the linear columns followed by the translation.
// Before C++17, a program that binds OSPTypeFor<T>::value to a reference (the wrappers
// never do) defines OSPRAY_GLM_DEFINITIONS before including this in one translation unit.
#pragma once

#include <glm/mat2x2.hpp>
#include <glm/mat3x2.hpp>
#include <glm/mat3x3.hpp>
#include <glm/mat4x3.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <glm/vec4.hpp>

#include "../Traits.h"

// OSPRay reads packed components; glm's aligned gentypes (GLM_FORCE_DEFAULT_ALIGNED_GENTYPES
// with SIMD intrinsics) pad a vec3 to 16 bytes.
static_assert(sizeof(glm::vec3) == 3 * sizeof(float) && sizeof(glm::mat4x3) == 12 * sizeof(float),
              "ospray_cpp/ext/glm.h needs glm's packed types (no GLM_FORCE_DEFAULT_ALIGNED_GENTYPES)");

// Each type's OSPTypeFor specialization and, on request, its out-of-line definition (which
// C++17 makes implicit, and deprecates).
#if defined(OSPRAY_GLM_DEFINITIONS) && __cplusplus < 201703L
#define SCIRAY_OSP_GLM_TYPE(type, osp_type) \
  OSPTYPEFOR_SPECIALIZATION(glm::type, osp_type) OSPTYPEFOR_DEFINITION(glm::type);
#else
#define SCIRAY_OSP_GLM_TYPE(type, osp_type) OSPTYPEFOR_SPECIALIZATION(glm::type, osp_type)
#endif

namespace ospray {

SCIRAY_OSP_GLM_TYPE(vec2, OSP_VEC2F)
SCIRAY_OSP_GLM_TYPE(vec3, OSP_VEC3F)
SCIRAY_OSP_GLM_TYPE(vec4, OSP_VEC4F)
SCIRAY_OSP_GLM_TYPE(ivec2, OSP_VEC2I)
SCIRAY_OSP_GLM_TYPE(ivec3, OSP_VEC3I)
SCIRAY_OSP_GLM_TYPE(ivec4, OSP_VEC4I)
SCIRAY_OSP_GLM_TYPE(uvec2, OSP_VEC2UI)
SCIRAY_OSP_GLM_TYPE(uvec3, OSP_VEC3UI)
SCIRAY_OSP_GLM_TYPE(uvec4, OSP_VEC4UI)
SCIRAY_OSP_GLM_TYPE(mat2x2, OSP_LINEAR2F)
SCIRAY_OSP_GLM_TYPE(mat3x3, OSP_LINEAR3F)
SCIRAY_OSP_GLM_TYPE(mat3x2, OSP_AFFINE2F)
SCIRAY_OSP_GLM_TYPE(mat4x3, OSP_AFFINE3F)

}  // namespace ospray

#undef SCIRAY_OSP_GLM_TYPE
