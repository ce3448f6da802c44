// One use of the Gmsh library (a global object): initialised on construction, finalised on
// destruction, under a process-wide lock. Gmsh's terminal output is off
// (General.Terminal = 0) and its messages go to its logger; errors are reported as a MeshFileError
// naming the file. Errors are logged, not thrown (General.AbortOnError = 0): Gmsh 4.8.4 throws out
// of its .geo parser mid-parse, which leaves the parser's state broken for every later file.
// Numbers for a .geo are not given as `-setnumber` (Gmsh 4.8.4 keeps those for every later file of
// the process, even after finalize) but as assignments in a wrapper that includes the .geo.
#pragma once

#include <functional>
#include <map>
#include <mutex>
#include <string>

#include "core/GmshApi.hpp"

namespace keller {

class GmshSession {
 public:
  // file: the file the session is about (named in every error).
  explicit GmshSession(std::string file);
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;

  // Runs one step of Gmsh work (`what`, e.g. "reading"); throws MeshFileError with Gmsh's own
  // error messages and the file name if Gmsh reported an error or a call failed. A MeshFileError
  // the step throws passes unchanged.
  void run(const std::string& what, const std::function<void()>& step);
  // Opens the file (a .msh, or a .geo with `numbers` assigned before it is parsed, which its
  // DefineConstant[...] then keeps).
  void open(const std::map<std::string, double>& numbers = {});
  // The model's mesh as the bytes of a binary .msh 4.1 file (elements of physical groups only).
  std::string msh_bytes();
  const std::string& file() const { return file_; }
  GmshApi& api() const { return api_; }

 private:
  GmshApi& api_;
  std::unique_lock<std::mutex> lock_;
  std::string file_;
  std::size_t log_seen_ = 0;
};

}  // namespace keller
