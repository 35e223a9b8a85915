// `rdsim teleop` as a person uses it: the real window under Xvfb, driven by key presses (xdotool),
// records a demonstration that loads and trains; a screenshot of the screen is not blank.
#include <catch2/catch.hpp>

#include <filesystem>
#include <cstdio>
#include <fstream>
#include <set>

#include "../remote/remote_test_util.hpp"
#include "rdsim/demos/demo_file.hpp"
#include "rdsim/envs/reaching/reach_options.hpp"
#include "rdsim/envs/registry.hpp"
#include "rdsim/remote/remote_env.hpp"
#include "rdsim/teleop/scene_mirror.hpp"
#include "rdsim/teleop/teleop_session.hpp"
#include "rdsim/teleop/teleop_window.hpp"
#include "rl_test_util.hpp"

using Catch::Matchers::Contains;
using rltest::run_rdsim;
using rltest::ScratchDir;

namespace {

bool have(const char* program) { return std::system((std::string("command -v ") + program + " >/dev/null 2>&1").c_str()) == 0; }

struct Ppm {
  int width = 0, height = 0;
  std::vector<unsigned char> rgb;
};

// A binary PPM (P6, maxval 255), as ImageMagick's `import` writes it.
Ppm read_ppm(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::string magic;
  int maxval = 0;
  Ppm p;
  in >> magic >> p.width >> p.height >> maxval;
  in.get();
  REQUIRE(magic == "P6");
  REQUIRE(maxval == 255);
  p.rgb.resize(static_cast<size_t>(p.width) * static_cast<size_t>(p.height) * 3);
  in.read(reinterpret_cast<char*>(p.rgb.data()), static_cast<std::streamsize>(p.rgb.size()));
  REQUIRE(in.gcount() == static_cast<std::streamsize>(p.rgb.size()));
  return p;
}

// Runs `person` (a shell script: $1 is the rdsim binary) on a fresh Xvfb screen; its exit status.
int under_xvfb(const ScratchDir& dir, const std::string& person) {
  const std::string script = dir / "person.sh";
  rltest::spit(script, "set -e\n" + person);
  const std::string cmd = std::string(rltest::no_leak_check_env) + "xvfb-run -a -s '-screen 0 1280x800x24' sh '" + script + "' " +
                          RDSIM_BINARY + " > '" + (dir / "xvfb.out") + "' 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// The window of `teleop_args` opened, focused, given `keys` (xdotool key names, 150 ms apart),
// then closed with Esc; its output goes to dir/teleop.out.
std::string person(const ScratchDir& dir, const std::string& teleop_args, const std::string& keys,
                   const std::string& grab_screen = "") {
  return "\"$1\" teleop " + teleop_args + " > '" + (dir / "teleop.out") + "' 2>&1 &\n"
         "pid=$!\n"
         "wid=$(timeout 60 xdotool search --sync --onlyvisible --name 'rdsim teleop')\n"
         "xdotool windowfocus --sync $wid\n"
         "sleep 1\n"
         "xdotool key --delay 150 " + keys + "\n"
         "sleep 2\n" +
         (grab_screen.empty() ? "" : "import -window root -depth 8 '" + grab_screen + "'\n") +
         "xdotool key Escape\n"
         "wait $pid\n";
}

bool window_tools() {
  if (!rdsim::teleop_window_available()) {
    WARN("this build has no teleop window (GLFW / Dear ImGui missing): nothing to test");
    return false;
  }
  for (const char* tool : {"xvfb-run", "Xvfb", "xdotool", "import"})
    if (!have(tool)) FAIL(std::string(tool) + " is missing (tools/apt-packages.txt: xvfb, xdotool, imagemagick)");
  return true;
}

}  // namespace

TEST_CASE("rdsim teleop under Xvfb: key presses record a demonstration that loads and trains", "[teleop][window]") {
  if (!window_tools()) return;
  ScratchDir dir("teleop_window");
  const std::string demos = dir / "human.demo", shot = dir / "window.png", screen = dir / "screen.ppm";
  // A person starts recording (R), presses E (down) ten times and W (forward) twice, stops (R) and
  // takes the window's own screenshot (P); the screen is also grabbed from outside.
  const int status = under_xvfb(dir, person(dir,
                                            "--env jaka_button --fixed-target --seed 7 --record '" + demos +
                                                "' --screenshot '" + shot + "' --width 1280 --height 800",
                                            "r e e e e e e e e e e w w r p", screen));
  INFO("teleop output:\n" << rltest::slurp(dir / "teleop.out") << "\nxvfb-run output:\n" << rltest::slurp(dir / "xvfb.out"));
  REQUIRE(status == 0);
  CHECK_THAT(rltest::slurp(dir / "teleop.out"), Contains("saved episode 1: 12 steps"));

  // The demonstration: one human episode of exactly the keys pressed, in the env's actions.
  const rdsim::DemoFile f = rdsim::read_demo_file(demos);
  REQUIRE(f.episodes.size() == 1);
  const rdsim::DemoEpisode& e = f.episodes[0];
  CHECK(e.source == rdsim::DemoSource::Human);
  REQUIRE(e.steps() == 12);
  for (int t = 0; t < 10; ++t) CHECK(e.actions[static_cast<size_t>(t)].index == 4);  // -z
  CHECK(e.actions[10].index == 1);                                                     // +x
  CHECK(e.observations.back().values[2] > e.observations.front().values[2]);  // target - flange: the flange went down
  auto r = run_rdsim("demos info " + demos, dir);
  CHECK_THAT(r.out, Contains("episodes     1 (0 scripted, 1 human)"));

  // It trains: behaviour cloning on it writes a model that replays.
  rltest::spit(dir / "bc.json", R"({"algorithm": "bc", "env": {"name": "jaka_button"}, "total_timesteps": 64,
    "bc": {"n_steps": 64}, "demonstrations": {"file": ")" + demos + R"(", "bc_epochs": 20, "validation_fraction": 0}})");
  r = run_rdsim("train --quiet --config " + (dir / "bc.json") + " --log-dir " + (dir / "run"), dir);
  REQUIRE(r.exit_code == 0);
  CHECK(run_rdsim("replay " + (dir / "run/model.bin") + " -n 1", dir).exit_code == 0);

