#include "rdsim/video/video_writer.hpp"

#include "rdsim/core/error.hpp"
#include "writers.hpp"

namespace rdsim {

bool video_mp4_available() {
#ifdef RDSIM_HAVE_FFMPEG
  return true;
#else
  return false;
#endif
}

std::unique_ptr<VideoWriter> open_video(const std::string& path, int width, int height, int fps) {
  if (width <= 0 || height <= 0) throw Error(path + ": frames of " + std::to_string(width) + "x" + std::to_string(height));
  if (fps < 1 || fps > 240) throw Error(path + ": expected 1 to 240 frames per second, not " + std::to_string(fps));
  auto ends_with = [&](const char* ext) {
    const std::string e = ext;
    return path.size() > e.size() && path.compare(path.size() - e.size(), e.size(), e) == 0;
  };
  if (ends_with(".gif")) return open_gif(path, width, height, fps);
  if (ends_with(".mp4")) {
#ifdef RDSIM_HAVE_FFMPEG
    return open_mp4(path, width, height, fps);
#else
    throw Error(path + ": this rdsim was built without FFmpeg (libavcodec-dev, libavformat-dev, libswscale-dev), "
                       "so it writes .gif videos only");
#endif
  }
  throw Error(path + ": expected a video file name ending in .mp4 or .gif");
}

}  // namespace rdsim
