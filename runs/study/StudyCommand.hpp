// `keller study STUDY.toml [--jobs N] [-o FOLDER]` runs a study here (or, under mpirun, over the
// ranks); `keller study list|run --task K|collect STUDY.toml` are the same study in the pieces
// a batch scheduler runs (docs/studies/README.md: a SLURM job array).
#pragma once

#include <string>

namespace keller {

struct StudyArguments {
  std::string action;  // "" (run it all), "list", "run", "collect"
  std::string study;
  std::string folder;  // "": <study stem> in the current directory
  int jobs = 0;        // 0: one per core
  int task = -1;       // for "run"
};

int run_study_command(const StudyArguments& args, int& argc, char**& argv);

}  // namespace keller