  // What was on the screen is the window, not a blank: many colours, and most pixels not the background.
  const Ppm p = read_ppm(screen);
  CHECK(p.width == 1280);
  CHECK(p.height == 800);
  std::set<int> colours;
  long long dark = 0;
  for (size_t i = 0; i < p.rgb.size(); i += 3) {
    colours.insert(p.rgb[i] << 16 | p.rgb[i + 1] << 8 | p.rgb[i + 2]);
    dark += p.rgb[i] < 8 && p.rgb[i + 1] < 8 && p.rgb[i + 2] < 8;
  }
  CHECK(colours.size() > 200);
  CHECK(dark < static_cast<long long>(p.rgb.size() / 3 / 2));
  // And the window's own screenshot (P) was written.
  CHECK(rltest::slurp(shot).substr(1, 3) == "PNG");
}

TEST_CASE("rdsim teleop --record leaves no empty file when nothing was recorded (first contact, item 10)", "[teleop][window]") {
  if (!window_tools()) return;
  ScratchDir dir("teleop_nothing_recorded");
  const std::string demos = dir / "nothing.demo";
  // The window opens, a few moves are made without recording, and it is closed.
  const int status = under_xvfb(dir, person(dir, "--env jaka_button --seed 7 --record '" + demos + "'", "e e w"));
  INFO("teleop output:\n" << rltest::slurp(dir / "teleop.out") << "\nxvfb-run output:\n" << rltest::slurp(dir / "xvfb.out"));
  REQUIRE(status == 0);
  CHECK_THAT(rltest::slurp(dir / "teleop.out"), Contains("nothing was recorded; " + demos + " not kept"));
  CHECK_FALSE(std::filesystem::exists(demos));
}

TEST_CASE("rdsim teleop --connect: the window drives an rdsim serve env (CurveZMQ) and records it", "[teleop][window][remote]") {
  if (!window_tools()) return;
  ScratchDir dir("teleop_remote_window");
  rdsim::test::Scratch keydir("teleop_remote_keys");
  rdsim::test::TestKeys keys(keydir);
  rdsim::test::ServerThread server(rdsim::test::curve_options(keys));
  const std::string demos = dir / "remote.demo";
  const int status = under_xvfb(dir, person(dir,
                                            "--env jaka_obstacle --seed 3 --record '" + demos + "' --connect " +
                                                server.endpoint() + " --server-key '" + keys.server_public +
                                                "' --client-key '" + keys.client_secret + "'",
                                            "r d d s r"));
  INFO("teleop output:\n" << rltest::slurp(dir / "teleop.out") << "\nxvfb-run output:\n" << rltest::slurp(dir / "xvfb.out"));
  REQUIRE(status == 0);
  CHECK_THAT(rltest::slurp(dir / "teleop.out"), Contains("jaka_obstacle on " + server.endpoint()));
  CHECK_THAT(server.log(), Contains("opened: jaka_obstacle"));
  const rdsim::DemoFile f = rdsim::read_demo_file(demos);
  REQUIRE(f.episodes.size() == 1);
  CHECK(f.episodes[0].steps() == 3);
  CHECK(f.episodes[0].actions[0].index == 2);  // D: -y
  CHECK(f.episodes[0].actions[2].index == 0);  // S: -x
}

TEST_CASE("a teleop session over rdsim serve records what the same env in this process replays exactly", "[teleop][remote]") {
  ScratchDir dir("teleop_remote_session");
  rdsim::test::ServerThread server(rdsim::test::plain_options());
  rdsim::EnvConfig config = rdsim::default_env_config("jaka_obstacle");
  config.get<rdsim::ReachOptions>().random_target = true;
  rdsim::RemoteEnvConfig link;
  link.remote = server.endpoint();
  std::unique_ptr<rdsim::RemoteEnv> env = rdsim::connect_remote_env(link, config);
  const nlohmann::json env_json = rdsim::to_json(env->resolved_config());
  rdsim::DemoWriter writer(dir / "r.demo", env_json, env->spec(), true);
  rdsim::TeleopSession session(*env, 11, &writer, env_json);
  rdsim::SceneMirror mirror(env->resolved_config());
  CHECK(session.move_effector(Eigen::Vector3f(0.25f, 0.2f, 0.2f)));  // the sliders' RobotControl step
  mirror.update(session.control().robot_state());
  session.start_recording();
  for (rdsim::Move m : {rdsim::Move::MinusY, rdsim::Move::MinusY, rdsim::Move::PlusX, rdsim::Move::MinusZ})
    session.act(rdsim::move_action(m, env->spec().action));
  session.stop_recording();
  rdsim::Image eye;
  session.control().camera_image(0, 64, 48, eye);  // the wrist camera, over the link
  CHECK(eye.width == 64);

  const rdsim::DemoFile f = rdsim::read_demo_file(dir / "r.demo");
  REQUIRE(f.episodes.size() == 1);
  const rdsim::DemoEpisode& e = f.episodes[0];
  auto local = rdsim::make_env(config);
  CHECK(local->reset(*e.seed).values == e.observations[0].values);
  for (int t = 0; t < e.steps(); ++t)
    CHECK(local->step(e.actions[static_cast<size_t>(t)]).observation.values == e.observations[static_cast<size_t>(t) + 1].values);
}
