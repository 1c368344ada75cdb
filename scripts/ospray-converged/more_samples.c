// Preloaded into OSPRay's test suite (LD_PRELOAD) by scripts/ospray-converged.sh: it wraps
// ospSetParam of whichever runtime is loaded, OSPRay's or sciray's, so that a test's own
// scene renders with more samples (to compare converged images instead of noise) or with
// one parameter changed (to take a scene apart).
//   OSPRAY_SAMPLES_SCALE=N         multiplies every renderer's pixelSamples by N
//   OSPRAY_LIGHT_SAMPLES=N         also sets the renderer's lightSamples to N (a path
//                                  tracer with 0 finds lights by BSDF sampling alone)
//   OSPRAY_VOLUME_RATE=R           also sets the renderer's volumeSamplingRate to R (to
//                                  converge a runtime that samples volumes coarsely)
//   OSPRAY_INT_OVERRIDE=name=v     replaces every int parameter `name` by v
//   OSPRAY_FLOAT_OVERRIDE=name:old=v  replaces float parameters `name` that were set to old
#define _GNU_SOURCE
#include <dlfcn.h>
#include <stdlib.h>
#include <string.h>

#include <ospray/ospray.h>

typedef void (*SetParam)(OSPObject, const char *, OSPDataType, const void *);

static int names_match(const char *id, const char *spec, const char *spec_end)
{
  return strlen(id) == (size_t)(spec_end - spec) && strncmp(id, spec, spec_end - spec) == 0;
}

void ospSetParam(OSPObject object, const char *id, OSPDataType type, const void *mem)
{
  static SetParam next;
  if (!next)
    next = (SetParam)dlsym(RTLD_NEXT, "ospSetParam");

  const char *scale = getenv("OSPRAY_SAMPLES_SCALE");
  if (scale && type == OSP_INT && strcmp(id, "pixelSamples") == 0) {
    const int samples = *(const int *)mem * atoi(scale);
    next(object, id, type, &samples);
    const char *light_samples = getenv("OSPRAY_LIGHT_SAMPLES");
    if (light_samples) {
      const int n = atoi(light_samples);
      next(object, "lightSamples", OSP_INT, &n);
    }
    const char *volume_rate = getenv("OSPRAY_VOLUME_RATE");
    if (volume_rate) {
      const float rate = (float)atof(volume_rate);
      next(object, "volumeSamplingRate", OSP_FLOAT, &rate);
    }
    return;
  }
  const char *int_override = getenv("OSPRAY_INT_OVERRIDE");
  if (int_override && type == OSP_INT) {
    const char *eq = strchr(int_override, '=');
    if (eq && names_match(id, int_override, eq)) {
      const int value = atoi(eq + 1);
      next(object, id, type, &value);
      return;
    }
  }
  const char *float_override = getenv("OSPRAY_FLOAT_OVERRIDE");
  if (float_override && type == OSP_FLOAT) {
    const char *colon = strchr(float_override, ':'), *eq = strchr(float_override, '=');
    if (colon && eq && names_match(id, float_override, colon)
        && *(const float *)mem == (float)atof(colon + 1)) {
      const float value = (float)atof(eq + 1);
      next(object, id, type, &value);
      return;
    }
  }
  next(object, id, type, mem);
}
