// One writer per output: a run holds a lock on a file beside what it writes (OUT.h5.lock beside
// OUT.h5, STUDY/study.lock in a study's folder) from its start to its end, and a second run on the
// same output is refused at its start, naming the process that holds it. The lock is flock(2) on
// the lock file, which the kernel releases when its process ends however it ends (a killed run
// leaves at most an unlocked file, which the next run takes); the lock file holds the pid of its
// holder and is removed when the lock is released.
#pragma once

#include <stdexcept>
#include <string>

namespace keller {

// Another process holds the lock: the message names it.
class OutputLocked : public std::runtime_error {
 public:
  explicit OutputLocked(const std::string& message) : std::runtime_error(message) {}
};

class OutputLock {
 public:
  OutputLock() = default;  // holds nothing
  // Takes the lock at `lock_path` for the output `what` names in messages ("'c.h5'", "the study
  // folder 'runs/x'"). Throws OutputLocked where another process holds it, IoError where the lock
  // file cannot be made (a symbolic link, a hard link or a directory there, a read-only folder).
  explicit OutputLock(const std::string& lock_path, const std::string& what);
  ~OutputLock();  // removes the lock file and releases the lock
  OutputLock(OutputLock&& o) noexcept;
  OutputLock& operator=(OutputLock&& o) noexcept;
  OutputLock(const OutputLock&) = delete;
  OutputLock& operator=(const OutputLock&) = delete;

  // OUT + ".lock".
  static std::string path_for(const std::string& output);
  const std::string& path() const { return path_; }

 private:
  void release();
  std::string path_;
  int fd_ = -1;
};

}  // namespace keller
