// The HDF5 file of a run written row by row (a branch, a time series), in HDF5's
// single-writer/multiple-reader mode: built under its temporary name and renamed once consistent
// on disk, so that the final name never shows a file that is not, and a run killed at any moment
// leaves a readable file holding every flushed row. GROUP/status says "running" until the run ends,
// then why; GROUP/exit_code is -1 until a run whose file takes its name writes its exit code there.
// BranchFile and TimeSeriesFile lay out their datasets in one and write their rows to it.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "core/H5File.hpp"
#include "core/HeldFile.hpp"

namespace keller {

class RunFile {
 public:
  // Creates the file under its temporary name (PendingFile::temporary_for, what an earlier run
  // left there cleared), lets `layout` write the groups and datasets, adds GROUP/status ("running")
  // and GROUP/exit_code (-1), enters SWMR mode, flushes and renames it to `path`, where its
  // temporary name still holds this very file. Where anything fails, the temporary (if still this
  // run's) is removed and the error rethrown (IoError where the file was replaced meanwhile or
  // cannot take its name).
  RunFile(const std::string& path, const std::string& group, const std::function<void(H5File&)>& layout);
  ~RunFile();  // closes the file; never throws (close() reports what fails)
  RunFile(const RunFile&) = delete;
  RunFile& operator=(const RunFile&) = delete;

  // The open file: rows are appended to it (only while is_open()).
  H5File& h5() { return *file_; }
  bool is_open() const { return file_ != nullptr; }
  // The file this run created, held: what it publishes must be this file.
  HeldFile& written() { return written_; }
  // The run has ended for `reason`: what is written is flushed and a watcher told ("ended");
  // finish() stores the reason.
  void ended(const std::string& reason);
  // GROUP/status gets why the run ended (ended()'s reason) and, for a file that takes its name,
  // GROUP/exit_code the code its run ends with, in one flush, and the file is closed.
  void finish(std::optional<int> publication_code);
  void close();

 private:
  std::string group_;
  std::unique_ptr<H5File> file_;
  HeldFile written_;
  std::string reason_ = "running";
};

}  // namespace keller
