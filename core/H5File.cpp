#include "core/H5File.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <stdexcept>

#include "core/IoError.hpp"

namespace keller {

namespace {

[[noreturn]] void fail(const std::string& file, const std::string& what) {
  throw std::runtime_error(fmt::format("HDF5 file '{}': {}", file, what));
}

// The system's error behind the failure of the last HDF5 call, from its error stack.
struct SystemError {
  std::string text;  // "No space left on device"; empty where there is none
  int number = 0;    // errno
};

herr_t find_system_error(unsigned, const H5E_error2_t* e, void* found) {
  const std::string desc = e->desc ? e->desc : "";
  SystemError& error = *static_cast<SystemError*>(found);
  const std::string text = "error message = '", number = "errno = ";
  if (const auto at = desc.find(text); at != std::string::npos)
    error.text = desc.substr(at + text.size(), desc.find('\'', at + text.size()) - at - text.size());
  if (const auto at = desc.find(number); at != std::string::npos)
    error.number = std::atoi(desc.c_str() + at + number.size());
  return 0;
}

SystemError system_error() {
  SystemError error;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, find_system_error, &error);
  return error;
}

// ": <the system's reason>" for the failure of the last HDF5 call, or "".
std::string system_reason() {
  const std::string text = system_error().text;
  return text.empty() ? "" : ": " + text;
}

// A file that cannot be created or written (a full disk, a file-size limit): IoError.
[[noreturn]] void fail_write(const std::string& file, const std::string& what) {
  throw IoError(fmt::format("HDF5 file '{}': {}{}", file, what, system_reason()));
}

struct Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  Handle(hid_t i, herr_t (*c)(hid_t)) : id(i), close(c) {}
  ~Handle() {
    if (id >= 0) close(id);
  }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  operator hid_t() const { return id; }
};

hid_t vlen_string_type() {
  hid_t t = H5Tcopy(H5T_C_S1);
  H5Tset_size(t, H5T_VARIABLE);
  H5Tset_cset(t, H5T_CSET_UTF8);
  return t;
}

}  // namespace

void silence_hdf5_errors() {
  // a file whose close failed (a full disk, a file-size limit) stays half closed in the library,
  // whose own clean-up at exit then crashes on it; every file is closed by its H5File, so that
  // clean-up is left out (this must come before the library's first call)
  static const bool no_clean_up_at_exit = H5dont_atexit() >= 0;
  (void)no_clean_up_at_exit;
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
}

void H5File::renamed(const std::string& path) { path_ = path; }

H5File::H5File(const std::string& path, Mode mode) : path_(path) {
  silence_hdf5_errors();
  if (mode == Mode::Create) {
    Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
    // the latest format is required for SWMR and gives the most robust metadata layout
    H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
    // a new file only: never truncated through a name that exists (a link to another file)
    std::error_code ec;
    const bool existed = std::filesystem::symlink_status(path, ec).type() != std::filesystem::file_type::not_found;
    file_ = H5Fcreate(path.c_str(), H5F_ACC_EXCL, H5P_DEFAULT, fapl);
    if (file_ < 0) {
      const SystemError error = system_error();
      // HDF5 refuses a file it holds open without an errno: whatever was at the name stays
      if (existed || error.number == EEXIST) fail_write(path, "cannot create: the name exists");
      // created (exclusively: this call's own, the name being free before it), then its first
      // writes failed: nothing of it stays
      if (std::filesystem::is_regular_file(std::filesystem::symlink_status(path, ec)))
        std::filesystem::remove(path, ec);
      throw IoError(fmt::format("HDF5 file '{}': cannot create{}", path,
                                error.text.empty() ? " (check the folder exists and is writable)" : ": " + error.text));
    }
  } else {
    const unsigned flags = mode == Mode::Read ? H5F_ACC_RDONLY : H5F_ACC_RDWR;
    file_ = H5Fopen(path.c_str(), flags, H5P_DEFAULT);
    if (file_ < 0 && mode == Mode::Read) {
      Handle fapl(H5Pcreate(H5P_FILE_ACCESS), H5Pclose);
      H5Pset_libver_bounds(fapl, H5F_LIBVER_LATEST, H5F_LIBVER_LATEST);
      file_ = H5Fopen(path.c_str(), H5F_ACC_RDONLY | H5F_ACC_SWMR_READ, fapl);
    }
    if (file_ < 0) fail(path, "cannot open (missing, not HDF5, or damaged)");
  }
}

