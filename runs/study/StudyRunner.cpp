#include "runs/study/StudyRunner.hpp"

#include <cstdlib>

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstring>
#include <deque>
#include <filesystem>
#include <map>
#include <thread>
#include <utility>

#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/SceneLoader.hpp"
#include "runs/TraceCommand.hpp"
#include "runs/study/StudyTable.hpp"
#include "runs/study/TaskScenes.hpp"

namespace keller {

namespace fs = std::filesystem;

namespace {

std::string g_task_program = "/proc/self/exe";

double now_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::string duration(double s) {
  if (s < 90) return fmt::format("{:.0f} s", s);
  if (s < 5400) return fmt::format("{:.0f} min", s / 60);
  return fmt::format("{:.1f} h", s / 3600);
}

// The wait for the end of a task's process that a signal to this process ends too: SIGINT,
// SIGTERM and SIGCHLD are blocked but in sigsuspend, so that none comes between a look at the
// children and the wait (the signal would then be seen only when a task ended by itself).
class ChildWait {
 public:
  ChildWait() {
    sigset_t block;
    sigemptyset(&block);
    for (int s : {SIGINT, SIGTERM, SIGCHLD}) sigaddset(&block, s);
    ::sigprocmask(SIG_BLOCK, &block, &old_mask_);
    waiting_ = old_mask_;
    for (int s : {SIGINT, SIGTERM, SIGCHLD}) sigdelset(&waiting_, s);
    struct sigaction sa {};
    sa.sa_handler = [](int) {};  // (the default action ignores SIGCHLD: it would not end sigsuspend)
    sigemptyset(&sa.sa_mask);
    ::sigaction(SIGCHLD, &sa, &old_chld_);
  }
  ~ChildWait() {
    ::sigaction(SIGCHLD, &old_chld_, nullptr);
    ::sigprocmask(SIG_SETMASK, &old_mask_, nullptr);
  }
  ChildWait(const ChildWait&) = delete;
  ChildWait& operator=(const ChildWait&) = delete;
  // A child that ended (its pid and status), 0 when a signal came first, -1 when none is left.
  pid_t next(int& status) {
    const pid_t pid = ::waitpid(-1, &status, WNOHANG);
    if (pid != 0) return pid;
    ::sigsuspend(&waiting_);
    return 0;
  }

 private:
  sigset_t old_mask_, waiting_;
  struct sigaction old_chld_ {};
};

}  // namespace

int blas_threads_for(int workers, int cores, const char* user) {
  int threads = std::max(1, std::max(1, cores) / std::max(1, workers));
  if (user) {
    char* end = nullptr;
    const long limit = std::strtol(user, &end, 10);
    if (end != user && *end == '\0' && limit > 0) threads = static_cast<int>(std::min<long>(threads, limit));
  }
  return threads;
}

int blas_threads_for(int workers) {
  return blas_threads_for(workers, static_cast<int>(std::max(1u, std::thread::hardware_concurrency())),
                          std::getenv("OPENBLAS_NUM_THREADS"));
}

pid_t spawn_task(const Study& study, const StudyTask& task, int blas_threads) {
  std::error_code ec;  // a folder that cannot be made: the task fails, and says why
  fs::create_directories(fs::path(study.task_log(task)).parent_path(), ec);
  const pid_t parent = ::getpid();
  const std::string index = std::to_string(task.index), threads = std::to_string(blas_threads);
  const std::string log = study.task_log(task);
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  // the child: dies with its parent (SIGTERM: it stops after its current point), writes to its log,
  // and takes the signals its parent may block while it waits (ChildWait)
  sigset_t signals;
  sigemptyset(&signals);
  for (int s : {SIGINT, SIGTERM, SIGCHLD}) sigaddset(&signals, s);
  ::sigprocmask(SIG_UNBLOCK, &signals, nullptr);
  ::prctl(PR_SET_PDEATHSIG, SIGTERM);
  if (::getppid() != parent) ::_exit(exit_code::interrupted);
  const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd >= 0) {
    ::dup2(fd, STDOUT_FILENO);
    ::dup2(fd, STDERR_FILENO);
    ::close(fd);
  }
  ::setenv("OPENBLAS_NUM_THREADS", threads.c_str(), 1);
  ::setenv("OMP_NUM_THREADS", threads.c_str(), 1);
  ::execl(g_task_program.c_str(), "keller", "study", "run", study.path().c_str(), "--task", index.c_str(), "-o",
          study.folder().c_str(), static_cast<char*>(nullptr));
  ::_exit(127);
}

void set_task_program(std::string path) { g_task_program = std::move(path); }

bool stopped_by_signal(int status) {
  return WIFSIGNALED(status) && (WTERMSIG(status) == SIGTERM || WTERMSIG(status) == SIGINT);
}

