#include "core/GmshProcess.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

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

// What Gmsh printed before the child ended without an answer: its last few error lines, or "".
std::string gmsh_errors(int log_fd) {
  if (log_fd < 0 || ::lseek(log_fd, 0, SEEK_SET) != 0) return "";
  const std::string log = read_all(log_fd);
  std::vector<std::string> errors;
  std::size_t start = 0;
  while (start < log.size()) {
    std::size_t end = log.find('\n', start);
    if (end == std::string::npos) end = log.size();
    const std::string line = log.substr(start, end - start);
    if (line.rfind("Error", 0) == 0) {
      const std::size_t colon = line.find(':');
      errors.push_back(colon == std::string::npos ? line : line.substr(line.find_first_not_of(' ', colon + 1)));
    }
    start = end + 1;
  }
  constexpr std::size_t kShown = 5;
  std::string text;
  for (std::size_t i = errors.size() > kShown ? errors.size() - kShown : 0; i < errors.size(); ++i)
    text += "\n  " + errors[i];
  return text;
}

// In the child: no output to keller's terminal (Gmsh's goes to the log file), none of keller's
// files, then the work.
[[noreturn]] void child(int answer_fd, int log_fd, std::size_t memory_limit, const std::function<std::string()>& work) {
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
  if (memory_limit > 0) {  // on top of what the child has from keller already
    const rlimit limit{data_in_use() + memory_limit, data_in_use() + memory_limit};
    ::setrlimit(RLIMIT_DATA, &limit);
  }
  if (answer_fd != 3) ::dup2(answer_fd, 3);
  const int out = log_fd >= 0 ? log_fd : ::open("/dev/null", O_RDWR);
  if (out >= 0) {
    ::dup2(out, STDOUT_FILENO);
    ::dup2(out, STDERR_FILENO);
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
  // what Gmsh prints, for the message where it stops without an answer (an unlinked file: nothing
  // is left behind, and no pipe fills up while the answer is read)
  // (in the system's temporary folder: TMPDIR where set)
  std::error_code ec;
  std::string log_name = (std::filesystem::temp_directory_path(ec) / "keller-gmsh-XXXXXX").string();
  const int log_fd = ec ? -1 : ::mkstemp(log_name.data());
  if (log_fd >= 0) ::unlink(log_name.c_str());
  std::cout.flush();  // what the child inherits unwritten would be written twice if Gmsh calls exit
  std::cerr.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    if (log_fd >= 0) ::close(log_fd);
    throw MeshFileError(fmt::format("{}: cannot start Gmsh (fork: {})", file, std::strerror(errno)));
  }
  if (pid == 0) {
    ::close(fds[0]);
    child(fds[1], log_fd, memory_limit, work);
  }
  ::close(fds[1]);
  const std::string answer = read_all(fds[0]);
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
  }
  const std::string said = answer.empty() || (answer[0] != kAnswer && answer[0] != kError) ? gmsh_errors(log_fd) : "";
  if (log_fd >= 0) ::close(log_fd);
  if (!answer.empty() && answer[0] == kAnswer) return answer.substr(1);
  if (!answer.empty() && answer[0] == kError) throw MeshFileError(answer.substr(1));
  if (WIFSIGNALED(status) && (WTERMSIG(status) == SIGINT || WTERMSIG(status) == SIGTERM))
    throw MeshFileError(fmt::format("{}: Gmsh was interrupted while {} it", file, what));
  // (a .geo that stops itself, Error(...) then Abort, says why in Gmsh's own error lines)
  if (!said.empty()) throw MeshFileError(fmt::format("{}: Gmsh stopped while {} it, with errors:{}", file, what, said));
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
