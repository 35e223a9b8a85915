// TFRecord framing and the Event encoding, checked byte for byte against published values; the
// Python test (test_event_accumulator.py) reads whole files with TensorBoard's own reader.
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <string>
#include <unistd.h>

#include "rdsim/core/checksum.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/tensorboard/event_proto.hpp"
#include "rdsim/tensorboard/event_writer.hpp"
#include "rdsim/tensorboard/tfrecord.hpp"

namespace fs = std::filesystem;

namespace {

std::uint64_t le(const std::string& bytes, std::size_t at, int n) {
  std::uint64_t v = 0;
  for (int i = 0; i < n; ++i) v |= static_cast<std::uint64_t>(static_cast<unsigned char>(bytes[at + i])) << (8 * i);
  return v;
}

}  // namespace

TEST_CASE("CRC-32C matches the Castagnoli check values", "[tensorboard][crc]") {
  CHECK(rdsim::crc32c("123456789") == 0xE3069283u);  // the CRC catalogue's check value
  CHECK(rdsim::crc32c("") == 0u);
  CHECK(rdsim::crc32c(std::string(32, '\0')) == 0x8A9136AAu);  // RFC 3720 B.4: 32 bytes of zeros
  CHECK(rdsim::crc32c(std::string(32, '\xff')) == 0x62A8AB43u);  // RFC 3720 B.4: 32 bytes of 0xff
  CHECK(rdsim::crc32c("56789", rdsim::crc32c("1234")) == 0xE3069283u);  // continued over split data
  CHECK(rdsim::crc32("123456789") == 0xCBF43926u);  // the zlib CRC is unchanged beside it
}

TEST_CASE("masked CRC-32C: rotated right by 15, plus 0xa282ead8", "[tensorboard][crc]") {
  const std::uint32_t crc = 0xE3069283u;
  CHECK(rdsim::masked_crc32c("123456789") == ((crc >> 15) | (crc << 17)) + 0xa282ead8u);
  // TFRecord's empty record, as TensorFlow writes it: length 0, its masked CRC, no data, masked CRC of "".
  const std::string empty = rdsim::tfrecord("");
  CHECK(empty == std::string("\0\0\0\0\0\0\0\0\x29\x03\x98\x07\xd8\xea\x82\xa2", 16));
}

TEST_CASE("a TFRecord frames its data with the length, and masked CRCs of both", "[tensorboard][framing]") {
  const std::string data = "hello, tensorboard";
  const std::string r = rdsim::tfrecord(data);
  REQUIRE(r.size() == 8 + 4 + data.size() + 4);
  CHECK(le(r, 0, 8) == data.size());
  CHECK(le(r, 8, 4) == rdsim::masked_crc32c(r.substr(0, 8)));
  CHECK(r.substr(12, data.size()) == data);
  CHECK(le(r, 12 + data.size(), 4) == rdsim::masked_crc32c(data));
}

TEST_CASE("Event protos: wall time, step, file version and scalar summaries, field by field", "[tensorboard][proto]") {
  // wall_time = 1.0 (field 1, fixed64), step 0 (field 2, varint), file_version (field 3, bytes).
  const std::string version = rdsim::encode_file_version_event(1.0);
  CHECK(version == std::string("\x09\x00\x00\x00\x00\x00\x00\xf0\x3f\x10\x00\x1a\x0d", 13) + "brain.Event:2");

  // step 300 = varint ac 02; summary (field 5) { value (1) { tag (1) "x", simple_value (2) 0.5f } }.
  const std::string scalar = rdsim::encode_scalars_event(1.0, 300, {{"x", 0.5}});
  const std::string head("\x09\x00\x00\x00\x00\x00\x00\xf0\x3f\x10\xac\x02", 12);
  const std::string value = std::string("\x0a\x01x\x15\x00\x00\x00\x3f", 8);
  CHECK(scalar == head + "\x2a\x0a" + "\x0a\x08" + value);

  // A negative step is 10 bytes of two's complement, as protobuf encodes int64.
  const std::string negative = rdsim::encode_scalars_event(0.0, -1, {});
  CHECK(negative == std::string("\x09\0\0\0\0\0\0\0\0\x10", 10) + std::string(9, '\xff') + "\x01" + std::string("\x2a\x00", 2));

  // session_log (field 7) { status (1) START (1) }.
  CHECK(rdsim::encode_session_start_event(1.0, 300) == head + "\x3a\x02\x08\x01");
}

TEST_CASE("scalars of a progress.csv row: one per numeric cell, empty (NaN) cells left out", "[tensorboard]") {
  const auto s = rdsim::scalars_of_row({"timesteps", "mean_return", "loss", "label"}, {"2048", "", "-0.25", "x"});
  REQUIRE(s.size() == 2);
  CHECK(s[0] == rdsim::Scalar{"timesteps", 2048.0});
  CHECK(s[1] == rdsim::Scalar{"loss", -0.25});
}

TEST_CASE("the event writer creates its folder and a new file each time, named for TensorBoard", "[tensorboard][writer]") {
  const fs::path dir = fs::temp_directory_path() / ("rdsim_test_tensorboard_" + std::to_string(::getpid())) / "run";
  fs::remove_all(dir.parent_path());
  std::string first_path, second_path;
  {
    rdsim::EventWriter first(dir.string(), 1700000000.0);
    rdsim::EventWriter second(dir.string(), 1700000000.0);  // the same second: still its own file
    first_path = first.path();
    second_path = second.path();
    first.scalar("loss", 64, 0.5, 1700000001.0);
    first.flush();
  }
  CHECK(first_path != second_path);
  CHECK(fs::path(first_path).filename().string().rfind("events.out.tfevents.1700000000.", 0) == 0);
  const std::string bytes = rdsim::read_file(first_path);
  const std::string version = rdsim::tfrecord(rdsim::encode_file_version_event(1700000000.0));
  CHECK(bytes == version + rdsim::tfrecord(rdsim::encode_scalars_event(1700000001.0, 64, {{"loss", 0.5}})));
  CHECK(rdsim::read_file(second_path) == version);
  CHECK(rdsim::is_event_file_name(fs::path(first_path).filename().string()));
  CHECK_FALSE(rdsim::is_event_file_name("progress.csv"));
  CHECK_FALSE(rdsim::is_event_file_name("old.events.out.tfevents.1"));
  fs::remove_all(dir.parent_path());
}
