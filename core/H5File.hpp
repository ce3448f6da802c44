// A thin RAII wrapper over the HDF5 C API: files, groups, string/number datasets and
// attributes, and appendable 2D datasets for branch tables. HDF5 failures throw
// std::runtime_error naming the file and object (they are I/O problems, not numerics): IoError
// (core/IoError.hpp) where a file cannot be created or written, with the system's reason.
#pragma once

#include <hdf5.h>

#include <string>
#include <vector>

#include "core/HeldFile.hpp"

namespace keller {

class H5File {
 public:
  enum class Mode { Create, Read, ReadWrite };
  // Create makes a new file and refuses a name that exists (never truncating a file, or another
  // file through a link). Read falls back to SWMR read mode for a file whose writer was killed while
  // it was open in single-writer/multiple-reader mode.
  H5File(const std::string& path, Mode mode);
  ~H5File();
  H5File(const H5File&) = delete;
  H5File& operator=(const H5File&) = delete;
  H5File(H5File&& o) noexcept;

  hid_t id() const { return file_; }
  // The open file itself, held (HeldFile): what a run publishes must be the file it wrote.
  HeldFile hold() const;
  const std::string& path() const { return path_; }
  // The file's name after its writer renamed it (for messages).
  void renamed(const std::string& path);
  bool exists(const std::string& object) const;
  // Removes the link to a group or dataset (ReadWrite); throws where there is none.
  void remove(const std::string& object);
  // Creates a group and any missing parents.
  void create_group(const std::string& group);

  void write_string(const std::string& dataset, const std::string& value);
  // Row-major rows x cols doubles (cols = 1 gives a 1D dataset).
  void write_matrix(const std::string& dataset, const double* data, long rows, long cols);
  void write_vector(const std::string& dataset, const std::vector<double>& v) {
    write_matrix(dataset, v.data(), static_cast<long>(v.size()), 1);
  }
  void write_int_matrix(const std::string& dataset, const int* data, long rows, long cols);
  void write_strings(const std::string& dataset, const std::vector<std::string>& values);

  void set_attribute(const std::string& object, const std::string& name, const std::string& value);
  void set_attribute(const std::string& object, const std::string& name, double value);
  void set_attribute(const std::string& object, const std::string& name, long value);

  std::string read_string(const std::string& dataset) const;
  std::vector<std::string> read_strings(const std::string& dataset) const;
  // Returns data row-major with its shape.
  std::vector<double> read_matrix(const std::string& dataset, long* rows, long* cols) const;
  std::string read_string_attribute(const std::string& object, const std::string& name) const;
  double read_double_attribute(const std::string& object, const std::string& name) const;
  bool has_attribute(const std::string& object, const std::string& name) const;
  std::vector<std::string> attribute_names(const std::string& object) const;
  std::vector<std::string> list(const std::string& group) const;

  // Appendable datasets (chunked, unlimited rows): create with a fixed number of columns, then
  // append rows. Only datasets created before start_swmr() can be appended in SWMR mode.
  void create_appendable(const std::string& dataset, long cols, long chunk_rows = 64);
  void append_rows(const std::string& dataset, const double* data, long rows);
  long num_rows(const std::string& dataset) const;
  // Overwrites `rows` rows from `first` on of an existing 2D dataset (allowed in SWMR mode, unlike
  // creating or extending: a ring of states rewritten in place).
  void write_rows(const std::string& dataset, long first, const double* data, long rows);
  // Overwrite a fixed-size string dataset created with create_fixed_string.
  void create_fixed_string(const std::string& dataset, long capacity);
  void write_fixed_string(const std::string& dataset, const std::string& value);
  // Switch to single-writer/multiple-reader mode: from now on the file on disk stays readable at
  // every moment, so a run killed with SIGKILL leaves every flushed row.
  void start_swmr();
  void flush();
  // Closes the file; a file whose write failed is left as it was then (not closed: see IoError).
  void close();

 private:
  // A write failed (IoError): the file is broken off, never closed.
  [[noreturn]] void failed(const std::string& what);
  hid_t file_ = -1;
  std::string path_;
  bool broken_ = false;
};

// Silences HDF5's automatic error stack printing (errors are reported by exceptions), and leaves
// out the library's clean-up at exit (every file is closed by its H5File).
void silence_hdf5_errors();

}  // namespace keller
