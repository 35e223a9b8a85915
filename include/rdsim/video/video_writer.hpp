#pragma once
#include <memory>
#include <string>

#include "rdsim/core/env.hpp"

// Videos of what an env draws (Env::render frames): MP4 (H.264) through FFmpeg's libraries when
// rdsim was built with them, GIF through giflib always. The file appears when the writer is closed
// (written beside it, then renamed), so a failed run never leaves half a video.
namespace rdsim {

class VideoWriter {
public:
  virtual ~VideoWriter() = default;
  // Frames must all have the size the writer was opened with.
  virtual void add_frame(const Image& frame) = 0;
  // Finishes the file. Throws rdsim::Error when it cannot be written.
  virtual void close() = 0;
  // What encodes it, for messages: "H.264 (libx264)", "GIF (giflib)".
  virtual std::string format() const = 0;
};

// A writer for `path` by its extension: .mp4 (needs FFmpeg) or .gif; fps frames per second.
// Throws rdsim::Error for another extension, for .mp4 in a build without FFmpeg (saying so), or
// when the encoder cannot start.
std::unique_ptr<VideoWriter> open_video(const std::string& path, int width, int height, int fps);

// Whether this build writes MP4 (FFmpeg's libraries were found when it was built).
bool video_mp4_available();

}  // namespace rdsim
