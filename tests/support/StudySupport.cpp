#include "support/StudySupport.hpp"

#include <fstream>
#include <set>
#include <sstream>
#include <vector>

#include "support/TestSupport.hpp"

namespace keller::test {

std::string bratu_study(const std::string& dir, const std::string& ends) {
  const std::string path = dir + "/bratu.toml";
  std::ofstream(path) << "[study]\nscene = \"" << source_path("runs/scenes/bratu1d_fold.toml")
                      << "\"\n\n[set]\n\"output.xdmf\" = false\n\"continuation.renewal_cost\" = "
                         "25.0\n\n[grid]\n\"bratu.intervals\" = [16, 24, 32, 48]\n"
                      << "\"continuation.stop_above\" = [" << ends << "]\n\n[collect]\nevents = [\"fold\", \"u_mid\"]\n"
                      << "stops = [\"u_mid\"]\nend = [\"u_mid\"]\n";
  return path;
}

std::string table_without_time(const std::string& csv) {
  const std::set<std::string> timed_columns = {"seconds", "process_seconds", "peak_mb", "factor_seconds",
                                               "solve_seconds"};
  std::ifstream in(csv);
  std::string line, out;
  std::set<size_t> timed;
  bool header = true;
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (header)
      for (size_t i = 0; i < cells.size(); ++i)
        if (timed_columns.count(cells[i])) timed.insert(i);
    header = false;
    for (size_t i = 0; i < cells.size(); ++i)
      if (!timed.count(i)) out += cells[i] + ",";
    out += "\n";
  }
  return out;
}

int count(const std::string& text, const std::string& what) {
  int n = 0;
  for (size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

}  // namespace keller::test
