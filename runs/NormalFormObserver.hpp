// Computes the normal form of every located fold, simple branch point and Hopf point of a traced
// branch (stability/NormalForms) as the points arrive, attaches its numbers to the point for the
// branch file (/branch/normal_forms) and tells the terminal what happens beyond the point.
#pragma once

#include <optional>
#include <string>

#include "continuation/Continuation.hpp"
#include "continuation/curves/HopfCurveProblem.hpp"
#include "core/Problem.hpp"
#include "core/SparseLU.hpp"
#include "stability/NormalForms.hpp"

namespace keller {

class NormalFormObserver final : public BranchObserver {
 public:
  // parameter: the traced parameter's index in the problem's ParameterSet.
  NormalFormObserver(BranchObserver& inner, Problem& problem, int parameter, SparseLUOptions lu);
  // On a fold or Hopf curve of `problem` (unknowns U = (u, p1, ...), continued in p2): the normal
  // form of every located cusp, Bogdanov-Takens and fold-Hopf point (the zeros of the monitors
  // `cusp`, `bogdanov-takens` and `fold-hopf`), NormalForms::cusp, bogdanov_takens or fold_hopf
  // (omega = U's after p1) at (u, p1, p2) with lambda = p1.
  // observables: the curve's observables' count (the branch file's amplitude columns, NaN there).
  static NormalFormObserver for_curve(BranchObserver& inner, Problem& problem, int p1, int p2, size_t observables,
                                      SparseLUOptions lu);
  void on_start(const std::vector<std::string>& o, const std::vector<std::string>& m) override {
    inner_.on_start(o, m);
  }
  void on_point(const BranchPoint& p) override;
  void on_rejected(double l, double s, const Status& w) override { inner_.on_rejected(l, s, w); }
  void on_note(const std::string& m) override { inner_.on_note(m); }
  void on_finish(const std::string& r, const BranchPoint& last) override { inner_.on_finish(r, last); }

 private:
  // the row and the note of a computed normal form (or why it was not)
  void pass_on(const BranchPoint& p, const Status& st, const NormalForm& nf, size_t observables);

  BranchObserver& inner_;
  Problem& problem_;
  int parameter_;
  NormalForms forms_;
  std::optional<bool> has_time_form_;  // asked at the first Hopf point's state
  int curve_p2_ = -1;                  // a curve's p2 (for_curve), else -1
  size_t curve_observables_ = 0;
};

// The prediction `keller trace --switch` starts a new branch with at the branch point bp: the
// tangent of the branch of bp's normal form that is not the old one (the one least parallel to
// bp's tangent), a pitchfork's bifurcating branch with its parabola; nothing (and why in `note`)
// where the normal form is not computed or has no real branches, so that the switch falls back on
// J's null vector.
std::optional<Continuation::SwitchPrediction> switch_prediction(Problem& problem, int parameter, const BranchPoint& bp,
                                                                SparseLUOptions lu, std::string& note);

// The first Lyapunov coefficient a Hopf curve monitors for Bautin points (HopfCurveProblem's
// "bautin" column): l1 of the normal form at the point with the eigenvector q scaled to unit
// 2-norm, l1 / |q|^2 of the branch file's max-normalised q. Its sign is l1's; unlike the
// max-normalised value it does not jump where q's largest entry moves to another unknown.
HopfCurveProblem::LyapunovCoefficient unit_mode_lyapunov_coefficient(SparseLUOptions lu);

// The numbers of a normal form in the order of normal_form_columns().
std::vector<double> normal_form_row(const NormalForm& nf);

}  // namespace keller
