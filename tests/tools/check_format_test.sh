#!/bin/sh
# The formatting check itself: it passes a formatted file and fails a misformatted one, naming it.
# Usage: check_format_test.sh SOURCE_DIR
set -u
src="$1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
mkdir "$tmp/good" "$tmp/bad"
cp "$src/tests/fixtures/format/good.cpp.in" "$tmp/good/good.cpp"
cp "$src/tests/fixtures/format/good.cpp.in" "$tmp/bad/good.cpp"
cp "$src/tests/fixtures/format/bad.cpp.in" "$tmp/bad/bad.cpp"
"$src/.ci/check_format" "$tmp/good" > "$tmp/good.out" 2>&1
rc=$?
[ $rc -eq 0 ] || { echo "a formatted file failed the check (exit $rc):"; cat "$tmp/good.out"; exit 1; }
"$src/.ci/check_format" "$tmp/bad" > "$tmp/bad.out" 2>&1
rc=$?
[ $rc -eq 1 ] || { echo "a misformatted file passed the check (exit $rc):"; cat "$tmp/bad.out"; exit 1; }
grep -q "not formatted: .*bad.cpp" "$tmp/bad.out" || { echo "the misformatted file is not named:"; cat "$tmp/bad.out"; exit 1; }
if grep -q "good.cpp" "$tmp/bad.out"; then echo "a formatted file was named:"; cat "$tmp/bad.out"; exit 1; fi
echo "check_format passes formatted files and names misformatted ones"