TaskRecord finished_task(const Study& study, const StudyTask& task, pid_t pid, int status) {
  if (auto r = read_task_record(study, task); r && r->pid == pid && task_current(study, task, *r)) return *r;
  TaskRecord died;
  died.hash = task.hash;
  died.status = "died";
  died.summary.exit_code = -1;
  died.summary.reason = WIFSIGNALED(status) ? fmt::format("its process died of signal {} ({})", WTERMSIG(status),
                                                          ::strsignal(WTERMSIG(status)))
                                            : fmt::format("its process ended with exit code {} and no record",
                                                          WIFEXITED(status) ? WEXITSTATUS(status) : -1);
  return died;
}

std::vector<int> tasks_to_run(const Study& study) {
  std::vector<int> todo;
  std::map<int, double> before;  // the time a task took when it last ran
  for (const StudyTask& t : study.tasks()) {
    if (task_done(study, t)) continue;
    try {
      const OutputLock held = hold_task_output(study, t);
      set_aside_foreign_outputs(study, t, held);
    } catch (const std::runtime_error& e) {  // the task's run meets it, and says so
      fmt::print(stderr, "keller: warning: {}\n", e.what());
    }
    todo.push_back(t.index);
    if (const auto r = read_task_record(study, t); r && r->summary.seconds > 0) before[t.index] = r->summary.seconds;
  }
  std::map<int, double> cost;
  if (before.size() == todo.size()) {
    cost = before;
  } else {
    // the size of each task's problem, built once per problem: a factorisation costs about n^1.5
    std::map<std::string, double> size_of;
    TaskScenes scenes(study.kind());
    for (int i : todo) {
      const StudyTask& t = study.tasks()[static_cast<size_t>(i)];
      if (!size_of.count(t.problem)) {
        size_of[t.problem] = 1;
        try {
          const LoadedScene loaded = scenes.load(t);
          size_of[t.problem] = static_cast<double>(loaded.type->build(loaded.scene)->size());
        } catch (const std::exception&) {  // it fails when it runs, and says why there
        }
      }
      cost[i] = std::pow(size_of[t.problem], 1.5);
    }
  }
  std::stable_sort(todo.begin(), todo.end(), [&](int a, int b) { return cost[a] > cost[b]; });
  return todo;
}

StudyProgress::StudyProgress(const Study& study, int to_run, int workers)
    : study_(study), total_(to_run), workers_(workers), start_(now_seconds()) {
  const int all = static_cast<int>(study.tasks().size());
  fmt::print("study {}: {} tasks, {} done before, {} to run on {} worker{} ({} BLAS thread{} each); output in {}/\n",
             study.name(), all, all - to_run, to_run, workers, workers == 1 ? "" : "s", blas_threads_for(workers),
             blas_threads_for(workers) == 1 ? "" : "s", study.folder());
  std::fflush(stdout);
}

void StudyProgress::finished(const StudyTask& task, const TaskRecord& record) {
  ++done_;
  const StudyRow row = StudyTable::row(study_, task);
  const double elapsed = now_seconds() - start_;
  const int left = total_ - done_;
  // the remaining tasks at the pace so far (the longest ran first, so this errs high)
  const std::string eta = left == 0 ? "" : fmt::format("; about {} left", duration(elapsed / done_ * left));
  const std::string what = record.status == "done" ? row.found : record.status + ": " + record.summary.reason;
  fmt::print("[{}/{}] task {} ({}): {}{}\n", done_, total_, task.index, task.label(), what, eta);
  std::fflush(stdout);
}

void print_overhead(int gaps, double gap_seconds, int tasks, double process_seconds) {
  if (gaps == 0 || tasks == 0) return;
  const double per_task = gap_seconds / gaps, task = process_seconds / tasks;
  fmt::print(
      "scheduling: {:.2f} ms between a task's end and the next task's start on its worker, {:.3f}% of a "
      "task's mean {:.3f} s\n",
      1e3 * per_task, task > 0 ? 100 * per_task / task : 0.0, task);
}

bool write_study_table(const Study& study) {
  const StudyTable table = StudyTable::collect(study);
  try {
    table.write(study.table_csv(), study.table_h5());
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: the study's table cannot be written: {}\n", e.what());
    return false;
  }
  int done = 0, failed = 0, damaged = 0;
  for (const StudyRow& r : table.rows()) {
    const std::string& s = r.text.at("status");
    done += s == "done";
    failed += s == "failed" || s == "died";
    damaged += s == "damaged";
  }
  fmt::print("collected {} tasks ({} done, {} failed, {} not run{}) in {} and {}\n", table.rows().size(), done, failed,
             table.rows().size() - done - failed - damaged,
             damaged ? fmt::format(", {} with a damaged or foreign output", damaged) : "", study.table_csv(),
             study.table_h5());
  return true;
}

