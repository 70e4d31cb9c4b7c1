#!/usr/bin/env bash
# Regenerates docs/results/performance.md, the one page of kurage's speed figures. It runs the
# benchmarks, keeps what each records (its JSON: the figures, and the machine, the date and
# kurage's commit) in docs/results/data/performance/NAME.json, then writes the page from every JSON
# file there. Usage, from the repository root, on an otherwise idle machine:
#   docs/make_performance.sh [KURAGE] [NAME ...]    run these benchmarks (default: all), then the page
#   docs/make_performance.sh --page                 only rewrite the page from the JSON files
# KURAGE defaults to build/kurage. NAME is one of: sim window surface render film preview. All of
# them take about 6 minutes on 2 cores, half of it the film.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
data=docs/results/data/performance
page=docs/results/performance.md
kurage=build/kurage
if [[ $# -gt 0 && -x "$1" && ! -d "$1" ]]; then kurage=$1; shift; fi
names=("$@")
if [[ ${#names[@]} -eq 0 ]]; then names=(sim window surface render film preview); fi
if [[ ${names[0]} == --page ]]; then names=(); fi
mkdir -p "$data"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# A benchmark's JSON, written atomically.
keep() { mv "$tmp/$1.json" "$data/$1.json"; echo "$data/$1.json"; }

# The machine record of this binary (bench render at 1 spp is the cheapest way to get one).
machine() { "$kurage" bench render --spp 1 --json | python3 -c 'import json,sys; print(json.dumps(json.load(sys.stdin)["machine"]))'; }

for name in "${names[@]}"; do
  case $name in
    sim)  # every solver on a 100,800-particle dam break, 1 and 2 threads
      "$kurage" bench sim --particles 100000 --json > "$tmp/sim.json" && keep sim ;;
    window)  # DFSPH against WCSPH over the same simulated second of the collapse, 2 threads
      {
        echo '{"runs": ['
        "$kurage" bench sim --particles 100000 --threads 2 --warmup-time 0.7 --duration 1 --solver dfsph --json; echo ,
        "$kurage" bench sim --particles 100000 --threads 2 --warmup-time 0.7 --duration 1 --solver dfsph-calm --json; echo ,
        "$kurage" bench sim --particles 100000 --threads 2 --warmup-time 0.7 --duration 1 --solver wcsph --sound-speed-scale 1.6 --json; echo ,
        "$kurage" bench sim --particles 100000 --threads 2 --warmup-time 0.7 --duration 1 --solver wcsph --sound-speed-scale 1.6 --cfl 1 --json
        echo ']}'
      } > "$tmp/window.json" && keep window ;;
    surface)
      "$kurage" bench surface --json > "$tmp/surface.json" && keep surface ;;
    render)
      "$kurage" bench render --json > "$tmp/render.json" && keep render ;;
    film)  # the README's main command, stage by stage from its run.json
      start=$(date +%s.%N)
      "$kurage" run scenes/jellyfish.json -o "$tmp/film" --quality preview > /dev/null
      end=$(date +%s.%N)
      python3 - "$tmp/film/run.json" "$start" "$end" "$(machine)" > "$tmp/film.json" <<'PY'
import json, sys
run, start, end, machine = json.load(open(sys.argv[1])), float(sys.argv[2]), float(sys.argv[3]), json.loads(sys.argv[4])
print(json.dumps({"benchmark": "film", "command": "kurage run scenes/jellyfish.json -o OUT --quality preview",
                  "machine": machine, "wall_s": end - start, "run": run}, indent=2))
PY
      keep film ;;
    preview)  # the default dam break drawn as spheres, against its path-traced frames
      "$kurage" sim scenes/dam_break.json -o "$tmp/db" > /dev/null
      "$kurage" preview scenes/dam_break.json -o "$tmp/db" --no-video 2> "$tmp/preview.log" > /dev/null
      python3 - "$tmp/preview.log" "$(machine)" > "$tmp/preview.json" <<'PY'
