#!/bin/sh
# tools/compare.py end to end: two solvers for six frames in 160x90 tiles give one labelled video
# of 320x90 and six frames (ffprobe reads it back), and with --png six PNGs of 320x90; each tile's first label holds its first frame's
# cloth milliseconds and its run's mean, as awk sums the air, forces, solve, collision and contact
# columns of its profile.csv. One solver, or a mistyped one, is refused with exit code 2 and a
# message naming it, and leaves no video.
# Usage: test_compare.sh PYTHON COMPARE_PY FLAGSIM OUT_DIR
set -u
py=$1 compare=$2 flagsim=$3 out=$4
rm -rf "$out" && mkdir -p "$out"
fail() { echo "FAIL: $*"; exit 1; }

"$py" "$compare" --flagsim "$flagsim" --solvers "kangcho;vbd:iterations=2" --frames 6 --width 160 --height 90 \
    --png --out "$out/two" > "$out/two.log" 2>&1 || { cat "$out/two.log"; fail "two solvers: exit $?"; }
probe=$(ffprobe -v error -count_frames -show_entries stream=width,height,nb_read_frames -of csv=p=0 "$out/two/compare.mp4")
[ "$probe" = "320,90,6" ] || fail "compare.mp4 is '$probe', not 320,90,6"
pngs=$(ls "$out/two/frames" | grep -c '^frame_0000[0-5]\.png$')
[ "$pngs" = 6 ] && [ ! -e "$out/two/frames.tmp" ] || { ls "$out/two"; fail "--png wrote $pngs of frame_00000..5.png"; }
frame=$(ffprobe -v error -show_entries stream=width,height -of csv=p=0 "$out/two/frames/frame_00005.png")
[ "$frame" = "320,90" ] || fail "frame_00005.png is '$frame', not 320x90"
for k in 1 2; do
    want=$(awk -F, 'NR == 1 { for (i = 1; i <= NF; ++i) col[$i] = i; next }
        { c = $col["air"] + $col["cloth_forces"] + $col["cloth_solve"] + $col["collision"] + $col["contact"]
          if (n++ == 0) first = c; s += c }
        END { printf "cloth %.1f ms/frame (run mean %.1f)", first, s / n }' "$out/two/$k/profile.csv")
    grep -qF "0.0000 drawtext@ms$((k - 1)) reinit text='$want';" "$out/two/$k/labels.cmd" ||
        { cat "$out/two/$k/labels.cmd"; fail "tile $k is not labelled '$want'"; }
done

"$py" "$compare" --flagsim "$flagsim" --solvers "kangcho" --out "$out/one" > "$out/one.log" 2>&1
code=$?
[ $code -eq 2 ] && grep -q "names 1 solvers; give two to four" "$out/one.log" || { cat "$out/one.log"; fail "one solver: exit $code"; }

"$py" "$compare" --flagsim "$flagsim" --solvers "kangcho;vbd:iteratons=2" --frames 2 --out "$out/bad" > "$out/bad.log" 2>&1
code=$?
[ $code -eq 2 ] && grep -q "'vbd:iteratons=2'.*no parameter 'iteratons'" "$out/bad.log" || { cat "$out/bad.log"; fail "bad spec: exit $code"; }
[ ! -e "$out/bad/compare.mp4" ] && [ ! -e "$out/bad/1" ] || fail "a refused comparison left output behind"
echo "compare: ok"
