#!/bin/sh
# Builds the seed corpora in fuzz/corpus/TARGET from the project's own files: the
# bad-input corpus (tests/bad_inputs), the presets, and small valid inputs written here.
# Run from the repository root: sh fuzz/seed.sh
set -eu
cd "$(dirname "$0")"
bad=../tests/bad_inputs
for target in rig table obj waters openface timeline combo; do
    mkdir -p "corpus/$target"
done
cp $bad/*.rig.ron ../presets/*.rig.ron corpus/rig/
cp $bad/*.au.ron ../presets/*.au.ron corpus/table/
cp $bad/*.obj corpus/obj/
# Every other corpus gets the binary garbage and invalid UTF-8 too.
for target in waters openface timeline combo; do
    cp $bad/binary_garbage.obj $bad/invalid_utf8.obj "corpus/$target/"
done

# A tiny quad mesh with groups, relative indices and the v/vt/vn corner forms.
cat > corpus/obj/quad.obj <<'OBJ'
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
vt 0 0
vn 0 0 1
g mouth
f 1/1/1 2/1/1 3/1/1 4/1/1
g brow
f -4//1 -2//1 -1//1
OBJ

# The classic Waters data: faceline.dat, NUL, index.dat, NUL, muscle.dat.
printf '4\n0.5 0 1\n1 0 1\n1 1 1\n0.5 1 1\n\0002\n1 2 3 4\n1000 1 2 3\n\0002\nL_pull 0.5 0 1 1 1 1 0.2 0.9 40 1\nR_pull -0.5 0 1 -1 1 1 0.2 0.9 40 1\n' \
    > corpus/waters/quad
printf '1\n0 0 0\n\0001\n1 1 1 1\n\0001\nm 0 0 0 1 1 1 0 1 10 1\n' > corpus/waters/point

# OpenFace CSV: the header of OpenFace 2.0 (trimmed) and rows, good and bad.
cat > corpus/openface/two_rows.csv <<'CSV'
frame, face_id, timestamp, confidence, success, AU01_r, AU06_r, AU12_r, AU45_r, AU01_c
1, 0, 0.000, 0.98, 1, 0.10, 1.50, 2.25, 0.00, 1
2, 0, 0.033, 0.98, 1, 0.20, 1.40, 2.50, 0.10, 1
3, 0, 0.067, 0.00, 0, 0.00, 0.00, 0.00, 0.00, 0
4, 0, 0.100, 0.98, 1, x, 1.40, 2.50
CSV
printf 'AU12_r,AU06_r\r\n5,0\r\n\r\n0.5,nan\r\n' > corpus/openface/minimal.csv

cat > corpus/timeline/smile.timeline.ron <<'RON'
Timeline(
    version: 1,
    frame_rate: 30.0,
    interpolation: Smooth,
    keyframes: [
        (time: 0.0),
        (time: 1.0, aus: "6+12@0.5"),
        (time: 1.5, aus: "smile", jaw: 1.0),
        (time: 2.0, muscles: {"L_pull": 0.5}),
    ],
)
RON
printf 'Timeline(version: 1, frame_rate: 4.0, interpolation: Step, keyframes: [(time: 0.0, aus: "L12C+R12A")])' \
    > corpus/timeline/step.timeline.ron

i=0
for combo in '1+2+5B+26' '6+12@0.5' 'L12C+R12A' '  4 + 7E ' '12@1e-3+12' '99' '0' '100' '12@' '12@nan' 'L' '+' ''; do
    printf '%s' "$combo" > "corpus/combo/seed$i"
    i=$((i + 1))
done
for target in rig table obj waters openface timeline combo; do
    echo "$target: $(ls corpus/$target | wc -l) seeds"
done