bool save_task_record(const Study& study, const StudyTask& task, const TaskRecord& record) {
  try {
    write_task_record(study, task, record);
    return true;
  } catch (const std::exception& e) {
    fmt::print(stderr, "keller: error: the record of task {} cannot be written: {}\n", task.index, e.what());
    return false;
  }
}

OutputLock hold_study_folder(const Study& study) {
  const fs::path folder(study.folder());
  for (const fs::path& dir : {folder, folder / "tasks"}) {
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
      throw std::invalid_argument(
          fmt::format("'{}' is not a folder: a study's files go to a folder (-o FOLDER)", dir.string()));
    if (!fs::is_directory(dir, ec) && !fs::create_directories(dir, ec))
      throw std::invalid_argument(fmt::format("the study folder '{}' cannot be made: {}", dir.string(), ec.message()));
    if (::access(dir.c_str(), W_OK) != 0)
      throw std::invalid_argument(fmt::format("the study folder '{}' is not writable", dir.string()));
  }
  return OutputLock((folder / "study.lock").string(), fmt::format("the study folder '{}'", folder.string()));
}

int run_study_local(const Study& study, int jobs) {
  const std::vector<int> order = tasks_to_run(study);
  const int workers = std::max(1, std::min<int>(jobs, static_cast<int>(order.size())));
  StudyProgress progress(study, static_cast<int>(order.size()), workers);
  InterruptGuard interrupts;
  ChildWait wait;
  std::deque<int> queue(order.begin(), order.end());
  std::map<pid_t, int> running;
  std::map<pid_t, double> started;
  std::map<int, int> attempts;
  std::map<int, double> earlier;  // the process seconds of a task's interrupted runs (interrupted_record)
  bool failures = false, interrupted = false, forwarded = false;
  bool unwritten = false;  // a record could not be written: no task starts after it
  // the scheduling overhead: from a task's end to the start of the next on its worker
  double reaped = -1, gaps = 0, process = 0;
  int spawned_after_reap = 0, finished = 0;
  auto fill = [&]() {  // a free worker starts the next task before anything else is done
    while (!InterruptGuard::requested() && !unwritten && !queue.empty() && static_cast<int>(running.size()) < workers) {
      const int i = queue.front();
      queue.pop_front();
      ++attempts[i];
      const StudyTask& task = study.tasks()[static_cast<size_t>(i)];
      const auto before = interrupted_record(study, task);
      earlier[i] = before ? before->process_seconds : 0.0;
      const pid_t pid = spawn_task(study, task, blas_threads_for(workers));
      running[pid] = i;
      started[pid] = now_seconds();
      if (reaped >= 0) {
        gaps += started[pid] - reaped;
        ++spawned_after_reap;
        reaped = -1;
      }
    }
  };
  while (!queue.empty() || !running.empty()) {
    fill();
    if (running.empty()) break;
    if (InterruptGuard::requested() && !forwarded) {
      // a signal to this process alone reaches the running tasks: they stop after their current point
      for (const auto& [pid, index] : running) ::kill(pid, SIGTERM);
      forwarded = true;
    }
    int status = 0;
    const pid_t pid = wait.next(status);
    if (pid == 0) continue;  // a signal
    if (pid < 0) {
      if (errno == EINTR) continue;
      break;
    }
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    reaped = now_seconds();
    const StudyTask& task = study.tasks()[static_cast<size_t>(it->second)];
    running.erase(it);
    const double task_seconds = reaped - started[pid];
    fill();
    TaskRecord record = finished_task(study, task, pid, status);
    record.attempts = attempts[task.index];
    record.process_seconds = (record.summary.runs > 1 ? earlier[task.index] : 0.0) + task_seconds;
    process += task_seconds;
    ++finished;
    if (record.status == "died" && InterruptGuard::requested() && stopped_by_signal(status))
      record.status = "interrupted";  // (before its run took signals: its output is as it was)
    if (record.status == "died" && record.attempts < 2 && !InterruptGuard::requested() && !unwritten) {
      fmt::print("task {} ({}): {}; running it again\n", task.index, task.label(), record.summary.reason);
      queue.push_back(task.index);
      continue;
    }
    if (record.status == "died") record.status = "failed";
    unwritten |= !save_task_record(study, task, record);
    failures |= record.status == "failed";
    interrupted |= record.status == "interrupted";
    progress.finished(task, record);
  }
  print_overhead(spawned_after_reap, gaps, finished, process);
  unwritten |= !write_study_table(study);
  if (unwritten) {
    fmt::print(stderr, "keller: error: the study stopped: its files cannot be written in {}/ (is the disk full?)\n",
               study.folder());
    return exit_code::io_failure;
  }
  if (InterruptGuard::requested() || interrupted) {
    fmt::print(
        "interrupted: the tasks that were running stop after their current point; run the study again to "
        "continue them\n");
    return exit_code::interrupted;
  }
  return failures ? exit_code::numerical_failure : exit_code::ok;
}

}  // namespace keller
