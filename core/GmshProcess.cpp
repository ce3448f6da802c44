#include "core/GmshProcess.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <iostream>
#include <stdexcept>

#include "core/MeshFileError.hpp"

namespace keller {

namespace {

constexpr char kAnswer = 'A';  // the child's answer: 'A' and the bytes, or 'E' and a message
constexpr char kError = 'E';

bool write_all(int fd, const char* data, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, data, n);
    if (w < 0 && errno == EINTR) continue;
    if (w <= 0) return false;
    data += w;
    n -= static_cast<std::size_t>(w);
  }
  return true;
}

std::string read_all(int fd) {
  std::string out;
  char buffer[65536];
  for (;;) {
    const ssize_t r = ::read(fd, buffer, sizeof buffer);
    if (r < 0 && errno == EINTR) continue;
    if (r <= 0) return out;
    out.append(buffer, static_cast<std::size_t>(r));
  }
}

// The process's data segment in bytes (/proc/self/statm: data + stack pages), 0 if unknown.
std::size_t data_in_use() {
  std::FILE* statm = std::fopen("/proc/self/statm", "r");
  if (!statm) return 0;
  unsigned long pages[6] = {};
  const int read =
      std::fscanf(statm, "%lu %lu %lu %lu %lu %lu", &pages[0], &pages[1], &pages[2], &pages[3], &pages[4], &pages[5]);
  std::fclose(statm);
  return read == 6 ? pages[5] * static_cast<std::size_t>(::sysconf(_SC_PAGESIZE)) : 0;
}

// In the child: no output to keller's terminal, none of keller's files, then the work.
[[noreturn]] void child(int answer_fd, std::size_t memory_limit, const std::function<std::string()>& work) {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (memory_limit > 0) {  // on top of what the child has from keller already
    const rlimit limit{data_in_use() + memory_limit, data_in_use() + memory_limit};
    ::setrlimit(RLIMIT_DATA, &limit);
  }
  if (answer_fd != 3) ::dup2(answer_fd, 3);
  const int null = ::open("/dev/null", O_RDWR);
  if (null >= 0) {
    ::dup2(null, STDOUT_FILENO);
    ::dup2(null, STDERR_FILENO);
  }
  ::close_range(4, ~0U, 0);
  std::string message;
  char kind = kAnswer;
  try {
    message = work();
  } catch (const std::exception& e) {
    kind = kError;
    message = e.what();
  } catch (...) {
    kind = kError;
    message = "the Gmsh process stopped with an unknown exception";
  }
  const bool sent = write_all(3, &kind, 1) && write_all(3, message.data(), message.size());
  ::_exit(sent ? 0 : 1);
}

}  // namespace

std::string run_gmsh_child(const std::string& file, const std::string& what, std::size_t memory_limit,
                           const std::function<std::string()>& work) {
  int fds[2];
  if (::pipe(fds) != 0)
    throw MeshFileError(fmt::format("{}: cannot start Gmsh (pipe: {})", file, std::strerror(errno)));
  std::cout.flush();  // what the child inherits unwritten would be written twice if Gmsh calls exit
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    throw MeshFileError(fmt::format("{}: cannot start Gmsh (fork: {})", file, std::strerror(errno)));
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(fds[1], memory_limit, work);
  }
  ::close(fds[1]);
  const std::string answer = read_all(fds[0]);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  if (!answer.empty() && answer[0] == kAnswer) return answer.substr(1);
  if (!answer.empty() && answer[0] == kError) throw MeshFileError(answer.substr(1));
  if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM))
    throw MeshFileError(fmt::format("{}: Gmsh was interrupted while {} it", file, what));
  if (WIFSIGNALED(status)) {
    throw MeshFileError(
        fmt::format("{}: Gmsh crashed while {} it (signal {}, {}): the file is damaged or not one Gmsh "
                    "can read; open it in Gmsh to see where",
                    file, what, WTERMSIG(status), strsignal(WTERMSIG(status))));
  }
  throw MeshFileError(
      fmt::format("{}: Gmsh stopped while {} it (exit status {}): the file is damaged or not one Gmsh "
                  "can read; open it in Gmsh to see where",
                  file, what, WIFEXITED(status) ? WEXITSTATUS(status) : -1));
}

const char* ByteReader::take(std::size_t n) {
  if (n > bytes_.size() - pos_) throw std::runtime_error("the answer of the Gmsh process is incomplete");
  const char* p = bytes_.data() + pos_;
  pos_ += n;
  return p;
}

}  // namespace keller
