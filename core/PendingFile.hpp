// An output written under a temporary name in its own folder (TARGET.part) and renamed over
// TARGET only once complete, so that TARGET is at every moment either what it was before the
// run or the complete new file, whatever interrupts the run.
#pragma once

#include <string>

namespace keller {

class PendingFile {
 public:
  explicit PendingFile(std::string target);
  ~PendingFile();  // removes the temporary file unless it was committed or kept
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  // TARGET + ".part": where the file is written.
  static std::string temporary_for(const std::string& target);
  const std::string& path() const { return path_; }
  const std::string& target() const { return target_; }
  // Flushes the written file to disk and renames it over the target (refusing a target that
  // has become something other than a regular file). Throws std::runtime_error.
  void commit();
  // Leaves the file under its temporary name (the record of a run that did not finish).
  void keep() { done_ = true; }
  bool done() const { return done_; }

 private:
  std::string target_, path_;
  bool done_ = false;
};

// Flushes a closed file's data to disk (fsync); throws std::runtime_error on failure.
void sync_file(const std::string& path);

}  // namespace keller