import json, re, sys
log, machine = open(sys.argv[1]).read(), json.loads(sys.argv[2])
m = re.search(r"preview: (\d+) frames, ([\d.]+) frames/s drawing \((.*)\), ([\d.]+) frames/s with reading", log)
print(json.dumps({"benchmark": "preview", "scene": "scenes/dam_break.json", "machine": machine,
                  "frames": int(m.group(1)), "drawing_frames_per_s": float(m.group(2)), "gl": m.group(3),
                  "with_io_frames_per_s": float(m.group(4))}, indent=2))
PY
      keep preview ;;
    *) echo "make_performance.sh: unknown benchmark $name (sim window surface render film preview)" >&2; exit 2 ;;
  esac
done

python3 - "$data" > "$tmp/page.md" <<'PY'
import json, os, sys
data = sys.argv[1]
def load(name):
    path = os.path.join(data, name + ".json")
    return json.load(open(path)) if os.path.exists(path) else None
def measured(machine):
    flags = ", ".join(machine.get("cpu_flags", [])) or "none of note"
    return (f"Measured {machine['date']} on {machine['cpu_model']} ({machine['cores']} cores; {flags}), "
            f"kurage {machine['kurage_version']} at {machine['kurage_commit']} ({machine['build']}).")
def f(x, d=2): return f"{x:,.{d}f}"
out = []
w = out.append
def section(title, commands):
    """A section's heading and the line naming the command(s) that regenerate its table."""
    w("")
    w("## " + title)
    w("")
    w(commands)
    w("")
