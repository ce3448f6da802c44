#include "core/GmshSession.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <vector>

#include "core/MeshFileError.hpp"

namespace keller {

namespace {

// A private folder under the system's temporary directory, removed with everything in it.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (std::filesystem::temp_directory_path() / "keller-gmsh-XXXXXX").string();
    if (!mkdtemp(pattern.data())) throw MeshFileError("cannot create a temporary folder under " + pattern);
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace

GmshSession::GmshSession(std::string file) : api_(GmshApi::get(file)), file_(std::move(file)) {
  api_.initialize();
  // (printed to the Gmsh child's log, which says why where a file stops Gmsh itself: Abort)
  api_.set_option("General.Terminal", 1);
  api_.set_option("General.AbortOnError", 0);
  api_.logger_start();
}

GmshSession::~GmshSession() {
  try {
    api_.logger_stop();
    api_.finalize();
  } catch (const std::exception&) {
    // a failed finalize leaves nothing to undo; the next session initialises Gmsh again
  }
}

void GmshSession::run(const std::string& what, const std::function<void()>& step) {
  std::vector<std::string> errors;
  try {
    step();
  } catch (const MeshFileError&) {
    throw;
  } catch (const std::exception& e) {
    errors.emplace_back(e.what());
  } catch (const std::string& e) {
    errors.push_back(e);
  } catch (...) {
    errors.emplace_back("Gmsh stopped with an unknown exception");
  }
  const std::vector<std::string> log = api_.logger_get();
  for (std::size_t i = log_seen_; i < log.size(); ++i) {
    if (log[i].rfind("Error: ", 0) == 0) errors.push_back(log[i].substr(7));
  }
  log_seen_ = log.size();
  if (errors.empty()) return;
  const std::size_t shown = std::min<std::size_t>(errors.size(), 5);
  std::string text;
  for (std::size_t i = 0; i < shown; ++i) text += "\n  " + errors[i];
  if (shown < errors.size()) text += fmt::format("\n  ({} more)", errors.size() - shown);
  throw MeshFileError(fmt::format("{}: Gmsh reported an error while {} it:{}", file_, what, text));
}

void GmshSession::open(const std::map<std::string, double>& numbers) {
  if (numbers.empty()) {
    run("reading", [&] { api_.open(file_); });
    return;
  }
  TemporaryFolder folder;
  const std::string wrapper = (folder.path() / "parameters.geo").string();
  std::string text;
  for (const auto& [name, value] : numbers) text += fmt::format("{} = {:.17g};\n", name, value);
  text += fmt::format("Include \"{}\";\n", std::filesystem::absolute(file_).string());
  std::ofstream out(wrapper);
  out << text;
  out.close();
  if (!out) throw MeshFileError(file_ + ": cannot write the file that sets its parameters, " + wrapper);
  run("reading", [&] { api_.open(wrapper); });
}

std::string GmshSession::msh_bytes() {
  TemporaryFolder folder;
  const std::string path = (folder.path() / "mesh.msh").string();
  run("writing a copy of", [&] {
    api_.set_option("Mesh.MshFileVersion", 4.1);
    api_.set_option("Mesh.Binary", 1);
    api_.set_option("Mesh.SaveAll", 0);
    api_.write(path);
  });
  std::ifstream in(path, std::ios::binary);
  std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (!in.good() && !in.eof()) throw MeshFileError(file_ + ": cannot read back the copy Gmsh wrote of it at " + path);
  return bytes;
}

}  // namespace keller
