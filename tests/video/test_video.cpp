#include <catch2/catch.hpp>
#include <gif_lib.h>

#include <cmath>
#include <csignal>
#include <filesystem>
#include <sys/resource.h>
#include <unistd.h>
#include <vector>

#include "rdsim/core/error.hpp"
#include "rdsim/video/overlay.hpp"
#include "rdsim/video/video_writer.hpp"
#include "../scratch_dir.hpp"

#ifdef RDSIM_HAVE_FFMPEG
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
}
#endif

namespace fs = std::filesystem;

namespace {

std::string scratch(const std::string& name) {
  static const rdsim::test::ScratchDir root("video");  // removed when the test program exits
  return root / name;
}

// A still gradient with a red square that moves right by 4 pixels a frame.
rdsim::Image test_frame(int w, int h, int k) {
  rdsim::Image f;
  f.width = w;
  f.height = h;
  f.rgb.resize(static_cast<std::size_t>(w) * h * 3);
  for (int y = 0; y < h; ++y) {
    for (int x = 0; x < w; ++x) {
      std::uint8_t* p = &f.rgb[(static_cast<std::size_t>(y) * w + x) * 3];
      const bool square = x >= 10 + 4 * k && x < 40 + 4 * k && y >= 30 && y < 60;
      p[0] = square ? 220 : static_cast<std::uint8_t>(60 + x * 120 / w);
      p[1] = square ? 30 : static_cast<std::uint8_t>(90 + y * 100 / h);
      p[2] = square ? 30 : 160;
    }
  }
  return f;
}

double mean_abs_difference(const std::vector<std::uint8_t>& a, const std::vector<std::uint8_t>& b) {
  double sum = 0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += std::abs(a[i] - b[i]);
  return sum / static_cast<double>(a.size());
}

}  // namespace

TEST_CASE("GIF video: every frame, a looping file, colours close to the source", "[video]") {
  const std::string path = scratch("moving.gif");
  const int w = 160, h = 120, n = 12;
  auto video = rdsim::open_video(path, w, h, 20);
  CHECK(video->format() == "GIF (giflib)");
  for (int k = 0; k < n; ++k) video->add_frame(test_frame(w, h, k));
  CHECK_FALSE(fs::exists(path));  // written when closed
  video->close();

  int error = 0;
  GifFileType* gif = DGifOpenFileName(path.c_str(), &error);
  REQUIRE(gif);
  REQUIRE(DGifSlurp(gif) == GIF_OK);
  CHECK(gif->SWidth == w);
  CHECK(gif->SHeight == h);
  REQUIRE(gif->ImageCount == n);
  bool loops = false;
  for (int e = 0; e < gif->SavedImages[0].ExtensionBlockCount; ++e) {  // extensions before the first image
    const ExtensionBlock& b = gif->SavedImages[0].ExtensionBlocks[e];
    if (b.Function == APPLICATION_EXT_FUNC_CODE && b.ByteCount == 11 && std::memcmp(b.Bytes, "NETSCAPE2.0", 11) == 0) loops = true;
  }
  CHECK(loops);
  // Compose the frames as a viewer does and compare each with its source.
  std::vector<std::uint8_t> canvas(static_cast<std::size_t>(w) * h * 3, 0);
  const ColorMapObject* map = gif->SColorMap;
  REQUIRE(map);
  for (int k = 0; k < n; ++k) {
    const SavedImage& image = gif->SavedImages[k];
    GraphicsControlBlock gcb;
    REQUIRE(DGifSavedExtensionToGCB(gif, k, &gcb) == GIF_OK);
    CHECK(gcb.DelayTime == 5);
    const GifImageDesc& d = image.ImageDesc;
    if (k > 0) CHECK(d.Width * d.Height < w * h / 2);  // only what changed
    for (int y = 0; y < d.Height; ++y) {
      for (int x = 0; x < d.Width; ++x) {
        const int index = image.RasterBits[y * d.Width + x];
        if (index == gcb.TransparentColor) continue;
        std::uint8_t* p = &canvas[(static_cast<std::size_t>(d.Top + y) * w + d.Left + x) * 3];
        p[0] = map->Colors[index].Red, p[1] = map->Colors[index].Green, p[2] = map->Colors[index].Blue;
      }
    }
    CHECK(mean_abs_difference(canvas, test_frame(w, h, k).rgb) < 6.0);
  }
  DGifCloseFile(gif, &error);
  CHECK(fs::file_size(path) < 40000);
}

TEST_CASE("video: bad names, sizes and empty videos are errors", "[video]") {
  CHECK_THROWS_WITH(rdsim::open_video(scratch("x.avi"), 10, 10, 20), Catch::Contains(".mp4 or .gif"));
  CHECK_THROWS_AS(rdsim::open_video(scratch("x.gif"), 0, 10, 20), rdsim::Error);
  CHECK_THROWS_AS(rdsim::open_video(scratch("x.gif"), 10, 10, 0), rdsim::Error);
  auto gif = rdsim::open_video(scratch("x.gif"), 10, 10, 20);
  CHECK_THROWS_WITH(gif->add_frame(test_frame(20, 10, 0)), Catch::Contains("changed size"));
  CHECK_THROWS_WITH(gif->close(), Catch::Contains("no frames"));
  CHECK_FALSE(fs::exists(scratch("x.gif")));
  if (!rdsim::video_mp4_available()) {
    CHECK_THROWS_WITH(rdsim::open_video(scratch("x.mp4"), 10, 10, 20), Catch::Contains("built without FFmpeg"));
  }
}