H5File::~H5File() {
  try {
    close();
  } catch (const std::exception&) {  // a destructor must not throw; close() reports it when called directly
  }
}

H5File::H5File(H5File&& o) noexcept : file_(o.file_), path_(std::move(o.path_)), broken_(o.broken_) { o.file_ = -1; }

void H5File::failed(const std::string& what) {
  broken_ = true;
  fail_write(path_, what);
}

void H5File::close() {
  if (file_ < 0) return;
  if (broken_) {
    // left as it was when the write failed: closing would write the superblock of a file that the
    // failed write may have left shorter than it says, which no reader then opens; unclosed, an
    // SWMR file still opens with what was flushed before the failure
    file_ = -1;
    return;
  }
  // every dataset, group, attribute and type this class opens is closed again at once; an open
  // object here would keep the file (and, in SWMR mode, its "open for writing" flag) alive
  const ssize_t open_objects = H5Fget_obj_count(file_, H5F_OBJ_ALL | H5F_OBJ_LOCAL);
  const herr_t status = H5Fclose(file_);
  const std::string reason = status < 0 ? system_reason() : "";
  file_ = -1;
  if (open_objects > 1 || status < 0)
    throw IoError(fmt::format("HDF5 file '{}': not closed cleanly ({} open objects, status {}){}", path_, open_objects,
                              status, reason));
}

void H5File::flush() {
  if (H5Fflush(file_, H5F_SCOPE_GLOBAL) < 0) failed("flush failed");
}

HeldFile H5File::hold() const {
  void* handle = nullptr;
  if (H5Fget_vfd_handle(file_, H5P_DEFAULT, &handle) < 0 || !handle) fail(path_, "no file descriptor to hold");
  return HeldFile::of_descriptor(*static_cast<int*>(handle), path_);
}

void H5File::start_swmr() {
  if (H5Fstart_swmr_write(file_) < 0) failed("cannot start SWMR write mode");
}

bool H5File::exists(const std::string& object) const {
  if (object == "/") return true;
  // check each prefix so that a missing parent is not an error
  size_t pos = 0;
  while ((pos = object.find('/', pos + 1)) != std::string::npos) {
    const std::string prefix = object.substr(0, pos);
    if (H5Lexists(file_, prefix.c_str(), H5P_DEFAULT) <= 0) return false;
  }
  return H5Lexists(file_, object.c_str(), H5P_DEFAULT) > 0;
}

