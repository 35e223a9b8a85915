#include <catch2/catch.hpp>

#include "rdsim/training/model_file.hpp"
#include "rdsim/core/error.hpp"

using Catch::Matchers::Contains;

namespace {

std::string decode_error(const std::string& bytes) {
  try {
    rdsim::decode_model_file(bytes, "m.bin");
  } catch (const rdsim::Error& e) {
    return e.what();
  }
  return "";
}

rdsim::ModelFile sample() {
  rdsim::ModelFile f;
  f.kind = rdsim::ModelKind::Checkpoint;
  f.config = {{"algorithm", "ppo"}, {"seed", 3}};
  f.payload = std::string("\x00\x01weights\xff", 10);
  f.policy = "policy";
  return f;
}

}  // namespace

TEST_CASE("model files round-trip", "[model_file]") {
  const auto bytes = rdsim::encode_model_file(sample());
  CHECK(bytes.substr(0, 8) == "RDSIMMDL");
  const auto back = rdsim::decode_model_file(bytes, "m.bin");
  CHECK(back.kind == rdsim::ModelKind::Checkpoint);
  CHECK(back.config == sample().config);
  CHECK(back.payload == sample().payload);
  CHECK(back.policy == "policy");
}

TEST_CASE("damaged, truncated and foreign model files are rejected clearly", "[model_file]") {
  const auto bytes = rdsim::encode_model_file(sample());
  // Any single flipped byte is caught, wherever it is.
  for (std::size_t i = 0; i < bytes.size(); ++i) {
    std::string damaged = bytes;
    damaged[i] = static_cast<char>(damaged[i] ^ 0x20);
    const std::string msg = decode_error(damaged);
    INFO("byte " << i << ": " << msg);
    CHECK_THAT(msg, Contains("m.bin: "));
  }
  std::string flipped = bytes;
  flipped[bytes.size() - 8 - 6 - 8 - 3] ^= 1;  // inside the payload (before the policy, its length and the checksum)
  CHECK_THAT(decode_error(flipped), Contains("checksum mismatch"));
  for (std::size_t n = 8; n < bytes.size(); ++n) {
    const std::string msg = decode_error(bytes.substr(0, n));
    INFO("cut at " << n << ": " << msg);
    CHECK_THAT(msg, Contains("m.bin: "));
  }
  CHECK_THAT(decode_error(bytes.substr(0, bytes.size() - 3)), Contains("truncated"));
  CHECK_THAT(decode_error("{\"algorithm\": \"ppo\"}"), Contains("not an rdsim model file"));
  CHECK_THAT(decode_error(""), Contains("not an rdsim model file"));
  CHECK_THAT(decode_error(bytes + "x"), Contains("damaged"));
}
