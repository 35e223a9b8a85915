#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

// TensorBoard's `Event` protocol buffer (tensorflow/core/util/event.proto), encoded by hand.
// rdsim writes only a tiny fixed subset of it (wall time, step, the file version, scalar summaries
// and a session start): a dozen lines of varint and fixed-width encoding, where a protobuf
// dependency would add a code generator, a runtime library and a schema to keep in step to the
// build. The fields and their numbers:
//   Event        { double wall_time = 1; int64 step = 2; string file_version = 3;
//                  Summary summary = 5; SessionLog session_log = 7; }
//   Summary      { repeated Value value = 1; }   Value { string tag = 1; float simple_value = 2; }
//   SessionLog   { SessionStatus status = 1; }   (START = 1)
namespace rdsim {

// A named scalar: TensorBoard's tag (a chart) and its value at one step.
using Scalar = std::pair<std::string, double>;

// The first event of every file: file_version "brain.Event:2" (TensorBoard reads the rest by it).
std::string encode_file_version_event(double wall_time);

// One event holding every scalar at `step` (one chart point per tag). Values are stored as float,
// TensorBoard's simple_value.
std::string encode_scalars_event(double wall_time, long long step, const std::vector<Scalar>& scalars);

// A session start at `step`: TensorBoard then drops the points at `step` or later that earlier
// files hold (a resumed run that rewinds to its checkpoint replaces what came after it).
std::string encode_session_start_event(double wall_time, long long step);

}  // namespace rdsim
