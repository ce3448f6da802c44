// A point of a solution branch as the continuation engine reports it: the solution, its unit
// tangent, where it lies along the branch, what kind of point it is, and the problem's
// observables and monitors there.
#pragma once

#include <string>
#include <vector>

#include "core/Types.hpp"

namespace keller {

enum class PointKind {
  Regular = 0,      // an accepted continuation step
  Start = 1,        // the first point of a run (or of a restart)
  Requested = 2,    // located at a requested parameter value
  Event = 3,        // located zero of a monitor
  Fold = 4,         // located turning point in the parameter
  BranchPoint = 5,  // located sign change of det of the bordered Jacobian
  End = 6,          // located end of the branch (parameter bound or stop observable)
  Hopf = 7,         // located crossing of a complex pair of eigenvalues (PointAnalysis)
  // periodic orbits (continuation/orbits): a real Floquet multiplier through -1, a complex pair
  // through the unit circle (a fold or branch point of orbits is Fold or BranchPoint)
  PeriodDoubling = 8,
  NeimarkSacker = 9,
};
// point, start, stop, event, fold, bp, end, hopf, pd, ns: the terminal's, the CSV's and the
// labels' names
const char* to_string(PointKind k);

struct BranchPoint {
  int index = -1;  // row in the branch table
  PointKind kind = PointKind::Regular;
  std::string label;      // monitor name for events, "max"/"min" for folds, bound for ends
  double s = 0.0;         // arclength from the start of the branch (weighted norm)
  double lambda = 0.0;    // parameter value
  Vector u;               // solution
  Vector tu;              // unit tangent: state part
  double tlambda = 0.0;   //               parameter part
  double step = 0.0;      // step size the controller chose for the next step
  int iterations = 0;     // corrector iterations (location: corrector solves)
  double residual = 0.0;  // |F|_inf where the corrector converged (the start: |F|_inf there)
  double seconds = 0.0;   // wall time since the run started
  int det_sign = 0;       // sign of det(dF/du) (0: not known)
  int bordered_det_sign = 0;
  std::vector<double> observables;
  std::vector<double> monitors;  // the problem's monitors, then the stop-observable thresholds
  bool save = false;             // store the full solution
  // PointAnalysis (the stability spectrum) when the point was analysed: its columns, the count
  // whose changes are events, the locator that crosses zero there, the critical eigenvector
  bool analysed = false;
  std::vector<double> analysis;
  int count = -1;
  int analysis_width = 0;  // what the analysis computed (PointAnalysisResult::width)
  double locator = 0.0;
  double critical_imag = 0.0;
  int critical_multiplicity = 1;  // PointAnalysisResult::critical_multiplicity
  Vector critical_re, critical_im;
  // The normal form at a located fold, branch point or Hopf point, in the order of
  // normal_form_columns() (continuation/output/BranchFile.hpp) after row and kind; empty where none
  // was computed.
  std::vector<double> normal_form;
};

}  // namespace keller
