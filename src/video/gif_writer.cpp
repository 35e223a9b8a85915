// GIF through giflib: one palette for the whole video (the first frame quantised by giflib, plus
// the overlay's colours and a transparent index), and each later frame stored as only the rectangle
// that changed, its unchanged pixels transparent, so a robot moving over a still scene stays small.
#include <gif_lib.h>

#include <array>
#include <cstdio>
#include <cstring>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "writers.hpp"

namespace rdsim {
namespace {

constexpr int palette_size = 256;
constexpr int transparent = 255;      // palette index of "unchanged since the last frame"
constexpr int quantised_colours = 248;  // from the first frame; the rest are fixed colours below
const std::array<GifColorType, 7> fixed_colours = {{{255, 255, 255}, {0, 0, 0}, {115, 242, 115}, {64, 64, 64},
                                                    {128, 128, 128}, {192, 192, 192}, {30, 30, 30}}};

int append_bytes(GifFileType* gif, const GifByteType* data, int length) {
  static_cast<std::string*>(gif->UserData)->append(reinterpret_cast<const char*>(data), static_cast<std::size_t>(length));
  return length;
}

class GifWriter final : public VideoWriter {
public:
  GifWriter(std::string path, int width, int height, int fps)
      : path_(std::move(path)), width_(width), height_(height), delay_cs_((100 + fps / 2) / fps),
        previous_(static_cast<std::size_t>(width) * height), current_(previous_.size()) {
    int error = 0;
    gif_ = EGifOpen(&bytes_, append_bytes, &error);
    if (!gif_) throw Error(path_ + ": cannot start the GIF encoder: " + GifErrorString(error));
    nearest_.fill(-1);
  }
  ~GifWriter() override {
    if (gif_) {
      int error = 0;
      EGifCloseFile(gif_, &error);
    }
  }

  std::string format() const override { return "GIF (giflib)"; }

  void add_frame(const Image& frame) override {
    if (frame.width != width_ || frame.height != height_) throw Error(path_ + ": frames changed size");
    if (frames_ == 0) start(frame);
    for (std::size_t i = 0; i < current_.size(); ++i) {
      current_[i] = static_cast<GifPixelType>(palette_index(&frame.rgb[3 * i]));
    }
    // The rectangle that changed (the whole first frame).
    int x0 = 0, y0 = 0, x1 = width_ - 1, y1 = height_ - 1;
    if (frames_ > 0) {
      x0 = width_, y0 = height_, x1 = -1, y1 = -1;
      for (int y = 0; y < height_; ++y) {
        for (int x = 0; x < width_; ++x) {
          const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
          if (current_[i] == previous_[i]) continue;
          x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
        }
      }
      if (x1 < 0) x0 = x1 = y0 = y1 = 0;  // nothing changed: one transparent pixel keeps the timing
    }
    GraphicsControlBlock gcb{};
    gcb.DisposalMode = DISPOSE_DO_NOT;
    gcb.DelayTime = delay_cs_;
    gcb.TransparentColor = frames_ > 0 ? transparent : NO_TRANSPARENT_COLOR;
    GifByteType extension[4];
    EGifGCBToExtension(&gcb, extension);
    check(EGifPutExtension(gif_, GRAPHICS_EXT_FUNC_CODE, 4, extension));
    const int w = x1 - x0 + 1, h = y1 - y0 + 1;
    check(EGifPutImageDesc(gif_, x0, y0, w, h, false, nullptr));
    std::vector<GifPixelType> line(static_cast<std::size_t>(w));
    for (int y = y0; y <= y1; ++y) {
      for (int x = x0; x <= x1; ++x) {
        const std::size_t i = static_cast<std::size_t>(y) * width_ + x;
        line[static_cast<std::size_t>(x - x0)] =
            frames_ > 0 && current_[i] == previous_[i] ? static_cast<GifPixelType>(transparent) : current_[i];
      }
      check(EGifPutLine(gif_, line.data(), w));
    }
    previous_.swap(current_);
    ++frames_;
  }

