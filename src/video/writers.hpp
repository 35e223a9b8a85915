#pragma once
#include <memory>
#include <string>

#include "rdsim/video/video_writer.hpp"

// The encoders behind open_video (video_writer.cpp).
namespace rdsim {

std::unique_ptr<VideoWriter> open_gif(const std::string& path, int width, int height, int fps);
#ifdef RDSIM_HAVE_FFMPEG
std::unique_ptr<VideoWriter> open_mp4(const std::string& path, int width, int height, int fps);
#endif

}  // namespace rdsim
