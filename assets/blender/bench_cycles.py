"""Renders one frame of a kurage run with Cycles at several sample counts and prints the seconds
of each render (the scene loaded once, Blender's start-up not counted).

    blender -b --factory-startup --python assets/blender/bench_cycles.py -- OUT FRAME DIR SPP[,SPP...]

Each render goes to DIR/cycles_SPP.png. The scene is import_kurage.py's (OUT/exports/ must hold
the frame's meshes), rendered on the CPU with 2 threads, a fixed number of samples (no adaptive
sampling, no denoiser: Debian's Blender has no OpenImageDenoise), every bounce limit 6 (kurage's
preview max depth) and the seed from the environment's SEED (default 0). Used by
assets/blender/bench_against_cycles.sh.
"""
import sys, time, os
# this file's folder, for import_kurage (Blender passes the script after --python)
sys.path.insert(0, os.path.dirname(os.path.abspath(sys.argv[sys.argv.index("--python") + 1])))
import bpy
import import_kurage as ik
argv = sys.argv[sys.argv.index("--") + 1:]
run, frame, outdir = argv[0], int(argv[1]), argv[2]
spps = [int(s) for s in argv[3].split(",")]
ik.load_run(run, frame, False)
sc = bpy.context.scene
sc.render.engine = "CYCLES"
sc.cycles.device = "CPU"
sc.render.threads_mode = "FIXED"
sc.render.threads = 2
sc.cycles.use_adaptive_sampling = False
sc.cycles.use_denoising = False
for k in ("max_bounces", "diffuse_bounces", "glossy_bounces", "transmission_bounces", "transparent_max_bounces", "volume_bounces"):
    setattr(sc.cycles, k, 6)
sc.cycles.seed = int(os.environ.get("SEED", "0"))
sc.render.image_settings.file_format = "PNG"
sc.render.image_settings.color_mode = "RGB"
for spp in spps:
    sc.cycles.samples = spp
    sc.render.filepath = os.path.abspath(os.path.join(outdir, "cycles_%d.png" % spp))
    t = time.perf_counter()
    bpy.ops.render.render(write_still=True)
    print("CYCLES spp %d seconds %.3f" % (spp, time.perf_counter() - t), flush=True)
