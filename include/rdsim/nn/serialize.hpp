#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <iosfwd>
#include <string>

#include "rdsim/nn/param.hpp"

// Parameter values in a small binary format the model/checkpoint writer embeds:
//   "RDNP" | u32 version | u32 count | per tensor: u32 rows, u32 cols, rows*cols float32
// (little-endian, column-major). Gradients are not stored.
namespace rdsim::nn {

void save_params(const ParamList& params, std::ostream& out);
// Overwrites the values of `params`. rdsim::Error naming `source` (the file) and the offending
// tensor when the magic, count or any shape differs, or the stream ends early. On error the
// values are left untouched.
void load_params(const ParamList& params, std::istream& in, const std::string& source);

// The same through a byte string.
std::string params_to_bytes(const ParamList& params);
void params_from_bytes(const ParamList& params, const std::string& bytes, const std::string& source);

// One tensor: u32 rows, u32 cols, rows*cols float32 (core/binary_io.hpp for the scalars).
void write_matrix(std::ostream& out, const Eigen::MatrixXf& m);
// Reads a matrix and checks it has rows x cols (before allocating) and only finite values;
// `what` names it in the error.
void read_matrix(std::istream& in, Eigen::MatrixXf& m, int rows, int cols, const std::string& source,
                 const std::string& what);

}  // namespace rdsim::nn
