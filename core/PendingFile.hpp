// An output written under a temporary name in its own folder (TARGET.part) and renamed over
// TARGET only once complete, so that TARGET is at every moment either what it was before the
// run or the complete new file, whatever interrupts the run. The temporary is created by this
// run (exclusively: never through a name that exists) and only that file is renamed.
#pragma once

#include <string>
#include <string_view>

#include "core/HeldFile.hpp"

namespace keller {

class PendingFile {
 public:
  // Clears what an earlier run left at the temporary name (clear_leftover).
  explicit PendingFile(std::string target);
  ~PendingFile();  // removes the temporary file unless it was committed or kept (or is not this run's)
  PendingFile(const PendingFile&) = delete;
  PendingFile& operator=(const PendingFile&) = delete;

  // TARGET + ".part": where the file is written.
  static std::string temporary_for(const std::string& target);
  const std::string& path() const { return path_; }
  const std::string& target() const { return target_; }
  // Creates the temporary file (exclusively) holding `text`. Throws IoError naming it.
  void write(std::string_view text);
  // The temporary file as its writer created it (e.g. H5File::hold()): commit() renames that file.
  void created(HeldFile file) { file_ = std::move(file); }
  // Flushes the written file to disk and renames it over the target (refusing a target that
  // has become something other than a regular file, and a temporary name that no longer holds the
  // file this run wrote). Throws IoError.
  void commit();
  // Leaves the file under its temporary name (the record of a run that did not finish).
  void keep() { done_ = true; }
  bool done() const { return done_; }

 private:
  std::string target_, path_;
  HeldFile file_;
  bool done_ = false;
};

// Flushes a closed file's data to disk (fsync); throws IoError on failure.
void sync_file(const std::string& path);

// What an earlier run may have left at a temporary name, before this run creates it: a regular
// file with no other name is removed; anything else there (a symbolic or hard link, a directory, a
// FIFO) is refused with IoError naming it, so that no temporary is ever written through a link.
void clear_leftover(const std::string& temporary);
// Creates a new regular file for writing, exclusively (O_CREAT | O_EXCL: refused where the name
// exists, links not followed); returns its descriptor. Throws IoError naming it and the error.
int create_new_file(const std::string& path);
// Writes all of `data` to descriptor `fd` of the file `path`; throws IoError (a full disk, a
// file-size limit) naming the file and the error.
void write_all(int fd, std::string_view data, const std::string& path);

}  // namespace keller