w("# Performance")
w("")
w("kurage's speed, in one place: the throughput of the simulation, the surfacing and the renderer,")
w("and the default film's stage times. This page is written by `docs/make_performance.sh` from the")
w("JSON that the benchmarks record in [data/performance/](data/performance/) — the figures, and the")
w("machine, the date and the commit they were measured on — and is not edited by hand. Figures of")
w("earlier dates and states of the code are in the [notebook](../notebook/README.md). Single")
w("figures scatter by 5–15 % between runs on a shared machine.")
sim = load("sim")
if sim:
    section("Simulation", "Command: `kurage bench sim --particles 100000 --json`")
    w(measured(sim["machine"]) + f" {sim['scene']}; c = 10 √(2gH) for WCSPH; "
      f"{sim['warmup_steps']} warm-up steps excluded, {sim['timed_steps']} steps timed; DFSPH and IISPH at "
      f"{sim['max_density_error_percent']:.2g} % mean density error with boundary-particle walls. "
      "Stage columns are ms a step (sort: binning and reordering; density: neighbour search and "
      "density sum; forces: pressure and viscosity; the incompressible solvers' solves are in the step's total only). "
      "Iterations are a solver's a step, all its solves (DFSPH's divergence solve's apart). "
      "`sim s/s` is simulated seconds per wall second; `density %` the fluid's mean compression.")
    w("")
    w("| solver | particles | h/l | threads | neighbours | ms/step | sort | density | forces | M particle-steps/s | B/particle | iterations | of them divergence | sim s/s | density % |")
    w("| --- | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in sim["runs"]:
        st = r.get("ms_per_step_by_phase", r.get("ms_per_step_by_stage", {}))
        divergence = r.get("iterations_per_step_by_solve", {}).get("divergence", r.get("divergence_iterations_per_step", 0))
        w(f"| {r['solver']} | {r['particles']:,} | {r['h_over_spacing']:.1f} | {r['threads']} | {r['mean_neighbours']:.1f} | "
          f"{f(r['ms_per_step'])} | {f(st.get('neighbour_sort', 0))} | {f(st.get('density', 0))} | "
          f"{f(st.get('pressure_viscosity_forces', 0))} | **{f(r['particle_steps_per_s'] / 1e6)}** | {r['bytes_per_particle']:.0f} | "
          f"{r['iterations_per_step']:.1f} | {divergence:.1f} | {r['simulated_s_per_wall_s']:.3f} | "
          f"{100 * r['mean_density_error']:.3f} |")
win = load("window")
if win:
    section("DFSPH against WCSPH over the same window", "Commands: `kurage bench sim --particles 100000 --threads 2 --warmup-time 0.7 --duration 1 --solver dfsph --json`, "
      "`kurage bench sim --particles 100000 --threads 2 --warmup-time 0.7 --duration 1 --solver dfsph-calm --json`, "
      "`kurage bench sim --particles 100000 --threads 2 --warmup-time 0.7 --duration 1 --solver wcsph --sound-speed-scale 1.6 --json`, "
      "`kurage bench sim --particles 100000 --threads 2 --warmup-time 0.7 --duration 1 --solver wcsph --sound-speed-scale 1.6 --cfl 1 --json`")
    first = win["runs"][0]
    w(measured(first["machine"]) + " The same dam break, each solver warmed up to t = 0.7 s and timed over "
      "the next simulated second of the collapse, so that both solve the same flow: DFSPH at its "
      "default 0.1 % and in the still tank's calm and corrected setting (`dfsph-calm`), WCSPH at "
      "1.6 times its default speed of sound, the cheapest found to hold 0.1 % mean compression over "
      "this window at h = 2 l ([notebook](../notebook/simulation-speed.md); at h = 1.5 l it reads a little "
      "above), at the scenes' cfl 0.4 and at cfl 1. The ratio is simulated seconds per wall second against "
      "WCSPH's at cfl 0.4 with the same h.")
    w("")
    rows = [(b, r) for b in win["runs"] for r in b["runs"]]
    base = {r["h_over_spacing"]: r["simulated_s_per_wall_s"] for b, r in rows if r["solver"] == "wcsph" and abs(b["cfl"] - 0.4) < 1e-3}
    w("| solver | setting | h/l | steps | sim s/s | density % | against WCSPH at cfl 0.4 |")
    w("| --- | --- | ---: | ---: | ---: | ---: | ---: |")
    for b, r in rows:
        setting = f"cfl {b['cfl']:.1g}" + (f", c × {b['sound_speed_scale']:.2g}" if r["solver"] == "wcsph" else "")
        ratio = r["simulated_s_per_wall_s"] / base[r["h_over_spacing"]] if r["h_over_spacing"] in base else None
        w(f"| {r['solver']} | {setting} | {r['h_over_spacing']:.1f} | {r['timed_steps']:,} | {r['simulated_s_per_wall_s']:.3f} | "
          f"{100 * r['mean_density_error']:.3f} | {'' if ratio is None else f'{ratio:.2f}'} |")
sur = load("surface")
if sur:
    section("Surfacing", "Command: `kurage bench surface --json`")
    mb = sur["metaball"]
    w(measured(sur["machine"]) + f" A {sur['scene']}, written once as a particle cache; blob radius "
      f"{mb['radius']:g}, threshold {mb['threshold']:.2g}, voxel {mb['voxel_size']:g}, half width {mb['half_width']:g} voxels; "
      f"the fastest of {sur['repeats']} runs. Rates are million particles per second: *level set* alone, *from cache* with "
      "reading the cache, *mesh* with meshing too; *P2LS* is OpenVDB's own ParticlesToLevelSet on the same particles "
      f"({sur.get('reference', 'not run')}: a union of spheres, not a metaball surface), for comparison. "
      "The clip to the container and the anisotropic kernels' level set are timed apart.")
    w("")
    w("| particles | threads | read s | level set s | level set | from cache | active voxels | MB | mesh s | mesh | P2LS s | P2LS | clip s | anisotropic s |")
    w("| ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: | ---: |")
    for r in sur["runs"]:
        p2 = r.get("openvdb_seconds")
        p2rate = "" if p2 is None else f"{r['openvdb_particles_per_s'] / 1e6:.2f}"
        w(f"| {r['particles']:,} | {r['threads']} | {r['read_seconds']:.3f} | {r['level_set_seconds']:.3f} | "
          f"**{r['level_set_particles_per_s'] / 1e6:.2f}** | {r['level_set_from_cache_particles_per_s'] / 1e6:.2f} | "
          f"{r['level_set_active_voxels']:,} | {r['level_set_bytes'] / 1e6:.1f} | {r['mesh_seconds']:.3f} | "
          f"{r['mesh_from_cache_particles_per_s'] / 1e6:.2f} | {'' if p2 is None else f'{p2:.3f}'} | "
          f"{p2rate} | "
          f"{r['clip_to_container_seconds']:.3f} | {r['anisotropic_level_set_seconds']:.3f} |")
ren = load("render")
if ren:
    section("Path tracer", "Command: `kurage bench render --json`")
    w(measured(ren["machine"]) + f" A fixed {ren['width']}×{ren['height']} scene: a metaball water heap of "
      f"{ren['triangles']:,} triangles over a checker ground with sun and sky, {ren['spp']} samples per pixel, max depth "
      f"{ren['max_depth']}. A ray is one Embree query: camera, bounce or shadow ray.")
    w("")
    w("| threads | s/frame | M camera rays/s | M rays/s, all |")
    w("| ---: | ---: | ---: | ---: |")
    for r in ren["runs"]:
        w(f"| {r['threads']} | **{r['seconds_per_frame']:.2f}** | {r['primary_mrays_per_s']:.2f} | {r['total_mrays_per_s']:.2f} |")
film = load("film")
if film:
    run = film["run"]
    stages = run.get("stages", {})
    simst = stages.get("sim", {})
    section("The default film, stage by stage", "Command: `kurage run scenes/jellyfish.json -o OUT --quality preview`")
    steps = simst.get("steps", {})
    w(measured(film["machine"]) + f" The README's main command after the build: **{film['wall_s']:.0f} s** from the "
      "scene file to the MP4. Stage seconds from its `run.json`; the rest is the process start and the "
      "video's encoding by ffmpeg.")
    w("")
    w("| stage | what | seconds |")
    w("| --- | --- | ---: |")
    if simst:
        solver = simst.get("solver", {})
        iters = ""
        ds, dv = solver.get("density_solve", {}), solver.get("divergence_solve", {})
        if ds.get("mean_iterations") is not None:
            iters = f"; {ds['mean_iterations']:.1f} density and {dv.get('mean_iterations', 0):.1f} divergence iterations a step"
        w(f"| sim | {run['parameters']['output']['duration']:g} s simulated, {simst.get('particles', 0):,} particles, "
          f"{simst.get('steps', 0):,} steps{iters} | {simst['seconds']:.1f} |")
    for name in ("surface", "render"):
        st = stages.get(name)
        if st:
            what = f"{st.get('frames_done', 0)} frames"
            if name == "render":
                what += f", {st['width']}×{st['height']}, {st['samples']} samples per pixel"
            w(f"| {name} | {what} | {st['seconds']:.1f} |")
pre = load("preview")
if pre:
    section("Preview", "Commands: `kurage sim scenes/dam_break.json -o OUT`, `kurage preview scenes/dam_break.json -o OUT --no-video`")
    w(measured(pre["machine"]) + f" The default dam break's {pre['frames']} frames drawn as spheres with OpenGL "
      f"({pre['gl']}): **{pre['drawing_frames_per_s']:.0f} frames/s** drawing, {pre['with_io_frames_per_s']:.0f} frames/s "
      "with reading the caches and writing the PNGs.")
page = "\n".join(out) + "\n"
sys.stdout.write(page)
PY
mv "$tmp/page.md" "$page"
echo "$page"
