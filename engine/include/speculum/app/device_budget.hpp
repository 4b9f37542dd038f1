// Whether a scene fits the device before anything of it is uploaded (issue 15): a small glTF can
// ask for gigabytes, and vkAllocateMemory past the heap ended in a driver crash.
#pragma once

#include "speculum/gpu/context.hpp"
#include "speculum/scene.hpp"

namespace speculum::app {

// Throws Error(BadInput) naming the scene file, with the numbers, when its vertex, index and
// texture bytes exceed limits::kSceneHeapShare of the largest device-local heap, when one buffer
// exceeds the device's maxMemoryAllocationSize, or when a texture is
// larger than maxImageDimension2D.
void checkSceneFitsDevice(const gpu::Context& ctx, const Scene& scene);

}  // namespace speculum::app
