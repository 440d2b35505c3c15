#!/bin/sh
# tools/lint_rules.py fails on each rule it keeps: a fixture repository with one offence of each
# (a private header included from tools/, a 501-line test, a commit named in docs/) must give
# exactly those three lines and exit 1; the same repository mended must give none and exit 0.
set -u
lint="$1"
d=$(mktemp -d)
trap 'rm -rf "$d"' EXIT
cd "$d" && git init -q .
mkdir -p cloth/src/multigrid tools docs tests/cloth/whitebox
echo '#pragma once' > cloth/src/multigrid/cycle.h
printf '#include "multigrid/cycle.h"\n' > tools/x.cpp
printf '#include "multigrid/cycle.h"\n' > tests/cloth/whitebox/ok.cpp
seq 501 | sed 's|^|// |' > tests/big.cpp
echo 'Since 3cf7807 the stretch is lower.' > docs/x.md
echo 'The golden hash 9f7821d93241d522 holds.' > docs/y.md
out=$("$lint" "$d"); status=$?
echo "$out"
[ "$status" = 1 ] || { echo "FAIL: exit $status, wanted 1"; exit 1; }
[ "$(echo "$out" | wc -l)" = 3 ] || { echo "FAIL: wanted 3 offences"; exit 1; }
echo "$out" | grep -q 'tools/x.cpp:1: includes' || { echo "FAIL: the private include"; exit 1; }
echo "$out" | grep -q 'tests/big.cpp: 501 lines' || { echo "FAIL: the long test"; exit 1; }
echo "$out" | grep -q 'docs/x.md:1: names a commit (3cf7807)' || { echo "FAIL: the commit in docs"; exit 1; }
rm tools/x.cpp docs/x.md && seq 500 | sed 's|^|// |' > tests/big.cpp
out=$("$lint" "$d"); status=$?
[ "$status" = 0 ] && [ -z "$out" ] || { echo "FAIL: the mended repository: exit $status: $out"; exit 1; }
echo "lint rules: each offence caught, the mended repository clean"
