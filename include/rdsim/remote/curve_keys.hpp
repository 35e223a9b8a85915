#pragma once
#include <cstdint>
#include <string>
#include <vector>

// CurveZMQ key pairs (Curve25519, written as 40-character Z85 text) and their files, as
// `rdsim keygen NAME` writes them:
//   NAME.key         the public key: give it to the other side (readable by anyone);
//   NAME.key_secret  the public and the secret key (mode 0600, created so: never readable by
//                    others, not even for a moment). Reading a secret key file that group or
//                    others may read is refused, as ssh does; so is reading any key file that
//                    any user may write, or that lies in a folder any user may write.
// No key is ever compiled in or written into a config: configs name key files.
namespace rdsim::remote {

// Key files are a few lines: a larger one is not read (core/input_file.hpp).
inline constexpr std::uint64_t max_key_file_bytes = 4096;

struct CurveKeyPair {
  std::string public_key;  // Z85, 40 characters
  std::string secret_key;
};

// A fresh pair from libsodium's random source (through libzmq). rdsim::Error when libzmq was
// built without CurveZMQ.
CurveKeyPair generate_curve_keys();

// Writes DIR/NAME.key and DIR/NAME.key_secret (creating DIR). Refuses to overwrite either file.
// Returns the two paths.
std::vector<std::string> write_key_files(const std::string& dir, const std::string& name, const CurveKeyPair& keys);

// The public key in a NAME.key file (or the public half of a NAME.key_secret file).
// rdsim::Error naming the file when it holds no valid key.
std::string read_public_key(const std::string& path);
// Both keys of a NAME.key_secret file; rdsim::Error when it is malformed, when the keys do not
// belong together, or when others may read it.
CurveKeyPair read_secret_key(const std::string& path);

// Whether `text` is a valid Z85 Curve key (40 characters that decode to 32 bytes).
bool is_curve_key(const std::string& text);

}  // namespace rdsim::remote
