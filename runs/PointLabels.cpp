#include "runs/PointLabels.hpp"

#include <fmt/format.h>

#include <map>
#include <optional>
#include <stdexcept>

namespace keller {

namespace {

constexpr PointKind kLocated[] = {PointKind::Start, PointKind::Requested,      PointKind::Event,
                                  PointKind::Fold,  PointKind::BranchPoint,    PointKind::End,
                                  PointKind::Hopf,  PointKind::PeriodDoubling, PointKind::NeimarkSacker};

struct Parsed {
  PointKind kind;
  int k;
};

std::optional<Parsed> parse_label(const std::string& text) {
  for (PointKind kind : kLocated) {
    const std::string name = to_string(kind);
    if (text.rfind(name, 0) != 0) continue;
    const std::string number = text.substr(name.size());
    if (number.empty()) return Parsed{kind, 1};
    if (number.size() > 9 || number[0] == '0' || number.find_first_not_of("0123456789") != std::string::npos)
      return std::nullopt;
    return Parsed{kind, std::stoi(number)};
  }
  return std::nullopt;
}

}  // namespace

std::vector<PointLabel> point_labels(const BranchTable& table) {
  std::vector<PointLabel> out;
  if (table.rows.rows() == 0) return out;
  const int kind_col = table.column("kind"), row_col = table.column("row");
  std::map<PointKind, int> count, total;
  for (long i = 0; i < table.rows.rows(); ++i)
    ++total[static_cast<PointKind>(static_cast<int>(table.rows(i, kind_col)))];
  for (long i = 0; i < table.rows.rows(); ++i) {
    const auto kind = static_cast<PointKind>(static_cast<int>(table.rows(i, kind_col)));
    if (kind == PointKind::Regular) continue;
    const int k = ++count[kind];
    const bool alone = (kind == PointKind::Start || kind == PointKind::End) && total[kind] == 1;
    out.push_back({alone ? std::string(to_string(kind)) : fmt::format("{}{}", to_string(kind), k),
                   static_cast<int>(table.rows(i, row_col)), kind});
  }
  return out;
}

bool is_point_label(const std::string& text) { return parse_label(text).has_value(); }

int row_of_label(const BranchTable& table, const std::string& label, const std::string& where) {
  const std::optional<Parsed> wanted = parse_label(label);
  const std::vector<PointLabel> labels = point_labels(table);
  if (wanted) {
    int k = 0;
    for (const PointLabel& l : labels)
      if (l.kind == wanted->kind && ++k == wanted->k) return l.row;
  }
  throw std::invalid_argument(
      fmt::format("{}: no located point labelled '{}'; its labels: {}", where, label, describe_labels(labels)));
}

std::string describe_labels(const std::vector<PointLabel>& labels) {
  std::string out;
  for (const PointLabel& l : labels) out += fmt::format("{}{} (row {})", out.empty() ? "" : ", ", l.label, l.row);
  return out.empty() ? "none" : out;
}

}  // namespace keller
