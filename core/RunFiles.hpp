// The files one run reads and writes, checked together before any work: no output may be the
// same file as an input or as another output of the run (compared by file identity: device and
// inode where the file exists, so `./`, `..`, symbolic and hard links are seen through; the
// canonical path where it does not), and every output target must be a regular file or absent,
// in a folder that exists and is writable. Temporary names (TARGET.part) count as outputs, and
// keller creates them itself: a hard link there is refused as well.
#pragma once

#include <string>
#include <vector>

namespace keller {

// Whether two paths name the same file: equal device and inode when both exist, equal
// canonical paths (links resolved as far as the path exists) otherwise.
bool same_file(const std::string& a, const std::string& b);

class RunFiles {
 public:
  // `role` names the file in messages: "scene file", "--restart", "branch file", "--csv".
  void input(std::string role, std::string path);
  void output(std::string role, std::string path);
  // A temporary name the run creates (exclusively): an output that must not be a hard link either.
  void temporary(std::string role, std::string path);
  // Throws std::invalid_argument naming the role, the path and the problem: an output that is
  // an input or another output, an output that is a directory, a symbolic link, a FIFO, a
  // device or a socket (a temporary: or a hard link), or whose folder is missing or not writable.
  void check() const;

 private:
  struct Entry {
    std::string role, path;
    bool temporary = false;
  };
  std::vector<Entry> inputs_, outputs_;
};

}  // namespace keller
