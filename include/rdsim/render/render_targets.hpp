#pragma once
#include <cstdint>

namespace rdsim {

// Where one frame goes; each image is height x width, row-major, row 0 = the TOP of the image, and
// a null pointer skips it. All three come from the same drawing of the scene.
struct RenderTargets {
  std::uint8_t* rgb = nullptr;           // 3 bytes per pixel
  // Metres from the camera's plane to the surface seen, along the view direction (the camera's
  // z axis: what depth cameras report); the camera's zfar where nothing is drawn.
  float* depth = nullptr;
  std::uint8_t* segmentation = nullptr;  // the DrawItem::segment seen at each pixel, 0 for background
};

}  // namespace rdsim
