#include "rdsim/nn/serialize.hpp"

#include <cstring>
#include <istream>
#include <ostream>
#include <sstream>

#include "rdsim/core/binary_io.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim::nn {

namespace {

constexpr char kMagic[4] = {'R', 'D', 'N', 'P'};
constexpr std::uint32_t kVersion = 1;

std::string shape_text(Eigen::Index rows, Eigen::Index cols) {
  return std::to_string(rows) + "x" + std::to_string(cols);
}

}  // namespace

void write_matrix(std::ostream& out, const Eigen::MatrixXf& m) {
  write_u32(out, static_cast<std::uint32_t>(m.rows()));
  write_u32(out, static_cast<std::uint32_t>(m.cols()));
  out.write(reinterpret_cast<const char*>(m.data()), static_cast<std::streamsize>(m.size() * 4));
}

void read_matrix(std::istream& in, Eigen::MatrixXf& m, int rows, int cols, const std::string& source,
                 const std::string& what) {
  const std::uint32_t r = read_u32(in, source), c = read_u32(in, source);
  if (r != static_cast<std::uint32_t>(rows) || c != static_cast<std::uint32_t>(cols))
    throw Error(source + ": " + what + " has shape " + shape_text(r, c) + ", expected " +
                shape_text(rows, cols) + " (the model was saved with a different network)");
  if (static_cast<std::uint64_t>(rows) * static_cast<std::uint64_t>(cols) > bytes_left(in) / 4)
    throw Error(source + ": file is truncated (" + what + " does not fit in it)");
  m.resize(rows, cols);
  read_bytes(in, m.data(), static_cast<std::size_t>(m.size()) * 4, source);
  if (!m.allFinite()) throw Error(source + ": " + what + " holds a value that is not finite (NaN or infinity; damaged or diverged model)");
}

void save_params(const ParamList& params, std::ostream& out) {
  out.write(kMagic, 4);
  write_u32(out, kVersion);
  write_u32(out, static_cast<std::uint32_t>(params.size()));
  for (const Param& p : params) write_matrix(out, *p.value);
  if (!out) throw Error("nn::save_params: write failed");
}

void load_params(const ParamList& params, std::istream& in, const std::string& source) {
  char magic[4];
  read_bytes(in, magic, 4, source);
  if (std::memcmp(magic, kMagic, 4) != 0)
    throw Error(source + ": network parameters not found (bad magic bytes)");
  const std::uint32_t version = read_u32(in, source);
  if (version != kVersion)
    throw Error(source + ": network parameter format version " + std::to_string(version) +
                " is not supported (expected " + std::to_string(kVersion) + ")");
  const std::uint32_t count = read_u32(in, source);
  if (count != params.size())
    throw Error(source + ": holds " + std::to_string(count) + " parameter tensors, expected " +
                std::to_string(params.size()) + " (the model was saved with a different network)");
  // Read everything first so a bad file leaves the network as it was.
  std::vector<Eigen::MatrixXf> loaded(params.size());
  for (size_t i = 0; i < params.size(); ++i) {
    const Param& p = params[i];
    const std::string what = "parameter " + std::to_string(i) + (p.name.empty() ? "" : " (" + p.name + ")");
    read_matrix(in, loaded[i], static_cast<int>(p.value->rows()), static_cast<int>(p.value->cols()),
                source, what);
  }
  for (size_t i = 0; i < params.size(); ++i) *params[i].value = std::move(loaded[i]);
}

std::string params_to_bytes(const ParamList& params) {
  std::ostringstream out(std::ios::binary);
  save_params(params, out);
  return std::move(out).str();
}

void params_from_bytes(const ParamList& params, const std::string& bytes, const std::string& source) {
  std::istringstream in(bytes, std::ios::binary);
  load_params(params, in, source);
}

}  // namespace rdsim::nn
