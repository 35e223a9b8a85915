#include <catch2/catch.hpp>
#include <gif_lib.h>

#include <filesystem>
#include <regex>

#include "rdsim/video/video_writer.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;

TEST_CASE("replay --video films the episodes with a caption, GIF always, MP4 with FFmpeg", "[cli][video]") {
  rltest::ScratchDir dir("cli_video");
  const std::string run = dir / "run";
  auto r = rltest::run_rdsim("train --quiet --config configs/jaka_button.json --timesteps 1024 --log-dir " + run, dir);
  REQUIRE(r.exit_code == 0);
  r = rltest::run_rdsim("replay " + run + "/model.bin -n 2 --video " + (dir / "replay.gif") +
                            " --width 96 --height 72 --fps 10 --every 2",
                        dir);
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK_THAT(r.out, Contains("(GIF (giflib))"));

  // Frames: every 2nd step from the reset on, each episode's last step, and that one held for
  // half a second (5 frames at 10 fps).
  int expected = 0;
  const std::regex episode_line("episode \\d+: return [^,]+, length (\\d+)");
  for (std::sregex_iterator it(r.out.begin(), r.out.end(), episode_line), end; it != end; ++it) {
    const int length = std::stoi((*it)[1]);
    expected += length / 2 + 1 + length % 2 + 4;
  }
  int error = 0;
  GifFileType* gif = DGifOpenFileName((dir / "replay.gif").c_str(), &error);
  REQUIRE(gif);
  REQUIRE(DGifSlurp(gif) == GIF_OK);
  CHECK(gif->SWidth == 96);
  CHECK(gif->SHeight == 72);
  CHECK(gif->ImageCount == expected);
  DGifCloseFile(gif, &error);

  if (rdsim::video_mp4_available()) {
    r = rltest::run_rdsim("replay " + run + "/model.bin -n 1 --video " + (dir / "replay.mp4"), dir);
    REQUIRE(r.exit_code == 0);
    CHECK_THAT(r.out, Contains("H.264"));
    CHECK(rltest::slurp(dir / "replay.mp4").substr(4, 4) == "ftyp");
  }
  r = rltest::run_rdsim("replay " + run + "/model.bin -n 1 --video " + (dir / "replay.avi"), dir);
  CHECK(r.exit_code == 1);
  CHECK_THAT(r.err, Contains(".mp4 or .gif"));
}
