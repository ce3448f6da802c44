// AUTO-style labels of the located points of a branch file: KINDk names the k-th row of that kind
// along the branch, 1-based (fold1, fold2, hopf1, bp1, event1, stop3), with the kind's name as the
// CSV export and the terminal write it (to_string(PointKind)); a kind alone names its first point
// (start, end, fold). `--restart`, `--switch` and `--from` take a label where they take a row, and
// `keller info` lists them. Located points always have a stored solution.
#pragma once

#include <string>
#include <vector>

#include "continuation/engine/BranchPoint.hpp"
#include "continuation/output/BranchFile.hpp"

namespace keller {

struct PointLabel {
  std::string label;  // "fold2"; the start and the end without their number where they are the only one
  int row = -1;
  PointKind kind = PointKind::Regular;
};

// The located rows of a branch table (every kind but regular points) with their labels, in table
// order (along the branch).
std::vector<PointLabel> point_labels(const BranchTable& table);

// Whether `text` is a label: a kind's name (start, stop, event, fold, bp, end, hopf) and an
// optional number from 1.
bool is_point_label(const std::string& text);

// The row that `label` names in the table. Throws std::invalid_argument naming `where` and the
// labels the table has when it has no such point.
int row_of_label(const BranchTable& table, const std::string& label, const std::string& where);

// "start (row 0), fold1 (row 12), end (row 40)"; "none" for a table without located points.
std::string describe_labels(const std::vector<PointLabel>& labels);

}  // namespace keller
