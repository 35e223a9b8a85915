// `rdsim bench-learner`: the rows asked for, each with a description of its networks in the JSON.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>

#include "bench_json.hpp"
#include "rdsim/bench/bench_learner.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/nn/gemm.hpp"

using namespace rdsim;

namespace {

nlohmann::json run_bench(BenchLearnerOptions o) {
  o.runs = 1;
  o.min_seconds = 0.0;  // the minimum of 3 updates per run
  const nn::GemmBackend backend = nn::gemm_backend();  // the command sets --gemm process-wide
  nlohmann::json j = test::bench_json(o, bench_learner_command, "bench_learner");
  nn::set_gemm_backend(backend);
  nn::set_gemm_threads(1);
  return j;
}

}  // namespace

TEST_CASE("bench-learner: rows by name or prefix, each timed and described layer by layer", "[bench]") {
  BenchLearnerOptions o;
  o.rows = {"ppo_mlp_64", "sac"};
  o.gemm = "eigen";
  const nlohmann::json j = run_bench(o);
  CHECK(j.at("gemm") == "eigen");
  CHECK(j.at("threads") == 1);
  const nlohmann::json& rows = j.at("rows");
  REQUIRE(rows.size() == 2);
  CHECK(rows[0].at("name") == "ppo_mlp_64");
  const nlohmann::json& ppo = rows[0].at("network");
  CHECK(ppo.at("kind") == "ppo_mlp");
  CHECK(ppo.at("batch") == 512);
  CHECK(ppo.at("actions") == 6);  // jaka_button's Discrete(6)
  CHECK(ppo.at("actor").at("hidden") == nlohmann::json({64, 64}));
  CHECK(ppo.at("actor").at("outputs") == 6);
  CHECK(ppo.at("critic").at("outputs") == 1);
  CHECK(ppo.at("actor").at("activation") == "tanh");
  CHECK(rows[1].at("name") == "sac_critics");
  const nlohmann::json& sac = rows[1].at("network");
  CHECK(sac.at("critic").at("inputs") == ppo.at("actor").at("inputs").get<int>() + 3);  // observation + Box(3) action
  CHECK(sac.at("critic").at("activation") == "relu");
  for (const auto& row : rows) {
    CHECK(row.at("ms_per_update").get<double>() > 0.0);
    CHECK(row.at("cpu_ms_per_update").get<double>() > 0.0);
    CHECK(row.at("updates").get<long long>() >= 3);
  }
}

TEST_CASE("bench-learner: a CNN row describes its convolutions", "[bench]") {
  BenchLearnerOptions o;
  o.rows = {"ppo_cnn_small_64"};
  const nlohmann::json j = run_bench(o);
  REQUIRE(j.at("rows").size() == 1);
  const nlohmann::json& d = j.at("rows")[0].at("network");
  CHECK(d.at("image") == nlohmann::json({64, 64, 3}));
  CHECK(d.at("convs") == nlohmann::json({{16, 8, 4}, {32, 4, 2}}));
  CHECK(d.at("fc") == nlohmann::json({256}));
  CHECK(d.at("batch") == 256);
}

TEST_CASE("bench-learner: unknown rows and threads without oneDNN are refused", "[bench]") {
  BenchLearnerOptions o;
  o.rows = {"ppo_rnn"};
  CHECK_THROWS_WITH(bench_learner_command(o), Catch::Contains("no row named \"ppo_rnn\""));
  o.rows = {"ppo_mlp_64"};
  o.gemm = "eigen";
  o.threads = 2;
  CHECK_THROWS_WITH(bench_learner_command(o), Catch::Contains("only the onednn GEMM runs on several threads"));
  nn::set_gemm_backend(nn::onednn_available() ? nn::GemmBackend::OneDnn : nn::GemmBackend::Eigen);
}
