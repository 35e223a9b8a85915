// MP4 through FFmpeg's libraries (built only when they are found: see CMakeLists.txt). H.264 with
// libx264 when libavcodec has it (Debian's does), else any H.264 encoder, else MPEG-4 Part 2; 4:2:0
// pixels and the index at the front of the file (faststart), which browsers and players expect.
extern "C" {
#include <libavcodec/avcodec.h>
#include <libavformat/avformat.h>
#include <libavutil/log.h>
#include <libavutil/opt.h>
#include <libswscale/swscale.h>
}

#include <cstdio>
#include <filesystem>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "writers.hpp"

namespace rdsim {
namespace {

std::string av_message(int code) {
  char text[AV_ERROR_MAX_STRING_SIZE] = "";
  av_strerror(code, text, sizeof text);
  return text;
}

class Mp4Writer final : public VideoWriter {
public:
  Mp4Writer(std::string path, int width, int height, int fps)
      : path_(std::move(path)), temp_(path_ + ".part"), width_(width), height_(height) {
    try {
      create_parent_folders(path_);  // like every other output file: its folder is made
      open(fps);
    } catch (...) {
      // The destructor does not run for a constructor that throws: no .part may stay behind (a
      // full disk fails the header after the file was created).
      release();
      std::error_code ec;
      std::filesystem::remove(temp_, ec);
      throw;
    }
  }
  ~Mp4Writer() override {
    release();
    std::error_code ec;
    if (!closed_) std::filesystem::remove(temp_, ec);
  }

  std::string format() const override { return format_; }

  void add_frame(const Image& frame) override {
    if (frame.width != width_ || frame.height != height_) throw Error(path_ + ": frames changed size");
    check(av_frame_make_writable(frame_), "frame");
    const std::uint8_t* src[1] = {frame.rgb.data()};
    const int src_stride[1] = {3 * width_};
    sws_scale(scaler_, src, src_stride, 0, height_, frame_->data, frame_->linesize);
    frame_->pts = next_pts_++;
    encode(frame_);
  }

  void close() override {
    if (closed_) return;
    encode(nullptr);  // drain the encoder
    check(av_write_trailer(format_ctx_), "trailer");
    release();
    std::error_code ec;
    std::filesystem::rename(temp_, path_, ec);
    if (ec) throw Error(path_ + ": cannot write: " + ec.message());
    closed_ = true;
  }

private:
  void check(int code, const char* what) {
    if (code < 0) throw Error(path_ + ": FFmpeg (" + what + "): " + av_message(code));
  }

  void open(int fps) {
    av_log_set_level(AV_LOG_ERROR);  // the encoders' statistics are not the user's business
    check(avformat_alloc_output_context2(&format_ctx_, nullptr, "mp4", temp_.c_str()), "mp4 muxer");
    const AVCodec* codec = avcodec_find_encoder_by_name("libx264");
    if (!codec) codec = avcodec_find_encoder(AV_CODEC_ID_H264);
    if (!codec) codec = avcodec_find_encoder(AV_CODEC_ID_MPEG4);
    if (!codec) throw Error(path_ + ": this FFmpeg has neither an H.264 nor an MPEG-4 encoder");
    format_ = codec->id == AV_CODEC_ID_H264 ? std::string("H.264 (") + codec->name + ")"
                                            : std::string("MPEG-4 Part 2 (") + codec->name + ")";
    stream_ = avformat_new_stream(format_ctx_, nullptr);
    if (!stream_) throw Error(path_ + ": FFmpeg: cannot add a stream");
    codec_ctx_ = avcodec_alloc_context3(codec);
    // 4:2:0 needs even sizes: the picture is scaled by at most one pixel.
    codec_ctx_->width = width_ + (width_ & 1);
    codec_ctx_->height = height_ + (height_ & 1);
    codec_ctx_->pix_fmt = AV_PIX_FMT_YUV420P;
    codec_ctx_->time_base = AVRational{1, fps};
    codec_ctx_->framerate = AVRational{fps, 1};
    codec_ctx_->gop_size = 2 * fps;
    if (codec->id == AV_CODEC_ID_H264) {
      av_opt_set(codec_ctx_->priv_data, "preset", "medium", 0);
      av_opt_set(codec_ctx_->priv_data, "crf", "23", 0);
    } else {
      codec_ctx_->bit_rate = 2'000'000;
    }
    if (format_ctx_->oformat->flags & AVFMT_GLOBALHEADER) codec_ctx_->flags |= AV_CODEC_FLAG_GLOBAL_HEADER;
    check(avcodec_open2(codec_ctx_, codec, nullptr), "encoder");
    check(avcodec_parameters_from_context(stream_->codecpar, codec_ctx_), "stream");
    stream_->time_base = codec_ctx_->time_base;
    check(avio_open(&format_ctx_->pb, temp_.c_str(), AVIO_FLAG_WRITE), "open the file");
    AVDictionary* options = nullptr;
    av_dict_set(&options, "movflags", "+faststart", 0);
    const int header = avformat_write_header(format_ctx_, &options);
    av_dict_free(&options);
    check(header, "header");

    frame_ = av_frame_alloc();
    frame_->format = codec_ctx_->pix_fmt;
    frame_->width = codec_ctx_->width;
    frame_->height = codec_ctx_->height;
    check(av_frame_get_buffer(frame_, 0), "frame");
    packet_ = av_packet_alloc();
    scaler_ = sws_getContext(width_, height_, AV_PIX_FMT_RGB24, codec_ctx_->width, codec_ctx_->height,
                             AV_PIX_FMT_YUV420P, SWS_BICUBIC, nullptr, nullptr, nullptr);
    if (!scaler_ || !frame_ || !packet_) throw Error(path_ + ": FFmpeg: out of memory");
  }

  void encode(AVFrame* frame) {
    check(avcodec_send_frame(codec_ctx_, frame), "encode");
    for (;;) {
      const int got = avcodec_receive_packet(codec_ctx_, packet_);
      if (got == AVERROR(EAGAIN) || got == AVERROR_EOF) return;
      check(got, "encode");
      // One frame long: without a duration the MP4's edit list would end before the last frame.
      if (packet_->duration == 0) packet_->duration = 1;
      av_packet_rescale_ts(packet_, codec_ctx_->time_base, stream_->time_base);
      packet_->stream_index = stream_->index;
      check(av_interleaved_write_frame(format_ctx_, packet_), "write");
    }
  }

  void release() {
    if (scaler_) sws_freeContext(scaler_);
    scaler_ = nullptr;
    av_packet_free(&packet_);
    av_frame_free(&frame_);
    avcodec_free_context(&codec_ctx_);
    if (format_ctx_) {
      if (format_ctx_->pb) avio_closep(&format_ctx_->pb);
      avformat_free_context(format_ctx_);
      format_ctx_ = nullptr;
    }
  }

  std::string path_, temp_, format_;
  int width_, height_;
  AVFormatContext* format_ctx_ = nullptr;
  AVStream* stream_ = nullptr;
  AVCodecContext* codec_ctx_ = nullptr;
  AVFrame* frame_ = nullptr;
  AVPacket* packet_ = nullptr;
  SwsContext* scaler_ = nullptr;
  std::int64_t next_pts_ = 0;
  bool closed_ = false;
};

}  // namespace

std::unique_ptr<VideoWriter> open_mp4(const std::string& path, int width, int height, int fps) {
  return std::make_unique<Mp4Writer>(path, width, height, fps);
}

}  // namespace rdsim
