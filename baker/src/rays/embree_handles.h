#pragma once
// Owning handles for Embree 3 devices and scenes, and Embree's error codes
// by name: shared by the ray caster (embree_ray_caster.cpp) and the
// proxy builder's nearest-side index (nearest_side_index.cpp).

#include <embree3/rtcore.h>

#include <memory>
#include <type_traits>

namespace svit::baker {

struct EmbreeDeviceRelease {
  void operator()(RTCDevice device) const { rtcReleaseDevice(device); }
};
struct EmbreeSceneRelease {
  void operator()(RTCScene scene) const { rtcReleaseScene(scene); }
};
using EmbreeDevice = std::unique_ptr<std::remove_pointer_t<RTCDevice>, EmbreeDeviceRelease>;
using EmbreeScene = std::unique_ptr<std::remove_pointer_t<RTCScene>, EmbreeSceneRelease>;

/// "invalid argument", "out of memory", ... for messages.
inline const char* embreeErrorName(RTCError code) {
  switch (code) {
    case RTC_ERROR_NONE: return "no error";
    case RTC_ERROR_UNKNOWN: return "unknown error";
    case RTC_ERROR_INVALID_ARGUMENT: return "invalid argument";
    case RTC_ERROR_INVALID_OPERATION: return "invalid operation";
    case RTC_ERROR_OUT_OF_MEMORY: return "out of memory";
    case RTC_ERROR_UNSUPPORTED_CPU: return "unsupported CPU";
    case RTC_ERROR_CANCELLED: return "cancelled";
  }
  return "unrecognised error code";
}

}  // namespace svit::baker
