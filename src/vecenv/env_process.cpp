#include "rdsim/vecenv/env_process.hpp"

#include <atomic>
#include <chrono>
#include <csignal>
#include <cstring>
#include <ctime>
#include <linux/futex.h>
#include <new>
#include <sys/mman.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <sys/wait.h>
#include <unistd.h>
#if defined(__SSE2__)
#include <emmintrin.h>
#endif

#include "rdsim/core/assert.hpp"
#include "rdsim/core/env_state.hpp"
#include "rdsim/core/error.hpp"

namespace rdsim {
namespace {

enum Command : std::uint32_t { kReset = 1, kStep, kDropCaches, kSave, kLoad, kQuit };

constexpr std::size_t kAlign = 64;  // slots on their own cache lines
constexpr std::uint64_t kNoState = ~0ull;     // in a packed state list: the env has no EnvState
constexpr std::uint64_t kSaveFailed = ~0ull;  // as the length of the save reply: see the error instead
// Back-to-back steps hand over without a system call (as WorkerPool). Longer than the pool's 50 us:
// between two steps of pixel training the parent spends 0.3 ms choosing the actions (a CNN on 8
// images), and a child asleep by then costs a wake-up per step; measured on 2 cores, 60k steps of
// configs/jaka_button_pixels.json, two interleaved pairs: 18.9 / 19.3 s at 1 ms against 19.6 / 20.2
// s at 50 us.
constexpr int kSpinMicros = 1000;

std::size_t aligned(std::size_t n) { return (n + kAlign - 1) / kAlign * kAlign; }

// Copies an observation into shared memory with non-temporal stores where the CPU has them: the
// parent reads every byte of it after each step, and ordinary stores would first fetch each of
// those cache lines back from the parent's core (a 64x64 image is 192 lines). On the 2-core
// development VM the gain was within its noise; the copy itself costs about 1 us per image.
void stream_copy(std::uint8_t* dst, const std::uint8_t* src, std::size_t n) {
#if defined(__SSE2__)
  std::size_t i = 0;
  if (reinterpret_cast<std::uintptr_t>(dst) % 16 == 0) {
    for (; i + 16 <= n; i += 16)
      _mm_stream_si128(reinterpret_cast<__m128i*>(dst + i), _mm_loadu_si128(reinterpret_cast<const __m128i*>(src + i)));
    _mm_sfence();  // the stores are visible before the reply that announces them
  }
  std::memcpy(dst + i, src + i, n - i);
#else
  std::memcpy(dst, src, n);
#endif
}

// The head of an env's slot; its action values, observation and final observation follow.
struct SlotHead {
  std::int32_t action_index = 0;
  std::uint8_t active = 0;
  std::uint64_t seed = 0;
  StepOutcome outcome;
};

long futex(std::atomic<std::uint32_t>* word, int op, std::uint32_t value, const timespec* timeout) {
  return syscall(SYS_futex, reinterpret_cast<std::uint32_t*>(word), op, value, timeout, nullptr, 0);
}

// Waits until `word` differs from `seen`, at most about `timeout_ms` after the spin; true if it does.
bool wait_change(std::atomic<std::uint32_t>& word, std::uint32_t seen, int timeout_ms) {
  using Clock = std::chrono::steady_clock;
  const auto deadline = Clock::now() + std::chrono::microseconds(kSpinMicros);
  for (int i = 1; i % 64 != 0 || Clock::now() < deadline; ++i)
    if (word.load(std::memory_order_acquire) != seen) return true;
  const timespec timeout{timeout_ms / 1000, (timeout_ms % 1000) * 1000000L};
  futex(&word, FUTEX_WAIT, seen, &timeout);  // returns at once when the word changed meanwhile
  return word.load(std::memory_order_acquire) != seen;
}

void publish(std::atomic<std::uint32_t>& word, std::uint32_t value) {
  word.store(value, std::memory_order_release);
  futex(&word, FUTEX_WAKE, 1, nullptr);
}

// Whole-buffer socket I/O; false when the other side is gone.
bool send_all(int fd, const void* data, std::size_t n) {
  const char* p = static_cast<const char*>(data);
  while (n > 0) {
    const ssize_t k = send(fd, p, n, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}
bool recv_all(int fd, void* data, std::size_t n) {
  char* p = static_cast<char*>(data);
  while (n > 0) {
    const ssize_t k = recv(fd, p, n, 0);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}
bool send_blob(int fd, const std::string& blob) {
  const std::uint64_t n = blob.size();
  return send_all(fd, &n, sizeof n) && send_all(fd, blob.data(), blob.size());
}

// Strings packed as (length, bytes)...; has[i] false: no state.
std::string pack(const std::vector<std::optional<std::string>>& states) {
  std::string out;
  for (const auto& s : states) {
    const std::uint64_t n = s ? s->size() : kNoState;
    out.append(reinterpret_cast<const char*>(&n), sizeof n);
    if (s) out += *s;
  }
  return out;
}
std::vector<std::optional<std::string>> unpack(const std::string& blob, int count) {
  std::vector<std::optional<std::string>> out;
  std::size_t at = 0;
  for (int i = 0; i < count; ++i) {
    std::uint64_t n = 0;
    RDSIM_ASSERT(at + sizeof n <= blob.size(), "EnvProcess: short state blob");
    std::memcpy(&n, blob.data() + at, sizeof n);
    at += sizeof n;
    if (n == kNoState) {
      out.emplace_back();
      continue;
    }
    RDSIM_ASSERT(at + n <= blob.size(), "EnvProcess: short state blob");
    out.emplace_back(blob.substr(at, n));
    at += n;
  }
  return out;
}

std::string exit_reason(int status) {
  if (WIFSIGNALED(status)) return std::string("killed by signal ") + std::to_string(WTERMSIG(status)) + " (" +
                                  strsignal(WTERMSIG(status)) + ")";
  return "exited with status " + std::to_string(WEXITSTATUS(status));
}

}  // namespace

struct EnvProcess::Shared {
  alignas(kAlign) std::atomic<std::uint32_t> request{0};  // bumped by the parent per command
  alignas(kAlign) std::atomic<std::uint32_t> reply{0};    // set to request by the child when done
  alignas(kAlign) std::uint32_t command = 0;
  std::uint32_t failed = 0;
  char error[2048] = {};
};

EnvProcess::EnvProcess(std::vector<std::unique_ptr<Env>> envs, const Spec& spec, int first)
    : count_(static_cast<int>(envs.size())), first_(first), spec_(spec) {
  RDSIM_ASSERT(!envs.empty(), "EnvProcess needs envs");
  // An observation in a slot: its Float32 values, then its UInt8 bytes.
  value_bytes_ = 4 * static_cast<std::size_t>(spec.observation.value_count());
  obs_bytes_ = value_bytes_ + static_cast<std::size_t>(spec.observation.byte_count());
  action_floats_ = spec.action.discrete ? 0 : static_cast<std::size_t>(spec.action.dim());
  slot_bytes_ = aligned(sizeof(SlotHead) + 4 * action_floats_) + 2 * aligned(obs_bytes_);
  map_bytes_ = aligned(sizeof(Shared)) + slot_bytes_ * static_cast<std::size_t>(count_);
  void* map = mmap(nullptr, map_bytes_, PROT_READ | PROT_WRITE, MAP_SHARED | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED)
    throw Error(what_envs() + ": cannot map " + std::to_string(map_bytes_) + " bytes of shared memory: " +
                std::strerror(errno));
  shared_ = new (map) Shared;
  for (int i = 0; i < count_; ++i) new (slot(i)) SlotHead;
  int fds[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) {
    munmap(map, map_bytes_);
    throw Error(what_envs() + ": socketpair failed: " + std::strerror(errno));
  }
  const pid_t parent = getpid();
  std::fflush(nullptr);  // nothing buffered twice
  pid_ = fork();
  if (pid_ < 0) {
    close(fds[0]);
    close(fds[1]);
    munmap(map, map_bytes_);
    throw Error(what_envs() + ": fork failed: " + std::strerror(errno));
  }
  if (pid_ == 0) {
    close(fds[0]);
    socket_ = fds[1];
    prctl(PR_SET_PDEATHSIG, SIGKILL);
    if (getppid() != parent) _exit(0);  // the parent died before the line above
    // Ctrl-C reaches the whole process group: the parent handles it (finishing the update and
    // saving a checkpoint needs these envs), so the child must outlive it.
    std::signal(SIGINT, SIG_IGN);
    std::signal(SIGTERM, SIG_IGN);
    child_main(envs);
  }
  close(fds[1]);
  socket_ = fds[0];
  envs.clear();  // the child's copies are the live ones
}

EnvProcess::~EnvProcess() {
  if (pid_ > 0 && owner_.here()) {  // in a fork of the parent the child is the parent's to stop
    // A command still running (the caller's own envs threw meanwhile) may finish first; a child
    // that answers nothing within 5 s, or does not quit within 5 s more, is killed: a destructor
    // must end.
    using Clock = std::chrono::steady_clock;
    const auto deadline = Clock::now() + std::chrono::seconds(5);
    while (busy_ && Clock::now() < deadline) {
      const std::uint32_t seen = shared_->reply.load(std::memory_order_acquire);
      if (seen == shared_->request.load(std::memory_order_relaxed)) busy_ = false;
      else wait_change(shared_->reply, seen, 100);
    }
    int status = 0;
    if (!busy_) {
      start(kQuit);
      const auto quit_deadline = Clock::now() + std::chrono::seconds(5);
      while (waitpid(pid_, &status, WNOHANG) == 0 && Clock::now() < quit_deadline) usleep(1000);
    }
    if (waitpid(pid_, &status, WNOHANG) == 0) {
      kill(pid_, SIGKILL);
      waitpid(pid_, &status, 0);
    }
  }
  if (socket_ >= 0) close(socket_);
  if (shared_) munmap(shared_, map_bytes_);
}

std::string EnvProcess::what_envs() const {
  return "envs " + std::to_string(first_) + "-" + std::to_string(first_ + count_ - 1) + " (worker process)";
}

std::uint8_t* EnvProcess::slot(int i) const {
  return reinterpret_cast<std::uint8_t*>(shared_) + aligned(sizeof(Shared)) + slot_bytes_ * static_cast<std::size_t>(i);
}

void EnvProcess::start(std::uint32_t command) {
  owner_.require(what_envs());
  RDSIM_ASSERT(!busy_, "EnvProcess: a command is still running");
  shared_->command = command;
  busy_ = true;
  publish(shared_->request, shared_->request.load(std::memory_order_relaxed) + 1);
}

void EnvProcess::finish() {
  RDSIM_ASSERT(busy_, "EnvProcess::finish without a command");
  const std::uint32_t want = shared_->request.load(std::memory_order_relaxed);
  for (;;) {
    const std::uint32_t seen = shared_->reply.load(std::memory_order_acquire);
    if (seen == want) break;
    if (wait_change(shared_->reply, seen, 200)) continue;
    int status = 0;
    if (waitpid(pid_, &status, WNOHANG) == pid_) {  // only a dead child stops answering for good
      pid_ = -1;
      busy_ = false;
      throw Error(what_envs() + ": the process " + exit_reason(status));
    }
  }
  busy_ = false;
  if (shared_->failed) throw Error(std::string(shared_->error));
}

void EnvProcess::start_reset(const std::vector<std::uint64_t>& seeds) {
  RDSIM_ASSERT(static_cast<int>(seeds.size()) == count_, "EnvProcess: one seed per env");
  for (int i = 0; i < count_; ++i) reinterpret_cast<SlotHead*>(slot(i))->seed = seeds[static_cast<std::size_t>(i)];
  start(kReset);
}

void EnvProcess::start_step(const std::vector<Action>& actions, const std::vector<bool>& active) {
  for (int i = 0; i < count_; ++i) {
    const auto k = static_cast<std::size_t>(first_ + i);
    auto* head = reinterpret_cast<SlotHead*>(slot(i));
    head->active = active[k] ? 1 : 0;
    if (!head->active) continue;
    const Action& a = actions[k];
    head->action_index = a.index;
    if (action_floats_ > 0) {
      // The slot holds exactly the env's action size: a wrong-sized action is refused here, as the
      // env itself would refuse it, before anything is sent.
      if (static_cast<std::size_t>(a.values.size()) != action_floats_)
        throw Error("env " + std::to_string(first_ + i) + ": action of size " + std::to_string(a.values.size()) +
                    ", expected " + std::to_string(action_floats_));
      std::memcpy(slot(i) + sizeof(SlotHead), a.values.data(), 4 * action_floats_);
    }
  }
  start(kStep);
}

void EnvProcess::start_drop_caches() { start(kDropCaches); }

void EnvProcess::copy_observation(int i, ObservationOut out) const {
  copy_from_slot(slot(i) + aligned(sizeof(SlotHead) + 4 * action_floats_), out);
}

void EnvProcess::copy_from_slot(const std::uint8_t* obs, ObservationOut out) const {
  if (value_bytes_ > 0) std::memcpy(out.values, obs, value_bytes_);
  if (obs_bytes_ > value_bytes_) std::memcpy(out.pixels, obs + value_bytes_, obs_bytes_ - value_bytes_);
}

StepOutcome EnvProcess::outcome(int i) const { return reinterpret_cast<const SlotHead*>(slot(i))->outcome; }

void EnvProcess::copy_final_observation(int i, Observation& out) const {
  out = make_observation(spec_.observation);
  const std::uint8_t* obs = slot(i) + aligned(sizeof(SlotHead) + 4 * action_floats_) + aligned(obs_bytes_);
  copy_from_slot(obs, observation_out(out));
}

std::vector<std::optional<std::string>> EnvProcess::save_states() {
  start(kSave);
  std::uint64_t n = 0;
  std::string blob;
  if (recv_all(socket_, &n, sizeof n) && n != kSaveFailed) {
    blob.resize(n);
    if (!recv_all(socket_, blob.data(), n)) blob.clear();
  }
  finish();  // the child's error or death, if any
  return unpack(blob, count_);
}

void EnvProcess::load_states(const std::vector<std::string>& states, const std::string& source) {
  RDSIM_ASSERT(static_cast<int>(states.size()) == count_, "EnvProcess: one state per env");
  std::vector<std::optional<std::string>> all(states.begin(), states.end());
  std::string blob = pack(all);
  blob = source + '\0' + blob;
  start(kLoad);
  send_blob(socket_, blob);  // a dead child shows in finish()
  finish();
}

// ---- the child --------------------------------------------------------------------------------

void EnvProcess::child_main(std::vector<std::unique_ptr<Env>>& envs) {
  const pid_t parent = getppid();
  std::uint32_t seen = 0;  // the count at fork: the parent may have started a command already
  for (;;) {
    while (!wait_change(shared_->request, seen, 1000))
      if (getppid() != parent) _exit(0);
    seen = shared_->request.load(std::memory_order_acquire);
    const std::uint32_t command = shared_->command;
    if (command == kQuit) {
      envs.clear();  // a renderer releases its GL context
      publish(shared_->reply, seen);
      _exit(0);  // no atexit handlers or static destructors: they belong to the parent
    }
    shared_->failed = 0;
    try {
      child_run(envs, command);

    } catch (const std::exception& e) {
      std::snprintf(shared_->error, sizeof shared_->error, "%s", e.what());
      shared_->failed = 1;
    } catch (...) {
      std::snprintf(shared_->error, sizeof shared_->error, "%s: unknown error", what_envs().c_str());
      shared_->failed = 1;
    }
    publish(shared_->reply, seen);
  }
}

void EnvProcess::child_run(std::vector<std::unique_ptr<Env>>& envs, std::uint32_t command) {
  const std::size_t obs_at = aligned(sizeof(SlotHead) + 4 * action_floats_);
  // Envs write into this process's own memory, then the observation is streamed to the slot.
  scratch_.resize((obs_bytes_ + 3) / 4);
  auto* bytes = reinterpret_cast<std::uint8_t*>(scratch_.data());
  const ObservationOut out{value_bytes_ > 0 ? scratch_.data() : nullptr,
                           obs_bytes_ > value_bytes_ ? bytes + value_bytes_ : nullptr};
  switch (command) {
    case kReset:
      for (int i = 0; i < count_; ++i) {
        envs[static_cast<std::size_t>(i)]->reset_into(out, reinterpret_cast<SlotHead*>(slot(i))->seed);
        stream_copy(slot(i) + obs_at, bytes, obs_bytes_);
      }
      return;
    case kStep: {
      Action action;
      if (action_floats_ > 0) action.values.resize(static_cast<Eigen::Index>(action_floats_));
      for (int i = 0; i < count_; ++i) {
        auto* head = reinterpret_cast<SlotHead*>(slot(i));
        if (!head->active) continue;
        action.index = head->action_index;
        if (action_floats_ > 0) std::memcpy(action.values.data(), slot(i) + sizeof(SlotHead), 4 * action_floats_);
        Env& env = *envs[static_cast<std::size_t>(i)];
        head->outcome = env.step_into(action, out);
        if (head->outcome.terminated || head->outcome.truncated) {
          stream_copy(slot(i) + obs_at + aligned(obs_bytes_), bytes, obs_bytes_);
          env.reset_into(out);
        }
        stream_copy(slot(i) + obs_at, bytes, obs_bytes_);
      }
      return;
    }
    case kDropCaches:
      for (auto& env : envs)
        if (auto* caches = dynamic_cast<EnvCaches*>(env.get())) caches->drop_caches();
      return;
    case kSave: {
      std::string blob;
      try {
        std::vector<std::optional<std::string>> states;
        for (const auto& env : envs) {
          const auto* state = dynamic_cast<const EnvState*>(env.get());
          states.push_back(state ? std::optional<std::string>(state->save_state()) : std::nullopt);
        }
        blob = pack(states);
      } catch (...) {
        const std::uint64_t failed = kSaveFailed;
        send_all(socket_, &failed, sizeof failed);
        throw;
      }
      send_blob(socket_, blob);
      return;
    }
    case kLoad: {
      std::uint64_t n = 0;
      std::string blob;
      if (!recv_all(socket_, &n, sizeof n)) _exit(0);
      blob.resize(n);
      if (!recv_all(socket_, blob.data(), n)) _exit(0);
      const std::size_t end = blob.find('\0');
      const std::string source = blob.substr(0, end);
      const auto states = unpack(blob.substr(end + 1), count_);
      for (int i = 0; i < count_; ++i) {
        auto* state = dynamic_cast<EnvState*>(envs[static_cast<std::size_t>(i)].get());
        if (!state) throw Error(source + ": checkpoint holds env states this env cannot load");
        state->load_state(*states[static_cast<std::size_t>(i)], source);
      }
      return;
    }
    default:
      RDSIM_ASSERT(false, "EnvProcess: unknown command");
  }
}

}  // namespace rdsim