void H5File::create_group(const std::string& group) {
  if (exists(group)) return;
  Handle lcpl(H5Pcreate(H5P_LINK_CREATE), H5Pclose);
  H5Pset_create_intermediate_group(lcpl, 1);
  Handle g(H5Gcreate2(file_, group.c_str(), lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Gclose);
  if (g < 0) failed("cannot create group " + group);
}

namespace {
hid_t link_create_plist() {
  hid_t lcpl = H5Pcreate(H5P_LINK_CREATE);
  H5Pset_create_intermediate_group(lcpl, 1);
  return lcpl;
}
}  // namespace

void H5File::remove(const std::string& object) {
  if (H5Ldelete(file_, object.c_str(), H5P_DEFAULT) < 0) failed("cannot remove " + object);
}

void H5File::write_string(const std::string& dataset, const std::string& value) {
  Handle type(vlen_string_type(), H5Tclose);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle lcpl(link_create_plist(), H5Pclose);
  Handle ds(H5Dcreate2(file_, dataset.c_str(), type, space, lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (ds < 0) failed("cannot create dataset " + dataset);
  const char* p = value.c_str();
  if (H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0) failed("cannot write " + dataset);
}

void H5File::write_strings(const std::string& dataset, const std::vector<std::string>& values) {
  Handle type(vlen_string_type(), H5Tclose);
  const hsize_t dims[1] = {values.size()};
  Handle space(H5Screate_simple(1, dims, nullptr), H5Sclose);
  Handle lcpl(link_create_plist(), H5Pclose);
  Handle ds(H5Dcreate2(file_, dataset.c_str(), type, space, lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (ds < 0) failed("cannot create dataset " + dataset);
  std::vector<const char*> ptrs;
  for (const auto& s : values) ptrs.push_back(s.c_str());
  if (!values.empty() && H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()) < 0)
    failed("cannot write " + dataset);
}

void H5File::write_matrix(const std::string& dataset, const double* data, long rows, long cols) {
  const hsize_t dims[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(cols)};
  Handle space(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), H5Sclose);
  Handle lcpl(link_create_plist(), H5Pclose);
  Handle ds(H5Dcreate2(file_, dataset.c_str(), H5T_IEEE_F64LE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (ds < 0) failed("cannot create dataset " + dataset);
  if (rows * cols > 0 && H5Dwrite(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    failed("cannot write " + dataset);
}

void H5File::write_int_matrix(const std::string& dataset, const int* data, long rows, long cols) {
  const hsize_t dims[2] = {static_cast<hsize_t>(rows), static_cast<hsize_t>(cols)};
  Handle space(H5Screate_simple(cols == 1 ? 1 : 2, dims, nullptr), H5Sclose);
  Handle lcpl(link_create_plist(), H5Pclose);
  Handle ds(H5Dcreate2(file_, dataset.c_str(), H5T_STD_I32LE, space, lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (ds < 0) failed("cannot create dataset " + dataset);
  if (rows * cols > 0 && H5Dwrite(ds, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0)
    failed("cannot write " + dataset);
}

namespace {
template <class Writer>
bool with_attribute(hid_t file, const std::string& path, const std::string& object, const std::string& name, hid_t type,
                    Writer&& write) {
  Handle obj(H5Oopen(file, object.c_str(), H5P_DEFAULT), H5Oclose);
  if (obj < 0) fail(path, "no object " + object + " for attribute " + name);
  if (H5Aexists(obj, name.c_str()) > 0) H5Adelete(obj, name.c_str());
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle attr(H5Acreate2(obj, name.c_str(), type, space, H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  return attr >= 0 && write(attr) >= 0;
}
}  // namespace

void H5File::set_attribute(const std::string& object, const std::string& name, const std::string& value) {
  Handle type(vlen_string_type(), H5Tclose);
  const char* p = value.c_str();
  if (!with_attribute(file_, path_, object, name, type, [&](hid_t a) { return H5Awrite(a, type, &p); }))
    failed("cannot write attribute " + object + "@" + name);
}

void H5File::set_attribute(const std::string& object, const std::string& name, double value) {
  if (!with_attribute(file_, path_, object, name, H5T_IEEE_F64LE,
                      [&](hid_t a) { return H5Awrite(a, H5T_NATIVE_DOUBLE, &value); }))
    failed("cannot write attribute " + object + "@" + name);
}

void H5File::set_attribute(const std::string& object, const std::string& name, long value) {
  if (!with_attribute(file_, path_, object, name, H5T_STD_I64LE,
                      [&](hid_t a) { return H5Awrite(a, H5T_NATIVE_LONG, &value); }))
    failed("cannot write attribute " + object + "@" + name);
}

std::string H5File::read_string(const std::string& dataset) const {
  Handle ds(H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(path_, "no dataset " + dataset);
  Handle ftype(H5Dget_type(ds), H5Tclose);
  if (H5Tis_variable_str(ftype) > 0) {
    Handle type(vlen_string_type(), H5Tclose);
    char* p = nullptr;
    if (H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, &p) < 0) fail(path_, "cannot read " + dataset);
    std::string s = p ? p : "";
    Handle space(H5Dget_space(ds), H5Sclose);
    H5Dvlen_reclaim(type, space, H5P_DEFAULT, &p);
    return s;
  }
  const size_t n = H5Tget_size(ftype);
  std::string s(n, '\0');
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, n);
  if (H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, s.data()) < 0) fail(path_, "cannot read " + dataset);
  return std::string(s.c_str());
}

std::vector<std::string> H5File::read_strings(const std::string& dataset) const {
  Handle ds(H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(path_, "no dataset " + dataset);
  Handle space(H5Dget_space(ds), H5Sclose);
  const hssize_t n = H5Sget_simple_extent_npoints(space);
  std::vector<char*> ptrs(static_cast<size_t>(n), nullptr);
  Handle type(vlen_string_type(), H5Tclose);
  if (n > 0 && H5Dread(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, ptrs.data()) < 0) fail(path_, "cannot read " + dataset);
  std::vector<std::string> out;
  for (char* p : ptrs) out.emplace_back(p ? p : "");
  if (n > 0) H5Dvlen_reclaim(type, space, H5P_DEFAULT, ptrs.data());
  return out;
}

std::vector<double> H5File::read_matrix(const std::string& dataset, long* rows, long* cols) const {
  Handle ds(H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(path_, "no dataset " + dataset);
  H5Drefresh(ds);
  Handle space(H5Dget_space(ds), H5Sclose);
  hsize_t dims[2] = {0, 1};
  const int rank = H5Sget_simple_extent_ndims(space);
  if (rank < 1 || rank > 2) fail(path_, dataset + " is not a 1D or 2D dataset");
  H5Sget_simple_extent_dims(space, dims, nullptr);
  if (rank == 1) dims[1] = 1;
  std::vector<double> out(dims[0] * dims[1]);
  if (!out.empty() && H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0)
    fail(path_, "cannot read " + dataset);
  if (rows) *rows = static_cast<long>(dims[0]);
  if (cols) *cols = static_cast<long>(dims[1]);
  return out;
}

bool H5File::has_attribute(const std::string& object, const std::string& name) const {
  return H5Aexists_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT) > 0;
}

namespace {
herr_t collect_attribute_name(hid_t, const char* name, const H5A_info_t*, void* out) {
  static_cast<std::vector<std::string>*>(out)->emplace_back(name);
  return 0;
}
}  // namespace

std::vector<std::string> H5File::attribute_names(const std::string& object) const {
  std::vector<std::string> out;
  if (H5Aiterate_by_name(file_, object.c_str(), H5_INDEX_NAME, H5_ITER_INC, nullptr, collect_attribute_name, &out,
                         H5P_DEFAULT) < 0)
    fail(path_, "cannot list the attributes of " + object);
  return out;
}

std::string H5File::read_string_attribute(const std::string& object, const std::string& name) const {
  Handle attr(H5Aopen_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (attr < 0) fail(path_, "no attribute " + object + "@" + name);
  Handle type(vlen_string_type(), H5Tclose);
  char* p = nullptr;
  if (H5Aread(attr, type, &p) < 0) fail(path_, "cannot read attribute " + object + "@" + name);
  std::string s = p ? p : "";
  H5free_memory(p);
  return s;
}

double H5File::read_double_attribute(const std::string& object, const std::string& name) const {
  Handle attr(H5Aopen_by_name(file_, object.c_str(), name.c_str(), H5P_DEFAULT, H5P_DEFAULT), H5Aclose);
  if (attr < 0) fail(path_, "no attribute " + object + "@" + name);
  double v = 0;
  if (H5Aread(attr, H5T_NATIVE_DOUBLE, &v) < 0) fail(path_, "cannot read attribute " + object + "@" + name);
  return v;
}

std::vector<std::string> H5File::list(const std::string& group) const {
  std::vector<std::string> out;
  Handle g(H5Gopen2(file_, group.c_str(), H5P_DEFAULT), H5Gclose);
  if (g < 0) fail(path_, "no group " + group);
  H5G_info_t info;
  H5Gget_info(g, &info);
  for (hsize_t i = 0; i < info.nlinks; ++i) {
    const ssize_t len = H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, nullptr, 0, H5P_DEFAULT);
    std::string name(static_cast<size_t>(len), '\0');
    H5Lget_name_by_idx(g, ".", H5_INDEX_NAME, H5_ITER_INC, i, name.data(), static_cast<size_t>(len) + 1, H5P_DEFAULT);
    out.push_back(name);
  }
  return out;
}

void H5File::create_appendable(const std::string& dataset, long cols, long chunk_rows) {
  const hsize_t dims[2] = {0, static_cast<hsize_t>(cols)};
  const hsize_t maxdims[2] = {H5S_UNLIMITED, static_cast<hsize_t>(cols)};
  const hsize_t chunk[2] = {static_cast<hsize_t>(chunk_rows), static_cast<hsize_t>(cols)};
  Handle space(H5Screate_simple(2, dims, maxdims), H5Sclose);
  Handle dcpl(H5Pcreate(H5P_DATASET_CREATE), H5Pclose);
  H5Pset_chunk(dcpl, 2, chunk);
  Handle lcpl(link_create_plist(), H5Pclose);
  Handle ds(H5Dcreate2(file_, dataset.c_str(), H5T_IEEE_F64LE, space, lcpl, dcpl, H5P_DEFAULT), H5Dclose);
  if (ds < 0) failed("cannot create dataset " + dataset);
}

long H5File::num_rows(const std::string& dataset) const {
  Handle ds(H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(path_, "no dataset " + dataset);
  H5Drefresh(ds);
  Handle space(H5Dget_space(ds), H5Sclose);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  return static_cast<long>(dims[0]);
}

void H5File::append_rows(const std::string& dataset, const double* data, long rows) {
  Handle ds(H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(path_, "no dataset " + dataset);
  Handle space(H5Dget_space(ds), H5Sclose);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(space, dims, nullptr);
  const hsize_t newdims[2] = {dims[0] + static_cast<hsize_t>(rows), dims[1]};
  if (H5Dset_extent(ds, newdims) < 0) failed("cannot extend " + dataset);
  Handle fspace(H5Dget_space(ds), H5Sclose);
  const hsize_t start[2] = {dims[0], 0};
  const hsize_t count[2] = {static_cast<hsize_t>(rows), dims[1]};
  H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, nullptr, count, nullptr);
  Handle mspace(H5Screate_simple(2, count, nullptr), H5Sclose);
  if (H5Dwrite(ds, H5T_NATIVE_DOUBLE, mspace, fspace, H5P_DEFAULT, data) < 0) failed("cannot append to " + dataset);
  if (H5Dflush(ds) < 0) failed("cannot flush " + dataset);
}

void H5File::write_rows(const std::string& dataset, long first, const double* data, long rows) {
  Handle ds(H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(path_, "no dataset " + dataset);
  Handle fspace(H5Dget_space(ds), H5Sclose);
  hsize_t dims[2] = {0, 0};
  H5Sget_simple_extent_dims(fspace, dims, nullptr);
  if (first < 0 || static_cast<hsize_t>(first + rows) > dims[0])
    fail(path_, fmt::format("rows {} to {} are outside {} ({} rows)", first, first + rows - 1, dataset, dims[0]));
  const hsize_t start[2] = {static_cast<hsize_t>(first), 0};
  const hsize_t count[2] = {static_cast<hsize_t>(rows), dims[1]};
  H5Sselect_hyperslab(fspace, H5S_SELECT_SET, start, nullptr, count, nullptr);
  Handle mspace(H5Screate_simple(2, count, nullptr), H5Sclose);
  if (H5Dwrite(ds, H5T_NATIVE_DOUBLE, mspace, fspace, H5P_DEFAULT, data) < 0) failed("cannot write " + dataset);
  if (H5Dflush(ds) < 0) failed("cannot flush " + dataset);
}

void H5File::create_fixed_string(const std::string& dataset, long capacity) {
  Handle type(H5Tcopy(H5T_C_S1), H5Tclose);
  H5Tset_size(type, static_cast<size_t>(capacity));
  H5Tset_strpad(type, H5T_STR_NULLTERM);
  Handle space(H5Screate(H5S_SCALAR), H5Sclose);
  Handle lcpl(link_create_plist(), H5Pclose);
  Handle ds(H5Dcreate2(file_, dataset.c_str(), type, space, lcpl, H5P_DEFAULT, H5P_DEFAULT), H5Dclose);
  if (ds < 0) failed("cannot create dataset " + dataset);
  std::string blank(static_cast<size_t>(capacity), '\0');
  if (H5Dwrite(ds, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, blank.data()) < 0) failed("cannot write " + dataset);
}

void H5File::write_fixed_string(const std::string& dataset, const std::string& value) {
  Handle ds(H5Dopen2(file_, dataset.c_str(), H5P_DEFAULT), H5Dclose);
  if (ds < 0) fail(path_, "no dataset " + dataset);
  Handle ftype(H5Dget_type(ds), H5Tclose);
  const size_t cap = H5Tget_size(ftype);
  std::string buf(cap, '\0');
  std::copy_n(value.begin(), std::min(value.size(), cap - 1), buf.begin());
  if (H5Dwrite(ds, ftype, H5S_ALL, H5S_ALL, H5P_DEFAULT, buf.data()) < 0) failed("cannot write " + dataset);
  if (H5Dflush(ds) < 0) failed("cannot flush " + dataset);
}

}  // namespace keller
