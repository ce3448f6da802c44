// The MPI executor (built when CMake finds MPI): rank 0 schedules the tasks dynamically, longest
// expected first; every other rank asks for a task, runs it in its own process (so that a task
// that crashes costs that task and not the rank), reports, and asks again.
#include <mpi.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <map>
#include <set>
#include <thread>

#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/study/StudyRunner.hpp"

namespace keller {

namespace {

constexpr int tag_ready = 1, tag_task = 2;
constexpr int no_task = -1;
constexpr int stop_task = -2;  // (on tag_task) the study was interrupted: stop the running task after its point
// rank 0 polls instead of blocking in MPI_Recv, which spins on a core
constexpr auto poll_interval = std::chrono::milliseconds(1);

// The workers that share this rank's machine: OpenMPI says how many ranks run here.
int local_workers(int size) {
  const char* local = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  const int ranks_here = local ? std::atoi(local) : size;
  return std::max(1, ranks_here - 1);  // rank 0 schedules and mostly sleeps
}

int schedule(const Study& study, int size) {
  const std::vector<int> order = tasks_to_run(study);
  StudyProgress progress(study, static_cast<int>(order.size()), size - 1);
  InterruptGuard interrupts;
  std::deque<int> queue(order.begin(), order.end());
  std::deque<int> idle;  // workers waiting for a task while others run (one of theirs may come back)
  std::map<int, int> attempts;
  std::map<int, double> earlier;  // the process seconds of a task's interrupted runs (interrupted_record)
  std::set<int> busy;             // the workers running a task
  int stopped = 0, running = 0, gaps = 0, finished = 0;
  double gap_seconds = 0, process_seconds = 0;
  bool failures = false, interrupted = false, forwarded = false;
  bool unwritten = false;  // a record could not be written: no task starts after it
  bool signalled = false;  // a worker rank had a signal of its own: the study stops as for one to this rank
  auto stopping = [&]() { return InterruptGuard::requested() || signalled || unwritten; };
  auto give = [&](int worker) {  // the next task, or none (the worker stops) when none can come
    int next = no_task;
    if (!stopping() && !queue.empty()) {
      next = queue.front();
      queue.pop_front();
      ++attempts[next];
      const auto before = interrupted_record(study, study.tasks()[static_cast<size_t>(next)]);
      earlier[next] = before ? before->process_seconds : 0.0;
      busy.insert(worker);
      ++running;
    } else if (!stopping() && running > 0) {
      idle.push_back(worker);
      return;
    }
    if (next == no_task) ++stopped;
    MPI_Send(&next, 1, MPI_INT, worker, tag_task, MPI_COMM_WORLD);
  };
  while (stopped < size - 1) {
    if (stopping() && !forwarded) {
      // a signal to this rank alone reaches the running tasks: they stop after their current point
      for (int worker : busy) MPI_Send(&stop_task, 1, MPI_INT, worker, tag_task, MPI_COMM_WORLD);
      forwarded = true;
    }
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, tag_ready, MPI_COMM_WORLD, &flag, &st);
    if (!flag) {
      std::this_thread::sleep_for(poll_interval);
      continue;
    }
    // the task it finished (or no_task), waitpid's status, the task process's seconds, the time
    // it waited between its last task's end and the start of the task before, why it stopped
    // (wait_for_task) and the task process's pid
    double msg[6];
    MPI_Recv(msg, 6, MPI_DOUBLE, st.MPI_SOURCE, tag_ready, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (msg[3] > 0) {
      gap_seconds += msg[3];
      ++gaps;
    }
    signalled |= msg[4] > 1;
    const bool reported = static_cast<int>(msg[0]) != no_task;
    if (reported) --running;
    busy.erase(st.MPI_SOURCE);
    give(st.MPI_SOURCE);  // first the worker's next task; the finished one is read after
    if (reported) {
      const StudyTask& done = study.tasks()[static_cast<size_t>(msg[0])];
      TaskRecord record = finished_task(study, done, static_cast<pid_t>(msg[5]), static_cast<int>(msg[1]));
      record.attempts = attempts[done.index];
      record.process_seconds = (record.summary.runs > 1 ? earlier[done.index] : 0.0) + msg[2];
      process_seconds += msg[2];
      ++finished;
      if (record.status == "died" && (stopping() || msg[4] > 0) && stopped_by_signal(static_cast<int>(msg[1])))
        record.status = "interrupted";  // (before its run took signals: its output is as it was)
      if (record.status == "died" && record.attempts < 2 && !stopping()) {
        std::printf("task %d (%s): %s; running it again\n", done.index, done.label().c_str(),
                    record.summary.reason.c_str());
        queue.push_back(done.index);
      } else {
        if (record.status == "died") record.status = "failed";
        unwritten |= !save_task_record(study, done, record);
        failures |= record.status == "failed";
        interrupted |= record.status == "interrupted";
        progress.finished(done, record);
      }
    }
    // the waiting workers: a task came back, or nothing more can come
    while (!idle.empty() && (!queue.empty() || running == 0 || stopping())) {
      const int worker = idle.front();
      idle.pop_front();
      give(worker);
    }
  }
  print_overhead(gaps, gap_seconds, finished, process_seconds);
  unwritten |= !write_study_table(study);
  if (unwritten) {
    std::fprintf(stderr, "keller: error: the study stopped: its files cannot be written in %s/ (is the disk full?)\n",
                 study.folder().c_str());
    return exit_code::io_failure;
  }
  if (stopping() || interrupted) {
    std::printf(
        "interrupted: the tasks that were running stop after their current point; run the study again to "
        "continue them\n");
    return exit_code::interrupted;
  }
  return failures ? exit_code::numerical_failure : exit_code::ok;
}

// Waits for the task's process, which stops after its current point where rank 0 says the study
// was interrupted (stop_task: returns 1) or a signal reaches this rank (2); 0 where it ended by itself.
int wait_for_task(pid_t pid, int& status) {
  int stop = 0;
  while (true) {
    const pid_t ended = ::waitpid(pid, &status, WNOHANG);
    if (ended == pid || (ended < 0 && errno != EINTR)) return stop;
    int flag = 0;
    MPI_Iprobe(0, tag_task, MPI_COMM_WORLD, &flag, MPI_STATUS_IGNORE);
    if (flag) {
      int message = 0;
      MPI_Recv(&message, 1, MPI_INT, 0, tag_task, MPI_COMM_WORLD, MPI_STATUS_IGNORE);  // (only stop_task comes now)
    }
    if (!stop && (flag || InterruptGuard::requested())) {
      ::kill(pid, SIGTERM);
      stop = flag ? 1 : 2;
    }
    std::this_thread::sleep_for(poll_interval);
  }
}

void work(const Study& study, int size) {
  const int threads = blas_threads_for(local_workers(size));
  InterruptGuard interrupts;
  // the task it finished (or no_task), waitpid's status, the task process's seconds, the time it
  // waited between its last task's end and this task's start, why it stopped (wait_for_task) and
  // the task process's pid
  double msg[6] = {no_task, 0, 0, 0, 0, 0};
  auto ended = std::chrono::steady_clock::now();
  double waited = 0;  // between the last task's end and this task's start, reported with the next message
  while (true) {
    msg[3] = waited;
    MPI_Send(msg, 6, MPI_DOUBLE, 0, tag_ready, MPI_COMM_WORLD);
    int task = stop_task;
    while (task == stop_task)  // (a stop that came after its task had ended)
      MPI_Recv(&task, 1, MPI_INT, 0, tag_task, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (task == no_task) return;
    const auto t0 = std::chrono::steady_clock::now();
    waited = msg[0] == no_task ? 0 : std::chrono::duration<double>(t0 - ended).count();
    const pid_t pid = spawn_task(study, study.tasks()[static_cast<size_t>(task)], threads);
    int status = 0;
    const int stop = wait_for_task(pid, status);
    msg[0] = task;
    msg[1] = status;
    msg[4] = stop;
    msg[5] = pid;
    ended = std::chrono::steady_clock::now();
    msg[2] = std::chrono::duration<double>(ended - t0).count();
  }
}

}  // namespace

bool under_mpi() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"); }

int run_study_mpi(const Study& study, int& argc, char**& argv) {
  MPI_Init(&argc, &argv);
  // MPI_Initialized is the MPI library's alone: false here means that MPI_Init was bound to the MPI
  // stub of sequential MUMPS, which exports the same C symbol (the top-level CMakeLists.txt links
  // libmpi ahead of MUMPS to prevent it)
  int initialised = 0;
  MPI_Initialized(&initialised);
  if (!initialised) {
    std::fprintf(stderr,
                 "keller: error: MPI_Init did not reach the MPI library: this keller is linked with MUMPS's MPI stub "
                 "ahead of libmpi (link MPI::MPI_C before MUMPS's libraries)\n");
    return exit_code::usage;
  }
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  // rank 0 holds the study's folder (a second study on it is refused) and tells the others
  int code = exit_code::ok;
  OutputLock folder;
  if (rank == 0) {
    try {
      folder = hold_study_folder(study);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "keller: error: %s\n", e.what());
      code = exit_code::usage;
    }
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
  if (code == exit_code::ok) {
    if (size == 1) {
      if (rank == 0) code = run_study_local(study, 1);
    } else if (rank == 0) {
      code = schedule(study, size);
    } else {
      work(study, size);
    }
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return code;
}

}  // namespace keller