TEST_CASE("overlay: text in a dark box at the top left, the rest of the frame untouched", "[video]") {
  rdsim::Image frame = test_frame(320, 240, 0);
  const rdsim::Image before = frame;
  rdsim::draw_overlay(frame, {{"episode 1  step 12", false}, {"return -3.5", false}, {"success", true}});
  int changed_outside = 0, changed_inside = 0, green = 0;
  for (int y = 0; y < 240; ++y) {
    for (int x = 0; x < 320; ++x) {
      const std::size_t i = (static_cast<std::size_t>(y) * 320 + x) * 3;
      const bool changed = std::memcmp(&frame.rgb[i], &before.rgb[i], 3) != 0;
      if (x > 200 || y > 80) changed_outside += changed;
      else changed_inside += changed;
      green += frame.rgb[i + 1] > 200 && frame.rgb[i] < 160 && frame.rgb[i + 2] < 160;
    }
  }
  CHECK(changed_outside == 0);
  CHECK(changed_inside > 3000);
  CHECK(green > 20);  // the highlighted line
}

#ifdef RDSIM_HAVE_FFMPEG
TEST_CASE("MP4 video: H.264 that FFmpeg decodes back to the frames", "[video]") {
  const std::string path = scratch("moving.mp4");
  const int w = 161, h = 121, n = 30;  // odd sizes: 4:2:0 needs even ones
  auto video = rdsim::open_video(path, w, h, 25);
  CHECK(video->format().find("H.264") == 0);
  for (int k = 0; k < n; ++k) video->add_frame(test_frame(w, h, k % 20));
  video->close();

  AVFormatContext* format = nullptr;
  REQUIRE(avformat_open_input(&format, path.c_str(), nullptr, nullptr) == 0);
  REQUIRE(avformat_find_stream_info(format, nullptr) >= 0);
  REQUIRE(format->nb_streams == 1);
  const AVCodecParameters* par = format->streams[0]->codecpar;
  CHECK(par->codec_id == AV_CODEC_ID_H264);
  CHECK(par->width == 162);
  CHECK(par->height == 122);
  CHECK(par->format == AV_PIX_FMT_YUV420P);
  const AVCodec* codec = avcodec_find_decoder(par->codec_id);
  AVCodecContext* decoder = avcodec_alloc_context3(codec);
  avcodec_parameters_to_context(decoder, par);
  REQUIRE(avcodec_open2(decoder, codec, nullptr) == 0);
  AVPacket* packet = av_packet_alloc();
  AVFrame* frame = av_frame_alloc();
  int decoded = 0;
  double first_luma = -1;
  auto drain = [&] {
    while (avcodec_receive_frame(decoder, frame) == 0) {
      if (decoded++ == 0) {
        double sum = 0;
        for (int y = 0; y < frame->height; ++y)
          for (int x = 0; x < frame->width; ++x) sum += frame->data[0][y * frame->linesize[0] + x];
        first_luma = sum / (frame->width * frame->height);
      }
    }
  };
  while (av_read_frame(format, packet) == 0) {
    while (avcodec_send_packet(decoder, packet) == AVERROR(EAGAIN)) drain();
    av_packet_unref(packet);
    drain();
  }
  while (avcodec_send_packet(decoder, nullptr) == AVERROR(EAGAIN)) drain();
  drain();
  INFO("frames in the stream: " << format->streams[0]->nb_frames);
  CHECK(decoded == n);
  // The source's mean luma (BT.601, video range) is about 16 + 219 * 0.45.
  double luma = 0;
  const rdsim::Image src = test_frame(w, h, 0);
  for (std::size_t i = 0; i < src.rgb.size(); i += 3) luma += 0.299 * src.rgb[i] + 0.587 * src.rgb[i + 1] + 0.114 * src.rgb[i + 2];
  luma = 16 + luma / (w * h) * 219.0 / 255.0;
  CHECK(first_luma == Approx(luma).margin(4));
  av_frame_free(&frame);
  av_packet_free(&packet);
  avcodec_free_context(&decoder);
  avformat_close_input(&format);
}
#endif

TEST_CASE("video: a write that fails (a full disk) leaves neither a .part file nor a partial video", "[video]") {
  std::vector<std::string> names = {"full.gif"};
#ifdef RDSIM_HAVE_FFMPEG
  names.push_back("full.mp4");
#endif
  for (const std::string& name : names) {
    INFO(name);
    const std::string path = scratch(name);
    // A file size limit of 0 bytes fails every write as a full disk does (EFBIG instead of ENOSPC).
    struct sigaction ignore {}, previous {};
    ignore.sa_handler = SIG_IGN;
    ::sigaction(SIGXFSZ, &ignore, &previous);
    rlimit before{};
    ::getrlimit(RLIMIT_FSIZE, &before);
    rlimit none = before;
    none.rlim_cur = 0;
    ::setrlimit(RLIMIT_FSIZE, &none);
    bool failed = false;
    try {
      auto video = rdsim::open_video(path, 64, 48, 10);
      for (int k = 0; k < 5; ++k) video->add_frame(test_frame(64, 48, k));
      video->close();
    } catch (const rdsim::Error&) {
      failed = true;
    }
    ::setrlimit(RLIMIT_FSIZE, &before);
    ::sigaction(SIGXFSZ, &previous, nullptr);
    CHECK(failed);
    // Before: a failure while the MP4 header was written left an empty NAME.part behind.
    CHECK_FALSE(fs::exists(path + ".part"));
    CHECK_FALSE(fs::exists(path));
  }
}
