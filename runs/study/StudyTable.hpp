// The collected results of a study: one row per task with its overrides, how it ended, what the
// study's [collect] asks for (located events, observables at the requested stops and at the
// end) and its cost, read from the tasks' records and output files. Written as FOLDER/NAME.csv
// and FOLDER/NAME.h5 (/study/<column>: numbers, or strings for the overrides, status and
// reasons; the attribute `columns` of /study gives their order).
#pragma once

#include <map>
#include <string>
#include <vector>

#include "runs/study/Study.hpp"

namespace keller {

struct StudyRow {
  int task = 0;
  std::map<std::string, std::string> text;  // overrides (by key), name, status, reason, parameter
  std::map<std::string, double> number;     // exit_code, the collected values, the cost
  std::string found;                        // a line for people: what the task found
};

class StudyTable {
 public:
  // Reads every task's record and output (tasks without a record get status "missing").
  static StudyTable collect(const Study& study);
  // The row of one task alone (for progress lines).
  static StudyRow row(const Study& study, const StudyTask& task);

  const std::vector<std::string>& text_columns() const { return text_columns_; }
  const std::vector<std::string>& number_columns() const { return number_columns_; }
  const std::vector<StudyRow>& rows() const { return rows_; }
  // Both files, each written atomically.
  void write(const std::string& csv_path, const std::string& h5_path) const;

 private:
  std::vector<std::string> text_columns_, number_columns_;
  std::vector<StudyRow> rows_;
};

}  // namespace keller
