#!/usr/bin/env bash
# Runs the studies (all of scenes/studies/*.json, or those named) one after another on one
# thread, and copies each one's study.csv, its figure (study.png, .svg, .pdf and the gnuplot script
# study.gp) and study.md to docs/results/data/studies/NAME.*. A figure alone is redrawn from its CSV by
#   build/kurage study scenes/studies/NAME.json --replot docs/results/data/studies/NAME.csv -o docs/results/data/studies/NAME.png
# Usage, from the repository root: scenes/studies/run.sh [KURAGE] [NAME ...]
#   KURAGE defaults to build/kurage; NAME is a study file's name without .json.
set -euo pipefail
kurage=build/kurage
if [[ $# -gt 0 && -x "$1" && ! -d "$1" ]]; then kurage=$1; shift; fi
names=("$@")
if [[ ${#names[@]} -eq 0 ]]; then
  for f in scenes/studies/*.json; do names+=("$(basename "$f" .json)"); done
fi
mkdir -p docs/results/data/studies out/studies
for name in "${names[@]}"; do
  out=out/studies/$name
  start=$(date +%s)
  "$kurage" study "scenes/studies/$name.json" -o "$out" --threads 1
  echo "$name: $(( $(date +%s) - start )) s"
  for ext in csv png svg pdf gp md; do cp "$out/study.$ext" "docs/results/data/studies/$name.$ext.tmp" && mv "docs/results/data/studies/$name.$ext.tmp" "docs/results/data/studies/$name.$ext"; done
done
