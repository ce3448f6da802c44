// One use of the Gmsh library (a global object) in the child process that runs it
// (core/GmshProcess.hpp): initialised on construction, finalised on destruction. Gmsh's terminal
// output is off (General.Terminal = 0) and its messages go to its logger; an error is reported as a
// MeshFileError naming the file, with Gmsh's messages. Errors are logged and the call returns
// (General.AbortOnError = 0), so that every message is collected: otherwise Gmsh 4.8.4 throws out
// of its parser mid-parse, which breaks the parser for every later file of the process. Numbers
// for a .geo are assignments in a wrapper that includes the .geo, not `-setnumber`, which Gmsh
// 4.8.4 keeps for every later file of the process, even after finalize.
#pragma once

#include <functional>
#include <map>
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
  std::string file_;
  std::size_t log_seen_ = 0;
};

}  // namespace keller
