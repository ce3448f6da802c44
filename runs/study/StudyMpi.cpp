// The MPI executor (built when CMake finds MPI): rank 0 schedules the tasks dynamically, longest
// expected first; every other rank asks for a task, runs it in its own process (so that a task
// that crashes costs that task and not the rank), reports, and asks again.
#include <mpi.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <map>
#include <thread>

#include "runs/ExitCode.hpp"
#include "runs/Interrupts.hpp"
#include "runs/study/StudyRunner.hpp"

namespace keller {

namespace {

constexpr int tag_ready = 1, tag_task = 2;
constexpr int no_task = -1;
// rank 0 polls instead of blocking in MPI_Recv, which spins on a core
constexpr auto poll_interval = std::chrono::milliseconds(5);

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
  std::map<int, int> attempts;
  int stopped = 0, running = 0;
  bool failures = false;
  while (stopped < size - 1) {
    int flag = 0;
    MPI_Status st;
    MPI_Iprobe(MPI_ANY_SOURCE, tag_ready, MPI_COMM_WORLD, &flag, &st);
    if (!flag) {
      std::this_thread::sleep_for(poll_interval);
      continue;
    }
    int msg[2];  // the task it finished (or no_task), waitpid's status
    MPI_Recv(msg, 2, MPI_INT, st.MPI_SOURCE, tag_ready, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (msg[0] != no_task) {
      --running;
      const StudyTask& task = study.tasks()[static_cast<size_t>(msg[0])];
      TaskRecord record = finished_task(study, task, msg[1]);
      record.attempts = attempts[task.index];
      if (record.status == "died" && record.attempts < 2 && !InterruptGuard::requested()) {
        std::printf("task %d (%s): %s; running it again\n", task.index, task.label().c_str(),
                    record.summary.reason.c_str());
        queue.push_back(task.index);
      } else {
        if (record.status == "died") record.status = "failed";
        if (record.status != "interrupted") write_task_record(study, task, record);
        failures |= record.status == "failed";
        progress.finished(task, record);
      }
    }
    // a worker that gets nothing stops: a task that dies later is retried by the worker that
    // reports it, which asks for its next task in the same message
    int next = no_task;
    if (!InterruptGuard::requested() && !queue.empty()) {
      next = queue.front();
      queue.pop_front();
      ++attempts[next];
      ++running;
    }
    if (next == no_task) ++stopped;
    MPI_Send(&next, 1, MPI_INT, st.MPI_SOURCE, tag_task, MPI_COMM_WORLD);
  }
  write_study_table(study);
  if (InterruptGuard::requested()) return exit_code::interrupted;
  return failures ? exit_code::numerical_failure : exit_code::ok;
}

void work(const Study& study, int size) {
  const int threads = blas_threads_for(local_workers(size));
  int msg[2] = {no_task, 0};
  while (true) {
    MPI_Send(msg, 2, MPI_INT, 0, tag_ready, MPI_COMM_WORLD);
    int task = no_task;
    MPI_Recv(&task, 1, MPI_INT, 0, tag_task, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    if (task == no_task) return;
    const pid_t pid = spawn_task(study, study.tasks()[static_cast<size_t>(task)], threads);
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    msg[0] = task;
    msg[1] = status;
  }
}

}  // namespace

bool under_mpi() { return std::getenv("OMPI_COMM_WORLD_SIZE") || std::getenv("PMI_SIZE"); }

int run_study_mpi(const Study& study, int& argc, char**& argv) {
  MPI_Init(&argc, &argv);
  int rank = 0, size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  int code = exit_code::ok;
  if (size == 1) {
    if (rank == 0) code = run_study_local(study, 1);
  } else if (rank == 0) {
    code = schedule(study, size);
  } else {
    work(study, size);
  }
  MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD);
  MPI_Finalize();
  return code;
}

}  // namespace keller
