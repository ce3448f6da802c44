#include "runs/study/StudyTable.hpp"

#include <fmt/format.h>
#include <toml++/toml.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <set>
#include <sstream>
#include <tuple>

#include "continuation/output/BranchFile.hpp"
#include "core/H5File.hpp"
#include "core/PendingFile.hpp"
#include "runs/Provenance.hpp"
#include "runs/study/StudyTask.hpp"

namespace keller {

namespace fs = std::filesystem;

namespace {

std::string unquoted(const std::string& v) {
  if (v.size() >= 2 && v.front() == '"' && v.back() == '"') return v.substr(1, v.size() - 2);
  return v;
}

// Reads what [collect] asks for from a branch file into the row.
void collect_branch(const Study& study, const std::string& path, StudyRow& row) {
  const BranchTable t = read_branch_table(path);
  const StudyCollect& c = study.collect();
  const int kind = t.column("kind"), param = t.column(t.parameter);
  row.text["parameter"] = t.parameter;
  if (t.rows.rows() == 0) return;
  std::vector<std::string> found;
  for (const std::string& name : c.events) {
    const PointKind want_kind = collected_event_kind(name).value_or(PointKind::Event);
    // a monitor's zero is an event, or the end of the branch where the stop observable of that
    // name crossed its threshold (the engine reports such a point once, as the end; a file whose
    // end names no monitor says so in its status)
    const auto threshold_of = [&](const std::string& monitor) {
      return monitor.rfind(name + " < ", 0) == 0 || monitor.rfind(name + " > ", 0) == 0;
    };
    double value = NAN;
    for (const BranchEvent& e : t.events) {
      if (want_kind != PointKind::Event
              ? e.kind == want_kind
              : (e.kind == PointKind::Event && e.monitor == name) ||
                    (e.kind == PointKind::End &&
                     (e.monitor.empty() ? threshold_of(t.status) : threshold_of(e.monitor)))) {
        value = e.parameter;
        break;
      }
    }
    row.number["event:" + name] = value;
    if (std::isfinite(value)) found.push_back(fmt::format("{} at {} = {:.7g}", name, t.parameter, value));
  }
  // a stop crossed more than once (a branch that turns at a fold) gives o@v, then o@v#2, ...
  std::map<double, int> crossings;
  for (long i = 0; i < t.rows.rows(); ++i) {
    if (static_cast<int>(t.rows(i, kind)) != static_cast<int>(PointKind::Requested)) continue;
    const double v = t.rows(i, param);
    const int k = ++crossings[v];
    for (const std::string& o : c.stops)
      row.number[k == 1 ? fmt::format("{}@{}", o, v) : fmt::format("{}@{}#{}", o, v, k)] = t.rows(i, t.column(o));
  }
  const long last = t.rows.rows() - 1;
  // a requested stop at the bound the branch ends on is written as the end row, not as a stop:
  // collected as the stop too (the stops are read from the scene the file stores)
  if (!c.stops.empty() && crossings.count(t.rows(last, param)) == 0) {
    std::vector<double> requested;
    {
      H5File f(path, H5File::Mode::Read);
      if (f.exists("/scene")) {
        try {
          const toml::table scene = toml::parse(f.read_string("/scene"));
          if (const auto* list = scene["continuation"]["stops"].as_array())
            for (const auto& v : *list)
              if (const auto x = v.value<double>()) requested.push_back(*x);
        } catch (const toml::parse_error&) {
          // keller wrote it; a file it cannot parse has no stops to add
        }
      }
    }
    const double v = t.rows(last, param);
    if (std::find(requested.begin(), requested.end(), v) != requested.end())
      for (const std::string& o : c.stops) row.number[fmt::format("{}@{}", o, v)] = t.rows(last, t.column(o));
  }
  row.number["end_parameter"] = t.rows(last, param);
  for (const std::string& o : c.end) row.number["end:" + o] = t.rows(last, t.column(o));
  found.push_back(fmt::format("ended at {} = {:.7g} ({})", t.parameter, t.rows(last, param), t.status));
  row.found = fmt::format("{}", fmt::join(found, "; "));
}

void collect_solution(const Study& study, const std::string& path, StudyRow& row) {
  H5File f(path, H5File::Mode::Read);
  std::vector<std::string> shown;
  for (const std::string& o : study.collect().end) {
    const double v =
        f.has_attribute("/solution/observables", o) ? f.read_double_attribute("/solution/observables", o) : NAN;
    row.number["end:" + o] = v;
    shown.push_back(fmt::format("{} = {:.7g}", o, v));
  }
  row.found = shown.empty() ? "solved" : fmt::format("{}", fmt::join(shown, ", "));
}

std::string csv_field(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

}  // namespace

StudyRow StudyTable::row(const Study& study, const StudyTask& task) {
  StudyRow row;
  row.task = task.index;
  row.text["name"] = task.name;
  for (const auto& [k, v] : task.varied) row.text[k] = unquoted(v);
  const auto record = read_task_record(study, task);
  if (!record) {
    row.text["status"] = "missing";
    return row;
  }
  const bool current = task_current(study, task, *record);
  row.text["status"] = current ? record->status : "changed";
  row.text["reason"] = record->summary.reason;
  row.text["lu_backend"] = record->summary.lu_backend;
  const RunSummary& s = record->summary;
  row.number["exit_code"] = s.exit_code;
  row.number["unknowns"] = static_cast<double>(s.unknowns);
  row.number["points"] = s.points;
  row.number["rejected"] = s.rejected;
  row.number["factorisations"] = static_cast<double>(s.factorisations);
  row.number["seconds"] = s.seconds;
  row.number["solves"] = static_cast<double>(s.solves);
  row.number["nnz_lu"] = s.nnz_lu;
  row.number["lu_peak_mb"] = s.lu_peak_mb;
  row.number["factor_seconds"] = s.factor_seconds;
  row.number["solve_seconds"] = s.solve_seconds;
  row.number["attempts"] = record->attempts;
  row.number["runs"] = s.runs;
  row.number["process_seconds"] = record->process_seconds;
  row.number["peak_mb"] = record->peak_mb;
  row.found = record->status == "done" ? "" : record->status + ": " + s.reason;
  if (current && record->status == "done") {
    // what is collected is the task's own output, or nothing
    const std::string out = study.task_output(task);
    std::string fault = output_fault(study, task, out);
    StudyRow collected = row;
    if (fault.empty()) {
      try {
        if (study.kind() != "solve")
          collect_branch(study, out, collected);
        else
          collect_solution(study, out, collected);
      } catch (const std::exception& e) {
        fault = std::string("cannot be read: ") + e.what();
      }
    }
    if (fault.empty()) return collected;
    row.text["status"] = "damaged";
    row.text["reason"] = fmt::format("its output '{}' {}", out, fault);
    row.found = row.text["reason"];
  }
  return row;
}

StudyTable StudyTable::collect(const Study& study) {
  StudyTable t;
  for (const StudyTask& task : study.tasks()) t.rows_.push_back(row(study, task));
  t.text_columns_ = {"name"};
  for (const std::string& k : study.varied_keys()) t.text_columns_.push_back(k);
  for (const char* c : {"status", "reason", "parameter", "lu_backend"}) t.text_columns_.push_back(c);
  // the collected numbers in a fixed order: events, stops by observable and value, the end, the cost
  std::vector<std::string> events, stops, end;
  for (const std::string& e : study.collect().events) events.push_back("event:" + e);
  std::set<std::tuple<std::string, double, int>> stop_columns;  // observable, stop, crossing
  for (const StudyRow& r : t.rows_)
    for (const auto& [name, v] : r.number) {
      const auto at = name.find('@');
      if (at == std::string::npos) continue;
      const auto hash = name.find('#', at);
      const double value =
          std::stod(name.substr(at + 1, hash == std::string::npos ? std::string::npos : hash - at - 1));
      stop_columns.insert(
          {name.substr(0, at), value, hash == std::string::npos ? 1 : std::stoi(name.substr(hash + 1))});
    }
  for (const std::string& o : study.collect().stops)
    for (const auto& [obs, value, k] : stop_columns)
      if (obs == o) stops.push_back(k == 1 ? fmt::format("{}@{}", o, value) : fmt::format("{}@{}#{}", o, value, k));
  end.push_back("end_parameter");
  for (const std::string& o : study.collect().end) end.push_back("end:" + o);
  t.number_columns_ = {"exit_code"};
  for (const auto* group : {&events, &stops, &end})
    t.number_columns_.insert(t.number_columns_.end(), group->begin(), group->end());
  for (const char* c : {"unknowns", "points", "rejected", "factorisations", "seconds", "solves", "nnz_lu", "lu_peak_mb",
                        "factor_seconds", "solve_seconds", "process_seconds", "peak_mb", "attempts", "runs"})
    t.number_columns_.push_back(c);
  return t;
}

void StudyTable::write(const std::string& csv_path, const std::string& h5_path) const {
  fs::create_directories(fs::path(csv_path).parent_path());
  {
    PendingFile csv(csv_path);
    {
      std::ostringstream o;
      std::vector<std::string> header = {"task"};
      header.insert(header.end(), text_columns_.begin(), text_columns_.end());
      header.insert(header.end(), number_columns_.begin(), number_columns_.end());
      for (size_t i = 0; i < header.size(); ++i) o << (i ? "," : "") << csv_field(header[i]);
      o << "\n";
      for (const StudyRow& r : rows_) {
        o << r.task;
        for (const std::string& c : text_columns_) {
          const auto it = r.text.find(c);
          o << "," << csv_field(it == r.text.end() ? "" : it->second);
        }
        for (const std::string& c : number_columns_) {
          const auto it = r.number.find(c);
          o << ","
            << (it == r.number.end() || std::isnan(it->second) ? std::string() : fmt::format("{:.17g}", it->second));
        }
        o << "\n";
      }
      csv.write(o.str());
    }
    csv.commit();
  }
  PendingFile h5(h5_path);
  {
    H5File f(h5.path(), H5File::Mode::Create);
    h5.created(f.hold());
    f.create_group("/study");
    std::vector<double> task;
    for (const StudyRow& r : rows_) task.push_back(r.task);
    f.write_vector("/study/task", task);
    std::string order = "task";
    for (const std::string& c : text_columns_) {
      std::vector<std::string> v;
      for (const StudyRow& r : rows_) {
        const auto it = r.text.find(c);
        v.push_back(it == r.text.end() ? "" : it->second);
      }
      f.write_strings("/study/" + c, v);
      order += "," + c;
    }
    for (const std::string& c : number_columns_) {
      std::vector<double> v;
      for (const StudyRow& r : rows_) {
        const auto it = r.number.find(c);
        v.push_back(it == r.number.end() ? NAN : it->second);
      }
      f.write_vector("/study/" + c, v);
      order += "," + c;
    }
    f.set_attribute("/study", "columns", order);
    Provenance::current().write(f);
    f.close();
  }
  h5.commit();
}

}  // namespace keller