  void close() override {
    if (!gif_) return;
    if (frames_ == 0) throw Error(path_ + ": no frames to write");
    int error = 0;
    const int status = EGifCloseFile(gif_, &error);
    gif_ = nullptr;
    if (status != GIF_OK) throw Error(path_ + ": cannot finish the GIF: " + GifErrorString(error));
    write_file_atomic(path_, bytes_);
  }

private:
  void check(int status) {
    if (status != GIF_OK) throw Error(path_ + ": GIF encoder: " + GifErrorString(gif_->Error));
  }

  // The palette: giflib's median cut of the first frame, then fixed greys and the overlay's colours.
  void start(const Image& first) {
    const std::size_t n = static_cast<std::size_t>(width_) * height_;
    std::vector<GifByteType> r(n), g(n), b(n), out(n);
    for (std::size_t i = 0; i < n; ++i) r[i] = first.rgb[3 * i], g[i] = first.rgb[3 * i + 1], b[i] = first.rgb[3 * i + 2];
    std::array<GifColorType, palette_size> colours{};
    int count = quantised_colours;
    if (GifQuantizeBuffer(static_cast<unsigned>(width_), static_cast<unsigned>(height_), &count, r.data(), g.data(),
                          b.data(), out.data(), colours.data()) != GIF_OK) {
      throw Error(path_ + ": cannot choose the GIF's colours");
    }
    for (const auto& c : fixed_colours) colours[static_cast<std::size_t>(count++)] = c;
    used_ = count;
    palette_.assign(colours.begin(), colours.end());
    ColorMapObject* map = GifMakeMapObject(palette_size, colours.data());
    const int screen = EGifPutScreenDesc(gif_, width_, height_, 8, 0, map);
    GifFreeMapObject(map);
    check(screen);
    // Loop for ever (the NETSCAPE2.0 application extension).
    check(EGifPutExtensionLeader(gif_, APPLICATION_EXT_FUNC_CODE));
    check(EGifPutExtensionBlock(gif_, 11, "NETSCAPE2.0"));
    const GifByteType loop[3] = {1, 0, 0};
    check(EGifPutExtensionBlock(gif_, 3, loop));
    check(EGifPutExtensionTrailer(gif_));
  }

  // The nearest palette colour, cached per 5-bit-per-channel colour cube cell.
  int palette_index(const std::uint8_t* rgb) {
    const int key = (rgb[0] >> 3) << 10 | (rgb[1] >> 3) << 5 | (rgb[2] >> 3);
    int& cached = nearest_[static_cast<std::size_t>(key)];
    if (cached >= 0) return cached;
    const int r = (rgb[0] & 0xf8) | 4, g = (rgb[1] & 0xf8) | 4, b = (rgb[2] & 0xf8) | 4;  // the cell's centre
    int best = 0, best_d = 1 << 30;
    for (int k = 0; k < used_; ++k) {
      const GifColorType& c = palette_[static_cast<std::size_t>(k)];
      const int d = (c.Red - r) * (c.Red - r) * 3 + (c.Green - g) * (c.Green - g) * 4 + (c.Blue - b) * (c.Blue - b) * 2;
      if (d < best_d) best = k, best_d = d;
    }
    return cached = best;
  }

  std::string path_, bytes_;
  int width_, height_, delay_cs_;
  GifFileType* gif_ = nullptr;
  std::vector<GifColorType> palette_;
  int used_ = 0;
  std::array<int, 32 * 32 * 32> nearest_{};
  std::vector<GifPixelType> previous_, current_;
  long long frames_ = 0;
};

}  // namespace

std::unique_ptr<VideoWriter> open_gif(const std::string& path, int width, int height, int fps) {
  return std::make_unique<GifWriter>(path, width, height, fps);
}

}  // namespace rdsim
