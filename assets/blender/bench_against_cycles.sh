#!/bin/bash
# kurage's path tracer against Blender's Cycles (the established open-source path tracer) on the
# same frame, the same geometry and the same machine: seconds per frame and the RMSE of each
# renderer against its own converged frame, at the same sample counts.
#
#   assets/blender/bench_against_cycles.sh build/kurage OUT FRAME [REFERENCE_SPP]
#
# OUT is a run of scenes/jellyfish.json (`kurage run scenes/jellyfish.json -o OUT --quality preview`,
# the README's main command); FRAME one of its frames (96 is t = 8 s at the preview's 12 fps).
# kurage renders with `kurage still --from OUT --quality preview` (480 x 270, max depth 6; process
# start and surfacing included in its seconds) three ways: as the scene's path tracer ("path",
# with its transmissive shadows, docs/design/rendering.md), the same with the denoiser (against the path
# tracer's reference), and with exact transport ("exact",
# "transmissive_shadows": false: light reaches what lies under the water only through refraction,
# as in Cycles). Cycles renders the meshes `kurage export` writes, through
# assets/blender/import_kurage.py (its materials approximate kurage's), with bench_cycles.py. RMSE
# is over the 8-bit sRGB PNGs' r, g, b in [0, 1] (ffmpeg's PSNR), each against the same
# renderer's frame at REFERENCE_SPP (default 1024) with another seed. Single runs: about ±10 %.
# Takes about 8 minutes on 2 cores at 1,024 reference samples.
set -euo pipefail
KURAGE=$(realpath "$1"); OUT=$(realpath "$2"); FRAME=$3; REF=${4:-1024}
HERE=$(cd "$(dirname "$0")" && pwd)
WORK=$(mktemp -d); trap 'rm -rf "$WORK"' EXIT
SCENE=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['scene_file'])" "$OUT/run.json")
FPS=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['parameters']['output']['fps'])" "$OUT/run.json")
TIME=$(python3 -c "print($FRAME / $FPS)")
"$KURAGE" export "$OUT" --format mesh_ply,chains_obj --frames "$FRAME-$FRAME" >/dev/null
python3 - "$SCENE" "$WORK" <<'PY'
import json, sys
scene = json.load(open(sys.argv[1]))
scene["render"]["integrator"] = "path"
json.dump(scene, open(sys.argv[2] + "/path.json", "w"))
scene["render"]["denoise"] = {"enabled": True}
json.dump(scene, open(sys.argv[2] + "/denoised.json", "w"))
del scene["render"]["denoise"]
scene["render"]["transmissive_shadows"] = False
json.dump(scene, open(sys.argv[2] + "/exact.json", "w"))
PY
rmse() {  # RMSE of $1 against $2
  local p
  p=$(ffmpeg -hide_banner -i "$1" -i "$2" -lavfi "[0]format=gbrp[a];[1]format=gbrp[b];[a][b]psnr" -f null - 2>&1 |
      grep -o "average:[0-9.inf]*" | cut -d: -f2)
  python3 -c "print('%.4f' % (10 ** (-float('$p') / 20)))"
}
SPPS="1 4 16 64"
declare -A SECONDS_OF
for v in path denoised exact; do
  spps="$SPPS $REF"; [ $v = denoised ] && spps=$SPPS
  for spp in $spps; do
    seed=1; [ "$spp" = "$REF" ] && seed=7
    t0=$(date +%s.%N)
    "$KURAGE" still "$WORK/$v.json" --from "$OUT" --time "$TIME" --quality preview --spp "$spp" --seed $seed \
        --threads 2 -o "$WORK/${v}_$spp.png" >/dev/null
    t1=$(date +%s.%N)
    SECONDS_OF[$v$spp]=$(python3 -c "print('%.2f' % ($t1 - $t0))")
  done
done
cycles() {  # seed, sample list, folder
  SEED=$1 blender -b --factory-startup --python "$HERE/bench_cycles.py" -- "$OUT" "$FRAME" "$3" "$2" 2>&1 |
    awk '/^CYCLES/ {print $3, $5}'
}
while read -r spp s; do SECONDS_OF[cycles$spp]=$s; done < <(cycles 1 "${SPPS// /,}" "$WORK")
mkdir -p "$WORK/ref"
while read -r spp s; do SECONDS_OF[cycles$spp]=$s; done < <(cycles 7 "$REF" "$WORK/ref")
mv "$WORK/ref/cycles_$REF.png" "$WORK/cycles_$REF.png"
printf "frame %s of %s (t = %s s), 480x270, 2 threads; RMSE against the same renderer at %s spp\n" \
    "$FRAME" "$OUT" "$TIME" "$REF"
printf "%-34s %6s %10s %8s\n" "renderer" "spp" "s/frame" "RMSE"
for v in path denoised exact cycles; do
  ref=$v; [ $v = denoised ] && ref=path
  case $v in
    path) label="kurage path (transmissive shadows)";;
    denoised) label="kurage path + denoiser";;
    exact) label="kurage path (exact transport)";;
    cycles) label="Cycles (Blender $(blender --version 2>/dev/null | awk 'NR==1 {print $2}'))";;
  esac
  for spp in $SPPS; do
    printf "%-34s %6s %10s %8s\n" "$label" "$spp" "${SECONDS_OF[$v$spp]}" "$(rmse "$WORK/${v}_$spp.png" "$WORK/${ref}_$REF.png")"
  done
  [ $v = denoised ] || printf "%-34s %6s %10s %8s\n" "$label" "$REF" "${SECONDS_OF[$v$REF]}" "(reference)"
done
