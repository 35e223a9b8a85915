#include "rdsim/remote/curve_keys.hpp"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zmq.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>

#include "rdsim/core/error.hpp"
#include "rdsim/core/files.hpp"
#include "rdsim/core/input_file.hpp"

namespace rdsim::remote {
namespace {

constexpr std::size_t kZ85KeyLength = 40;

// Creates `path` with `mode` (never a wider mode first) and writes `text`; fails if it exists.
void create_file(const std::string& path, const std::string& text, mode_t mode) {
  const int fd = ::open(path.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, mode);
  if (fd < 0) {
    if (errno == EEXIST) throw Error(path + ": already exists (rdsim keygen never overwrites a key; remove it first)");
    throw Error(path + ": cannot create: " + std::strerror(errno));
  }
  ::fchmod(fd, mode);  // whatever the umask
  const bool ok = ::write(fd, text.data(), text.size()) == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
  ::close(fd);
  if (!ok) throw Error(path + ": cannot write");
}

// The value after `label ` on a line of `text`; "" when absent. Lines starting with # are comments.
std::string field(const std::string& text, const std::string& label) {
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) {
    if (line.empty() || line[0] == '#') continue;
    if (line.rfind(label + " ", 0) == 0) {
      std::string value = line.substr(label.size() + 1);
      while (!value.empty() && (value.back() == '\r' || value.back() == ' ')) value.pop_back();
      return value;
    }
  }
  return "";
}

// The keygen command that writes the key file `path` (DIR/NAME.key or DIR/NAME.key_secret).
std::string keygen_command_for(const std::string& path) {
  const std::filesystem::path p(path);
  const std::string dir = p.has_parent_path() ? p.parent_path().string() : ".";
  return "rdsim keygen " + p.stem().string() + " --dir " + dir;
}

std::string mode_text(mode_t mode) {
  char m[8];
  std::snprintf(m, sizeof m, "%04o", static_cast<unsigned>(mode & 07777));
  return m;
}

// A key file's text, read only when neither the file nor its folder may be written by any user
// (anyone could otherwise add a client key or swap the server's), within max_key_file_bytes and
// only from a regular file (core/input_file.hpp). `private_key`: group and others may not even
// read it, as ssh requires.
std::string read_key_file(const std::string& path, bool private_key) {
  const std::filesystem::path p(path);
  const std::string folder = p.has_parent_path() ? p.parent_path().string() : ".";
  struct stat dir {};
  if (::stat(folder.c_str(), &dir) == 0 && (dir.st_mode & S_IWOTH))
    throw Error(folder + ": any user may write to this key folder (mode " + mode_text(dir.st_mode) +
                "), so anyone could add or replace a key; make it yours alone: chmod o-w " + folder);
  require_file_or_hint(path, keygen_command_for(path));
  InputFile file(path, max_key_file_bytes);
  struct stat st {};
  if (::fstat(file.fd(), &st) != 0) throw Error(path + ": cannot read: " + std::strerror(errno));
  if (private_key && (st.st_mode & (S_IRWXG | S_IRWXO)))
    throw Error(path + ": other users may read this secret key (mode " + mode_text(st.st_mode) + "); make it private: chmod 600 " + path);
  if (st.st_mode & S_IWOTH)
    throw Error(path + ": any user may write to this key file (mode " + mode_text(st.st_mode) +
                "), so anyone could replace the key; make it yours alone: chmod o-w " + path);
  return file.read_rest();
}

}  // namespace

bool is_curve_key(const std::string& text) {
  if (text.size() != kZ85KeyLength) return false;
  std::uint8_t bytes[32];
  return zmq_z85_decode(bytes, text.c_str()) != nullptr;
}

CurveKeyPair generate_curve_keys() {
  if (!zmq_has("curve")) throw Error("this libzmq was built without CurveZMQ (libsodium): no keys can be made");
  char pub[kZ85KeyLength + 1], sec[kZ85KeyLength + 1];
  if (zmq_curve_keypair(pub, sec) != 0) throw Error(std::string("cannot make a key pair: ") + zmq_strerror(zmq_errno()));
  return {pub, sec};
}

std::vector<std::string> write_key_files(const std::string& dir, const std::string& name, const CurveKeyPair& keys) {
  if (name.empty() || name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") !=
                          std::string::npos || name[0] == '.')
    throw Error("keygen: NAME must be letters, digits, '_', '-' or '.' (not first), got \"" + name + "\"");
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw Error(dir + ": cannot create the folder: " + ec.message());
  const std::string pub = (std::filesystem::path(dir) / (name + ".key")).string();
  const std::string sec = pub + "_secret";
  if (std::filesystem::exists(pub)) throw Error(pub + ": already exists (rdsim keygen never overwrites a key; remove it first)");
  create_file(sec, "# rdsim CurveZMQ secret key of \"" + name + "\": keep it private (mode 0600)\npublic " +
                       keys.public_key + "\nsecret " + keys.secret_key + "\n",
              0600);
  create_file(pub, "# rdsim CurveZMQ public key of \"" + name + "\": give this file to the other side\npublic " +
                       keys.public_key + "\n",
              0644);
  return {pub, sec};
}

std::string read_public_key(const std::string& path) {
  const std::string key = field(read_key_file(path, false), "public");
  if (!is_curve_key(key)) throw Error(path + ": no public key in it (expected a line \"public <40 Z85 characters>\", as rdsim keygen writes)");
  return key;
}

CurveKeyPair read_secret_key(const std::string& path) {
  const std::string text = read_key_file(path, true);
  CurveKeyPair keys{field(text, "public"), field(text, "secret")};
  if (!is_curve_key(keys.secret_key))
    throw Error(path + ": no secret key in it (expected a line \"secret <40 Z85 characters>\", as rdsim keygen writes)");
  char derived[kZ85KeyLength + 1];
  if (zmq_curve_public(derived, keys.secret_key.c_str()) != 0 || keys.public_key != derived)
    throw Error(path + ": its public and secret keys do not belong together");
  return keys;
}

}  // namespace rdsim::remote
