#include "core/GeoConstants.hpp"

#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>

#include "core/MeshFileError.hpp"

namespace keller {

namespace {

constexpr int kMaxIncludeDepth = 16;

bool is_name_start(char c) { return std::isalpha(static_cast<unsigned char>(c)) || c == '_'; }
bool is_name_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// The whole file (comments and strings are skipped by the Scanner).
std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw MeshFileError(path + ": cannot be read (no such file, or no permission)");
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

class Scanner {
 public:
  explicit Scanner(std::string text) : text_(std::move(text)) {}
  bool done() {
    skip_space();
    return pos_ >= text_.size();
  }
  char peek() {
    skip_space();
    return pos_ < text_.size() ? text_[pos_] : '\0';
  }
  // The next token: a name, a string (with its quotes), or one character.
  std::string next() {
    skip_space();
    if (pos_ >= text_.size()) return "";
    const std::size_t start = pos_;
    if (is_name_start(text_[pos_])) {
      while (pos_ < text_.size() && is_name_char(text_[pos_])) ++pos_;
    } else if (text_[pos_] == '"') {
      ++pos_;
      while (pos_ < text_.size() && text_[pos_] != '"') pos_ += text_[pos_] == '\\' ? 2 : 1;
      pos_ = std::min(pos_ + 1, text_.size());
    } else {
      ++pos_;
    }
    return text_.substr(start, pos_ - start);
  }

 private:
  void skip_space() {
    while (pos_ < text_.size()) {
      if (std::isspace(static_cast<unsigned char>(text_[pos_]))) {
        ++pos_;
      } else if (text_.compare(pos_, 2, "//") == 0) {
        pos_ = text_.find('\n', pos_);
        if (pos_ == std::string::npos) pos_ = text_.size();
      } else if (text_.compare(pos_, 2, "/*") == 0) {
        pos_ = text_.find("*/", pos_ + 2);
        pos_ = pos_ == std::string::npos ? text_.size() : pos_ + 2;
      } else {
        return;
      }
    }
  }
  std::string text_;
  std::size_t pos_ = 0;
};

// Reads DefineConstant's list after its '[': names before '=' at depth 0, up to the closing ']'.
void read_define_constant(Scanner& scan, std::set<std::string>& names) {
  int depth = 0;
  bool expect_name = true;
  while (!scan.done()) {
    const std::string token = scan.next();
    if (token == "[" || token == "{" || token == "(") ++depth;
    if (token == "}" || token == ")") --depth;
    if (token == "]") {
      if (depth == 0) return;
      --depth;
    }
    if (depth == 0 && token == ",") {
      expect_name = true;
      continue;
    }
    if (depth == 0 && expect_name && is_name_start(token[0]) && scan.peek() == '=') names.insert(token);
    expect_name = false;
  }
}

void scan_file(const std::string& path, int depth, std::set<std::string>& names) {
  Scanner scan(read_text(path));
  while (!scan.done()) {
    const std::string token = scan.next();
    if (token == "DefineConstant" && scan.peek() == '[') {
      scan.next();
      read_define_constant(scan, names);
    } else if (token == "Include" && scan.peek() == '"' && depth < kMaxIncludeDepth) {
      const std::string quoted = scan.next();
      const std::string name = quoted.substr(1, quoted.size() - 2);
      const std::filesystem::path included = std::filesystem::path(path).parent_path() / name;
      scan_file(std::filesystem::path(name).is_absolute() ? name : included.string(), depth + 1, names);
    }
  }
}

}  // namespace

std::set<std::string> declared_geo_constants(const std::string& path) {
  std::set<std::string> names;
  scan_file(path, 0, names);
  return names;
}

}  // namespace keller
