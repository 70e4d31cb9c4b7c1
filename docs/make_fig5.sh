#!/bin/bash
# The README's figure in the manner of the paper's Fig. 5: six frames over one pulse cycle of the
# jellyfish (from a finished run in OUT) above a plot of the ring muscle's force over the same
# cycle (from OUT/bodies.csv). Usage: docs/make_fig5.sh OUT [T0] [FILE.png]
#   OUT      a run of scenes/jellyfish.json (`kurage run` or `kurage sim`)
#   T0       start of the cycle, s (default 5.5: the fourth pulse, while the bell climbs)
#   FILE     output (default docs/figures/jellyfish_fig5.png)
set -euo pipefail
out=${1:?usage: docs/make_fig5.sh OUT [T0] [FILE.png]}
t0=${2:-5.5}
file=${3:-docs/figures/jellyfish_fig5.png}
here=$(cd "$(dirname "$0")/.." && pwd)
kurage=${KURAGE:-$here/build/kurage}
scene=$here/scenes/jellyfish.json
period=$(python3 -c "import json;print(json.load(open('$scene'))['bodies'][0]['muscles'][0]['force']['period'])")
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
# The scene with its camera 22 m in front of the bell's centre of mass at mid-cycle (bodies.csv).
python3 - "$scene" "$out/bodies.csv" "$t0" "$period" "$tmp/scene.json" <<'PY'
import csv, json, sys
scene, rows, t0, period, dest = sys.argv[1], list(csv.DictReader(open(sys.argv[2]))), float(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
mid = min(rows, key=lambda r: abs(float(r['time_s']) - (t0 + period / 2)))
x, y, z = (float(mid['bell_' + k + '_m']) for k in 'xyz')
s = json.load(open(scene))
s['$schema'] = 'schema.json'
s['render']['camera'] = {'position': [x, y - 22.0, z + 2.0], 'look_at': [x, y, z + 0.5], 'up': [0, 0, 1], 'fov': 45}
json.dump(s, open(dest, 'w'))
PY
cp "$here/scenes/schema.json" "$tmp/schema.json"
# The run's quality sets its frame rate (a preview run has preview_quality.fps): the stills must use it.
quality=$(python3 -c "import json;print(json.load(open('$out/run.json'))['quality'])")
inputs=()
for k in 0 1 2 3 4 5; do
  t=$(python3 -c "print(round($t0 + $k * $period / 6, 3))")
  "$kurage" still "$tmp/scene.json" --time "$t" --from "$out" -o "$tmp/$k.png" --quality "$quality" --width 320 --height 360 --spp 4 \
    >/dev/null
  inputs+=(-i "$tmp/$k.png")
done
python3 - "$out/bodies.csv" "$t0" "$period" > "$tmp/force.dat" <<'PY'
import csv, sys
t0, period = float(sys.argv[2]), float(sys.argv[3])
for r in csv.DictReader(open(sys.argv[1])):
    t = float(r['time_s'])
    if t0 - 1e-9 <= t <= t0 + period + 1e-9:
        print(t - t0, r['bell_ring_force_N'])
PY
gnuplot <<GP
set terminal pngcairo size 1920,300 font ",16"
set output "$tmp/force.png"
set xlabel "time in the cycle (s)"
set ylabel "ring force per spring (N)"
set xrange [0:$period]
set key off
set grid
plot "$tmp/force.dat" using 1:2 with lines lw 3 lc rgb "#b03060"
GP
ffmpeg -loglevel error -y "${inputs[@]}" -i "$tmp/force.png" \
  -filter_complex "[0][1][2][3][4][5]hstack=6[strip];[strip][6]vstack" "$tmp/fig5.png"
mv "$tmp/fig5.png" "$file"
echo "$file"
