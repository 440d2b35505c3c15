#!/bin/sh
# cloth_study with NVIDIA Newton's configurations when their process cannot run: without its
# Python the run refuses before it writes anything (exit 2, the path named); when the process
# refuses a step (the stand-in, fake_newton_bridge.py) the run stops with its reason (exit 1) and
# the rows written so far are front.csv.partial, never a front.csv that looks whole.
# Usage: test_peer_failures.sh CLOTH_STUDY FAKE_BRIDGE OUT_DIR
set -u
study=$1 fake=$2 out=$3
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }
args="--front-only --flags demo --paths drive --front-sizes 33 --nvidia-newton --no-references --no-cache"

FLAGSIM_NVIDIA_NEWTON_PYTHON=/nonexistent/python "$study" $args --configs nvidia_newton_vbd --out "$out/none" \
    > "$out/none.log" 2>&1
code=$?
[ $code -eq 2 ] && grep -q "no Python at '/nonexistent/python'" "$out/none.log" || { cat "$out/none.log"; fail "no Python: exit $code"; }
[ ! -e "$out/none" ] || fail "a refused run left $out/none"

FAKE_NEWTON_FAIL=step FLAGSIM_NVIDIA_NEWTON_PYTHON="$fake" "$study" $args --configs nvidia_newton_vbd --out "$out/step" \
    > "$out/step.log" 2>&1
code=$?
[ $code -eq 1 ] && grep -q "nvidia_newton: RuntimeError: the stand-in refuses to step" "$out/step.log" ||
    { cat "$out/step.log"; fail "a refused step: exit $code"; }
[ -e "$out/step/front.csv.partial" ] && [ ! -e "$out/step/front.csv" ] || { ls "$out/step"; fail "no front.csv.partial alone"; }
echo "peer failures: ok"
