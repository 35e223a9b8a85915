#pragma once
#include <string>
#include <vector>

#include "rdsim/tensorboard/event_proto.hpp"

// A TensorBoard event file written by rdsim itself (TFRecord framing and hand-encoded Event
// protos: tfrecord.hpp, event_proto.hpp), so `tensorboard --logdir runs/` shows rdsim runs beside
// those of other libraries.
namespace rdsim {

class EventWriter {
public:
  // Creates `dir` (and the folders above it) and a new file in it,
  // events.out.tfevents.<unix seconds>.<host>.<pid>.<n>, opened exclusively (never another
  // writer's file) and appended to; its first event is the file version. TensorBoard reads every
  // such file of a folder, in name order, as one run. Throws rdsim::Error naming the file.
  explicit EventWriter(const std::string& dir, double wall_time = now());
  ~EventWriter();
  EventWriter(const EventWriter&) = delete;
  EventWriter& operator=(const EventWriter&) = delete;

  // One point on the chart `tag` at `step`; wall_time in seconds since 1970 (TensorBoard's
  // "relative" and "wall" x axes). Buffered until flush().
  void scalar(const std::string& tag, long long step, double value, double wall_time = now());
  // Several charts' points at one step, in one event.
  void scalars(long long step, const std::vector<Scalar>& values, double wall_time = now());
  // A resumed run restarting at `step`: TensorBoard drops the earlier files' points from `step` on.
  void session_start(long long step, double wall_time = now());
  // Writes what is buffered (whole records: a reader never sees half of one). rdsim::Error on failure.
  void flush();

  const std::string& path() const { return path_; }

  // The system clock in seconds since 1970.
  static double now();

private:
  void add(const std::string& event);

  std::string path_;
  int fd_ = -1;
  std::string pending_;
};

// Whether `name` (a file name, no folder) is an event file EventWriter writes: a run folder's
// `--overwrite` must delete them with the CSVs (else TensorBoard shows the old run's points), and
// a new run must not start in a folder that holds them.
bool is_event_file_name(const std::string& name);

// The scalars of one CSV row (progress.csv): one per column, tag = column name, skipping empty
// cells (CsvWriter writes NaN, "no episode finished yet", as an empty cell) and cells that are
// not numbers.
std::vector<Scalar> scalars_of_row(const std::vector<std::string>& columns, const std::vector<std::string>& cells);

}  // namespace rdsim
