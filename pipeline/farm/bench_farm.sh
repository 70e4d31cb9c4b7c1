#!/usr/bin/env bash
# Wall time of a scene farmed on a private single-node Slurm in 1, 2 and 4 array tasks against
# `kurage run` of the same scene and quality: the scheduler's overhead per task. Needs root and
# slurm-wlm + munge (.ci/install-deps). Prints a Markdown table.
#   pipeline/farm/bench_farm.sh [KURAGE] SCENE [QUALITY]     e.g. build/kurage scenes/dam_break.json preview
set -euo pipefail
kurage=build/kurage
if [[ $# -gt 1 && -x "$1" && ! -d "$1" ]]; then kurage=$1; shift; fi
scene=$1
quality=${2:-preview}
kurage=$(realpath "$kurage")
scene=$(realpath "$scene")
work=$(mktemp -d /tmp/kurage-farm-bench.XXXXXX)
slurm=/tmp/kurage-slurm-bench
eval "$(SLURM_LOCAL_PARTITION_OPTS=${SLURM_LOCAL_PARTITION_OPTS:-} "$(dirname "$0")/../../tests/slurm_local.sh" restart "$slurm")"
trap '"$(dirname "$0")/../../tests/slurm_local.sh" stop "$slurm" >/dev/null; rm -rf "$work"' EXIT

now() { date +%s.%N; }
start=$(now)
"$kurage" run "$scene" -o "$work/local" --quality "$quality" > /dev/null 2>&1
local_s=$(python3 -c "print($(now) - $start)")
echo "| run | tasks | wall s | vs kurage run |"
echo "| --- | ---: | ---: | ---: |"
printf "| kurage run | - | %.1f | 1.00 |\n" "$local_s"
for tasks in 1 2 4; do
  out=$work/farm$tasks
  start=$(now)
  "$kurage" farm "$scene" -o "$out" --quality "$quality" --max-tasks "$tasks" --frames-per-task 1000000 --submit > "$work/submit$tasks.txt"
  ids=$(python3 -c "import json; j=json.load(open('$out/farm/jobs.json')); print(','.join(v for v in j.values() if isinstance(v, str)))")
  while [[ -n $(squeue -h -j "$ids" -t PD,R,CG,CF 2>/dev/null) ]]; do sleep 0.2; done
  s=$(python3 -c "print($(now) - $start)")
  grep -q "missing frames: none" <("$kurage" farm status "$out") || { echo "farm with $tasks tasks did not finish" >&2; exit 1; }
  printf "| kurage farm --submit | %d | %.1f | %.2f |\n" "$tasks" "$s" "$(python3 -c "print($s / $local_s)")"
done
