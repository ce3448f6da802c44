#!/bin/sh
# The layering check must fail on an include against the layers, and pass on the tree as it is.
# Each case copies the source folders into a fresh temporary tree, adds one file that breaks
# one rule, and requires .ci/check_layering to exit non-zero and to name that file.
# Usage: check_layering_test.sh SOURCE_DIR
src=${1:?source dir}
check="$src/.ci/check_layering"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
failures=0
fresh() {
  rm -rf "$work/tree"
  mkdir -p "$work/tree"
  for d in core problems continuation stability; do cp -R "$src/$d" "$work/tree/$d"; done
}
expect_pass() {
  fresh
  if ! sh "$check" "$work/tree" >"$work/out" 2>&1; then
    echo "FAIL: the unmodified tree does not pass:"
    cat "$work/out"
    failures=$((failures + 1))
  fi
}
expect_violation() {  # file (relative to the tree), its contents, what the case is
  fresh
  mkdir -p "$(dirname "$work/tree/$1")"
  printf '%s\n' "$2" >"$work/tree/$1"
  if sh "$check" "$work/tree" >"$work/out" 2>&1; then
    echo "FAIL: not detected: $3 ($1)"
    failures=$((failures + 1))
  elif ! grep -q "$1" "$work/out"; then
    echo "FAIL: detected, but the report does not name $1: $3"
    cat "$work/out"
    failures=$((failures + 1))
  else
    echo "ok: $3"
  fi
}
expect_pass
expect_violation problems/laws/Bad.hpp '#include "problems/kernels/FlowSource.hpp"' "a law includes a kernel"
expect_violation problems/kernels/Bad.hpp '#include "problems/components/FlowEquations.hpp"' "a kernel includes a component"
expect_violation problems/components/Bad.cpp '#include "problems/channel/ChannelMesh.hpp"' "a component includes a problem builder"
expect_violation problems/cylinder/Bad.cpp '#include "problems/channel/ChannelMesh.hpp"' "the cylinder includes the channel"
expect_violation problems/flow/Bad.cpp '#include "problems/cylinder/CylinderProblem.hpp"' "the flow layer includes the cylinder"
expect_violation problems/rheometry/Bad.cpp '#include "problems/components/FlowEquations.hpp"' "a homogeneous flow includes a component"
expect_violation problems/analytic/Bad.hpp '#include "problems/laws/ConstitutiveLaw.hpp"' "an analytic problem includes a law"
expect_violation problems/kernels/Bad.hpp '#include "problems/ProblemRegistry.hpp"' "a kernel includes the registry"
expect_violation problems/kernels/Bad.hpp '#include "FlowSource.hpp"' "a header included without its folder"
expect_violation problems/channel/Bad.cpp '#include "continuation/Continuation.hpp"' "a problem includes continuation/"
expect_violation continuation/Bad.cpp '#include "problems/channel/ChannelProblem.hpp"' "continuation/ includes problems/"
expect_violation stability/Bad.cpp '#include <problems/laws/ConstitutiveLaw.hpp>' "stability/ includes problems/"
expect_violation core/Bad.cpp '#include "problems/laws/ConstitutiveLaw.hpp"' "core/ includes problems/"
expect_violation continuation/engine/Bad.hpp '#include "continuation/events/EventLocator.hpp"' "the engine includes events"
expect_violation continuation/events/Bad.cpp '#include "continuation/Continuation.hpp"' "events include the stepper"
expect_violation continuation/Bad.cpp '#include "continuation/curves/CurveProblem.hpp"' "the stepper includes curves"
expect_violation continuation/curves/Bad.cpp '#include "continuation/start/StartSolver.hpp"' "curves include start"
expect_violation continuation/time/Bad.cpp '#include "continuation/engine/Corrector.hpp"' "time integration includes the engine"
expect_violation continuation/engine/Bad.cpp '#include "continuation/output/BranchFile.hpp"' "the engine includes output"
expect_violation continuation/misc/Bad.hpp '// a folder outside the rule' "a folder that is not a subsystem"
expect_violation continuation/Bad.cpp '#include "stability/EigenSolver.hpp"' "continuation/ includes stability/"
expect_violation stability/Bad.hpp '#include "continuation/Continuation.hpp"' "stability/ includes continuation/"
expect_violation continuation/Bad.hpp 'double Wi = 0;' "continuation/ names a physical quantity"
if [ $failures -ne 0 ]; then
  echo "$failures case(s) failed"
  exit 1
fi
echo "all layering cases detected"
