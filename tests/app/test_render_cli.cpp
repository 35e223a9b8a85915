#include <catch2/catch.hpp>
#include <filesystem>

#include "rdsim/app/render.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"

namespace fs = std::filesystem;

namespace {

std::uint32_t be32(const std::string& s, size_t at) {
  std::uint32_t v = 0;
  for (size_t i = 0; i < 4; ++i) v = (v << 8) | static_cast<unsigned char>(s[at + i]);
  return v;
}

}  // namespace

TEST_CASE("rdsim render writes the agent's view as a valid PNG", "[render_cli]") {
  const fs::path dir = fs::temp_directory_path() / "rdsim_test_render_cli";
  fs::remove_all(dir);
  fs::create_directories(dir);
  rdsim::RenderOptions o;
  o.env = "jaka_button";
  o.out_path = (dir / "view1.png").string();
  o.width = 40;
  o.height = 30;
  REQUIRE(rdsim::render_command(o) == 0);
  const std::string png = rdsim::read_file(o.out_path);
  REQUIRE(png.size() > 40u * 30u * 3u);
  CHECK(png.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
  CHECK(png.substr(12, 4) == "IHDR");
  CHECK(be32(png, 16) == 40u);
  CHECK(be32(png, 20) == 30u);
  CHECK(png[25] == 2);  // colour type RGB
  CHECK(png.substr(png.size() - 8, 4) == "IEND");

  // Deterministic: the same seed gives the same bytes; view 2 is another camera.
  o.out_path = (dir / "again.png").string();
  REQUIRE(rdsim::render_command(o) == 0);
  CHECK(rdsim::read_file(o.out_path) == png);
  o.view = 2;
  o.out_path = (dir / "view2.png").string();
  REQUIRE(rdsim::render_command(o) == 0);
  CHECK(rdsim::read_file(o.out_path) != png);

  // A goal task's raw-pixel observation (its image; the goals beside it are not drawn into the PNG).
  o.env = "push";
  o.view = 1;
  o.out_path = (dir / "push.png").string();
  REQUIRE(rdsim::render_command(o) == 0);
  const std::string frame = rdsim::read_file(o.out_path);
  CHECK(be32(frame, 16) == 40u);
  CHECK(be32(frame, 20) == 30u);
  o.view = 2;
  o.out_path = (dir / "push2.png").string();
  REQUIRE(rdsim::render_command(o) == 0);
  CHECK(rdsim::read_file(o.out_path) != frame);
  fs::remove_all(dir);
}

TEST_CASE("rdsim render rejects unknown envs and envs without pixels by name", "[render_cli]") {
  rdsim::RenderOptions o;
  o.out_path = (fs::temp_directory_path() / "rdsim_never_written.png").string();
  o.env = "no_such_env";
  CHECK_THROWS_WITH(rdsim::render_command(o), Catch::Contains("no_such_env") && Catch::Contains("jaka_button"));
  o.env = "cartpole";
  CHECK_THROWS_WITH(rdsim::render_command(o), Catch::Contains("cartpole") && Catch::Contains("pixel"));
  CHECK_FALSE(fs::exists(o.out_path));
}

TEST_CASE("rdsim render --config draws a config's robot before any training (first contact, item 4)", "[render_cli]") {
  const fs::path dir = fs::temp_directory_path() / "rdsim_test_render_config";
  fs::remove_all(dir);
  fs::create_directories(dir);
  // configs/reach_jaka.json gives the repo's JAKA as a user's URDF (a path relative to configs/).
  rdsim::RenderOptions o;
  o.config_path = "configs/reach_jaka.json";
  o.out_path = (dir / "mine.png").string();
  REQUIRE(rdsim::render_command(o) == 0);
  const std::string png = rdsim::read_file(o.out_path);
  CHECK(png.substr(1, 3) == "PNG");
  CHECK(be32(png, 16) == 64u);
  // A goal task's config draws its frame.
  const fs::path push = dir / "push.json";
  rdsim::write_file_atomic(push.string(), R"({"algorithm": "sac", "env": {"name": "push", "distance_threshold": 0.02}})");
  o.config_path = push.string();
  o.out_path = (dir / "push.png").string();
  REQUIRE(rdsim::render_command(o) == 0);
  // One of --env and --config.
  o.env = "push";
  CHECK_THROWS_WITH(rdsim::render_command(o), Catch::Contains("give --env NAME or --config FILE"));
  o.env.clear();
  o.config_path.clear();
  CHECK_THROWS_WITH(rdsim::render_command(o), Catch::Contains("give --env NAME or --config FILE"));
  fs::remove_all(dir);
}
