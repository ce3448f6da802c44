// Gmsh in a child process. Gmsh 4.8.4 crashes on some damaged files (a .msh element naming a node
// that does not exist ends in a segmentation fault inside its reader) and ends the process on a
// fatal error (exit), so every use of Gmsh runs in a child (fork) and hands its result back
// through a pipe: a crash or an exit ends the child, and keller reports it as a MeshFileError.
// The child writes nothing to keller's output (its standard output and error go to /dev/null) and
// holds none of keller's files (all other descriptors are closed).
#pragma once

#include <cstddef>
#include <cstring>
#include <functional>
#include <string>
#include <type_traits>
#include <vector>

namespace keller {

// Runs `work` in a child process and returns the bytes it returned. A MeshFileError (or other
// exception) thrown by `work` is thrown again here with its message; a child that crashes or exits
// without an answer gives a MeshFileError naming `file` and what happened while `what` it
// (e.g. "reading"). memory_limit (bytes, 0: none) caps the child's data (RLIMIT_DATA), so that a
// damaged count in a file ends in a refusal rather than in all the machine's memory. The child
// takes SIGINT and SIGTERM's default actions: an interrupt stops a Gmsh that loops.
std::string run_gmsh_child(const std::string& file, const std::string& what, std::size_t memory_limit,
                           const std::function<std::string()>& work);

// The bytes a child hands back: plain values, strings and vectors of plain values, appended and
// read back in the same order.
class ByteWriter {
 public:
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    bytes_.append(reinterpret_cast<const char*>(&v), sizeof(T));
  }
  void text(const std::string& s) {
    value(s.size());
    bytes_ += s;
  }
  template <class T>
  void values(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value(v.size());
    bytes_.append(reinterpret_cast<const char*>(v.data()), v.size() * sizeof(T));
  }
  std::string take() { return std::move(bytes_); }

 private:
  std::string bytes_;
};

class ByteReader {
 public:
  explicit ByteReader(const std::string& bytes) : bytes_(bytes) {}
  template <class T>
  T value() {
    T v;
    std::memcpy(&v, take(sizeof(T)), sizeof(T));
    return v;
  }
  std::string text() {
    const auto n = value<std::size_t>();
    return std::string(take(n), n);
  }
  template <class T>
  std::vector<T> values() {
    const auto n = value<std::size_t>();
    std::vector<T> v(n);
    if (n) std::memcpy(v.data(), take(n * sizeof(T)), n * sizeof(T));
    return v;
  }

 private:
  const char* take(std::size_t n);  // throws std::runtime_error past the end
  const std::string& bytes_;
  std::size_t pos_ = 0;
};

}  // namespace keller
