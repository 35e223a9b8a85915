#include <catch2/catch.hpp>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "rdsim/core/checksum.hpp"
#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/render/png.hpp"

using Catch::Matchers::Contains;
namespace fs = std::filesystem;

namespace {

std::uint32_t be32(const std::string& s, size_t at) {
  auto b = [&](size_t i) { return static_cast<std::uint32_t>(static_cast<unsigned char>(s[at + i])); };
  return b(0) << 24 | b(1) << 16 | b(2) << 8 | b(3);
}

struct Chunk {
  std::string type, data;
};

// Splits a PNG into chunks, checking each chunk's CRC on the way.
std::vector<Chunk> read_chunks(const std::string& png) {
  REQUIRE(png.substr(0, 8) == std::string("\x89PNG\r\n\x1a\n", 8));
  std::vector<Chunk> chunks;
  size_t at = 8;
  while (at < png.size()) {
    REQUIRE(at + 12 <= png.size());
    const std::uint32_t len = be32(png, at);
    REQUIRE(at + 12 + len <= png.size());
    Chunk c{png.substr(at + 4, 4), png.substr(at + 8, len)};
    CHECK(be32(png, at + 8 + len) == rdsim::crc32(png.substr(at + 4, 4 + len)));
    chunks.push_back(c);
    at += 12 + len;
  }
  return chunks;
}

// Inflates a zlib stream made only of stored deflate blocks, checking LEN/NLEN and Adler-32.
std::string inflate_stored(const std::string& z, int* blocks) {
  REQUIRE(z.size() >= 6);
  const unsigned cmf = static_cast<unsigned char>(z[0]), flg = static_cast<unsigned char>(z[1]);
  CHECK((cmf & 0x0F) == 8);            // deflate
  CHECK((cmf << 8 | flg) % 31 == 0);   // header check bits
  CHECK((flg & 0x20) == 0);            // no preset dictionary
  std::string out;
  size_t at = 2;
  bool last = false;
  *blocks = 0;
  while (!last) {
    REQUIRE(at + 5 <= z.size());
    const unsigned header = static_cast<unsigned char>(z[at]);
    last = header & 1;
    REQUIRE(((header >> 1) & 3) == 0);  // stored
    const unsigned len = static_cast<unsigned char>(z[at + 1]) | static_cast<unsigned char>(z[at + 2]) << 8;
    const unsigned nlen = static_cast<unsigned char>(z[at + 3]) | static_cast<unsigned char>(z[at + 4]) << 8;
    REQUIRE((len ^ 0xFFFFu) == nlen);
    REQUIRE(at + 5 + len <= z.size());
    out.append(z, at + 5, len);
    at += 5 + len;
    ++*blocks;
  }
  REQUIRE(at + 4 == z.size());
  CHECK(be32(z, at) == rdsim::adler32(out));
  return out;
}

std::vector<std::uint8_t> gradient(int w, int h, int channels) {
  std::vector<std::uint8_t> px(static_cast<size_t>(w * h * channels));
  for (size_t i = 0; i < px.size(); ++i) px[i] = static_cast<std::uint8_t>((i * 7 + i / 13) & 0xFF);
  return px;
}

}  // namespace

TEST_CASE("crc32 and adler32 match the published check values", "[render][png]") {
  CHECK(rdsim::crc32("123456789") == 0xCBF43926u);
  CHECK(rdsim::crc32("") == 0u);
  CHECK(rdsim::crc32("IEND") == 0xAE426082u);  // every PNG ends with these bytes
  CHECK(rdsim::adler32("Wikipedia") == 0x11E60398u);
  CHECK(rdsim::adler32("") == 1u);
  // Continuing over split input equals one pass, also across adler's 5552-byte blocks.
  std::string big(20000, '\0');
  for (size_t i = 0; i < big.size(); ++i) big[i] = static_cast<char>(255 - i % 251);
  const std::string_view v(big);
  CHECK(rdsim::crc32(v.substr(7000), rdsim::crc32(v.substr(0, 7000))) == rdsim::crc32(v));
  CHECK(rdsim::adler32(v.substr(7000), rdsim::adler32(v.substr(0, 7000))) == rdsim::adler32(v));
  // All-0xFF input drives the sums to their largest: the modulo must still be applied in time.
  const std::string ff(100000, '\xFF');
  std::uint64_t a = 1, b = 0;
  for (unsigned char c : ff) {
    a = (a + c) % 65521;
    b = (b + a) % 65521;
  }
  CHECK(rdsim::adler32(ff) == static_cast<std::uint32_t>(b << 16 | a));
}

TEST_CASE("encode_png writes a valid PNG whose stored blocks decode to the pixels",
          "[render][png]") {
  for (int channels : {1, 3, 4}) {
    const int w = 200, h = 150;  // more than 65535 bytes for 3 and 4 channels: several blocks
    const auto px = gradient(w, h, channels);
    const auto chunks = read_chunks(rdsim::encode_png(w, h, channels, px.data()));
    REQUIRE(chunks.size() == 3);
    CHECK(chunks[0].type == "IHDR");
    CHECK(chunks[1].type == "IDAT");
    CHECK(chunks[2].type == "IEND");
    CHECK(chunks[2].data.empty());
    const std::string& ihdr = chunks[0].data;
    REQUIRE(ihdr.size() == 13);
    CHECK(be32(ihdr, 0) == static_cast<std::uint32_t>(w));
    CHECK(be32(ihdr, 4) == static_cast<std::uint32_t>(h));
    CHECK(ihdr[8] == 8);  // bit depth
    CHECK(ihdr[9] == (channels == 1 ? 0 : channels == 3 ? 2 : 6));
    CHECK(ihdr.substr(10) == std::string(3, '\0'));

    int blocks = 0;
    const std::string raw = inflate_stored(chunks[1].data, &blocks);
    const size_t row = static_cast<size_t>(w * channels);
    CHECK(blocks == static_cast<int>((raw.size() + 65534) / 65535));
    REQUIRE(raw.size() == (row + 1) * static_cast<size_t>(h));
    for (int y = 0; y < h; ++y) {
      REQUIRE(raw[static_cast<size_t>(y) * (row + 1)] == '\0');  // filter None
      REQUIRE(std::equal(px.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(y)),
                         px.begin() + static_cast<std::ptrdiff_t>(row * static_cast<size_t>(y + 1)),
                         reinterpret_cast<const std::uint8_t*>(raw.data()) + static_cast<size_t>(y) * (row + 1) + 1));
    }
  }
}

TEST_CASE("write_png writes the file atomically and rejects bad images", "[render][png]") {
  const fs::path dir = fs::temp_directory_path() / "rdsim_test_png";
  fs::create_directories(dir);
  const std::string path = (dir / "img.png").string();
  const auto px = gradient(5, 3, 3);
  rdsim::write_png(path, 5, 3, 3, px.data());
  CHECK(rdsim::read_file(path) == rdsim::encode_png(5, 3, 3, px.data()));
  CHECK_FALSE(fs::exists(path + ".tmp"));
  CHECK_THROWS_WITH(rdsim::write_png(path, 5, 3, 2, px.data()),
                    Contains(path) && Contains("channels"));
  CHECK_THROWS_AS(rdsim::encode_png(0, 3, 3, px.data()), rdsim::Error);
  // A file where the folder would go (missing folders are made): the error names the file.
  CHECK_THROWS_WITH(rdsim::write_png((dir / "img.png" / "x.png").string(), 5, 3, 3, px.data()),
                    Contains("x.png"));
  fs::remove_all(dir);
}
