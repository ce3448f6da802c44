// A file a run created, held by an open descriptor: the run can tell whether a name still refers
// to it (device and inode compared, no link followed), publish it only where it does, and copy
// its content to a new file when its own name has lost it (removed, or replaced by another file).
#pragma once

#include <sys/types.h>

#include <string>

namespace keller {

class HeldFile {
 public:
  HeldFile() = default;  // holds nothing
  // The regular file at `path` now (a symbolic link is refused); throws IoError naming it.
  static HeldFile open(const std::string& path);
  // The file open at descriptor `fd` (duplicated: the caller keeps its own), written as `path`.
  static HeldFile of_descriptor(int fd, const std::string& path);
  ~HeldFile();
  HeldFile(HeldFile&& o) noexcept;
  HeldFile& operator=(HeldFile&& o) noexcept;
  HeldFile(const HeldFile&) = delete;
  HeldFile& operator=(const HeldFile&) = delete;

  bool held() const { return fd_ >= 0; }
  // Whether `path` names this very file now (false for a link to it, another file, or nothing).
  bool at(const std::string& path) const;
  // Whether the file still has a name somewhere (it may have been moved): false once removed.
  bool linked() const;
  // Copies the whole file to a new file at `path` (created exclusively, flushed to disk) and
  // returns that one held. Throws IoError naming the paths.
  HeldFile copy_to(const std::string& path) const;

 private:
  int fd_ = -1;
  dev_t device_ = 0;
  ino_t inode_ = 0;
};

}  // namespace keller
