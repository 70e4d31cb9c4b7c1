"""Loads a kurage run into Blender (tested with Blender 3.4, Debian 12).

What it builds, from OUT/run.json (the scene as run) and OUT/exports/ (`kurage export OUT
--format mesh_ply,chains_obj`, or the scene's output.exports):
  - one mesh object per surface grid (fluid, each body) from exports/GRID/NNNN.ply, its mesh
    swapped as the frame changes (a frame-change handler; every frame's mesh is loaded once);
  - the chains (oral arms) from exports/chains/NNNN.obj as curves with kurage's tapered radius;
  - kurage's camera (position, look-at, up, vertical field of view, resolution), its sun
    (direction, strength from the irradiance, angular diameter) and its sky (a vertical
    gradient from horizon to zenith colour);
  - materials approximated with the Principled BSDF: dielectric -> glass-like transmission with
    kurage's IOR and a volume absorption from its absorption coefficients; translucent -> a
    subsurface-tinted transmissive material; diffuse -> its albedo.
Units are metres, z up, as in kurage; frame N of the Blender scene is kurage's frame N.

Use, interactively (Scripting tab, or):
    blender --python assets/blender/import_kurage.py -- --run OUT
headless, rendering one frame with Cycles:
    blender -b --factory-startup --python assets/blender/import_kurage.py -- \
        --run OUT --frame 12 --render frame.png [--width W --height H --samples N] \
        [--transparent] [--surfaces-only]
--surfaces-only leaves out the sky, sun and materials' colours (white emission on a transparent
background): a silhouette, used by kurage's test that the camera matches (tests/test_blender.cpp).
"""

import argparse
import json
import math
import os
import struct
import sys

import bpy
from mathutils import Matrix, Vector


# ---------------------------------------------------------------------------------------------
# Readers for kurage's own export formats (no add-on needed).

def read_ply_mesh(path):
    """kurage's binary little-endian PLY: float x y z [nx ny nz], faces as uchar + 3 ints."""
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    vertices = faces = 0
    props = []
    for line in header:
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            vertices = int(words[2])
        elif words[:2] == ["element", "face"]:
            faces = int(words[2])
        elif words[:2] == ["property", "float"]:
            props.append(words[2])
    stride = 4 * len(props)
    body = memoryview(data)[end:]
    positions = [struct.unpack_from("<3f", body, i * stride) for i in range(vertices)]
    offset = vertices * stride
    triangles = []
    for i in range(faces):
        n = body[offset]
        triangles.append(struct.unpack_from("<%di" % n, body, offset + 1))
        offset += 1 + 4 * n
    return positions, triangles


def read_obj_polylines(path):
    """kurage's chain OBJ: `o NAME`, `v x y z`, `l i j k ...` (1-based, global)."""
    vertices, lines, name = [], [], None
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "o":
                name = words[1]
            elif words[0] == "v":
                vertices.append(tuple(float(w) for w in words[1:4]))
            elif words[0] == "l":
                lines.append((name, [vertices[int(w) - 1] for w in words[1:]]))
    return lines


# ---------------------------------------------------------------------------------------------
# Scene pieces.

def look_at_matrix(position, look_at, up):
    """World matrix of a Blender camera (it looks along its local -Z, local Y up)."""
    position, look_at, up = Vector(position), Vector(look_at), Vector(up)
    forward = (look_at - position).normalized()
    right = forward.cross(up).normalized()
    camera_up = right.cross(forward)
    m = Matrix((right, camera_up, -forward)).transposed().to_4x4()
    m.translation = position
    return m


def make_camera(render):
    cam = render["camera"]
    data = bpy.data.cameras.new("kurage camera")
    data.sensor_fit = "VERTICAL"
    data.angle_y = math.radians(cam["fov"])
    data.clip_start = 0.01
    data.clip_end = 10000.0
    if cam.get("aperture", 0.0) > 0.0:
        data.dof.use_dof = True
        data.dof.aperture_fstop = 1.0
        data.dof.focus_distance = cam.get("focus_distance", 0.0) or (
            Vector(cam["look_at"]) - Vector(cam["position"])).length
    obj = bpy.data.objects.new("kurage camera", data)
    obj.matrix_world = look_at_matrix(cam["position"], cam["look_at"], cam["up"])
    bpy.context.scene.collection.objects.link(obj)
    bpy.context.scene.camera = obj
    return obj


def make_sun(render):
    light = render.get("light")
    if not light:
        return None
    data = bpy.data.lights.new("kurage sun", type="SUN")
    irradiance = light.get("irradiance", [1.0, 1.0, 1.0])
    strength = max(irradiance)
    data.energy = strength
    data.color = [c / strength for c in irradiance] if strength > 0 else (1.0, 1.0, 1.0)
    data.angle = math.radians(light.get("angular_diameter", 0.53))
    obj = bpy.data.objects.new("kurage sun", data)
    # A sun shines along its local -Z.
    direction = Vector(light["direction"]).normalized()
    obj.rotation_euler = direction.to_track_quat("-Z", "Y").to_euler()
    bpy.context.scene.collection.objects.link(obj)
    return obj


def make_world(render):
    env = render.get("environment", {})
    world = bpy.data.worlds.new("kurage sky")
    world.use_nodes = True
    nodes, links = world.node_tree.nodes, world.node_tree.links
    background = nodes["Background"]
    background.inputs["Strength"].default_value = env.get("intensity", 1.0)
    # Sky gradient: horizon colour at the horizon, zenith colour straight up (z of the view ray).
    coords = nodes.new("ShaderNodeTexCoord")
    separate = nodes.new("ShaderNodeSeparateXYZ")
    ramp = nodes.new("ShaderNodeValToRGB")
    ramp.color_ramp.elements[0].color = (*env.get("horizon", [0.85, 0.9, 0.95]), 1.0)
    ramp.color_ramp.elements[1].color = (*env.get("zenith", [0.35, 0.55, 0.9]), 1.0)
    links.new(coords.outputs["Generated"], separate.inputs[0])
    links.new(separate.outputs["Z"], ramp.inputs["Fac"])
    links.new(ramp.outputs["Color"], background.inputs["Color"])
    bpy.context.scene.world = world


def make_material(name, spec):
    mat = bpy.data.materials.new(name)
    mat.use_nodes = True
    bsdf = mat.node_tree.nodes["Principled BSDF"]
    albedo = spec.get("albedo", [0.8, 0.8, 0.8])
    kind = spec.get("type", "diffuse")
    # kurage's dielectric is clear (its colour comes from absorption); the others have an albedo.
    bsdf.inputs["Base Color"].default_value = (1.0, 1.0, 1.0, 1.0) if kind == "dielectric" else (*albedo, 1.0)
    checker = spec.get("checker_size", 0.0)
    if checker > 0.0:
        checker_texture(mat, bsdf.inputs["Base Color"], checker, albedo, spec.get("albedo_b", albedo))
    if kind in ("dielectric", "translucent"):
        bsdf.inputs["Transmission"].default_value = 1.0
        bsdf.inputs["Roughness"].default_value = 0.0 if kind == "dielectric" else 0.3
        bsdf.inputs["IOR"].default_value = spec.get("ior", 1.33)
        absorption = spec.get("absorption", [0.0, 0.0, 0.0])
        if any(a > 0.0 for a in absorption):
            # Beer-Lambert absorption per metre, as kurage's medium.
            volume = mat.node_tree.nodes.new("ShaderNodeVolumeAbsorption")
            strongest = max(absorption)
            volume.inputs["Density"].default_value = strongest
            volume.inputs["Color"].default_value = (*[math.exp(-a / strongest) for a in absorption], 1.0)
            output = mat.node_tree.nodes["Material Output"]
            mat.node_tree.links.new(volume.outputs["Volume"], output.inputs["Volume"])
    elif kind == "mirror":
        bsdf.inputs["Metallic"].default_value = 1.0
        bsdf.inputs["Roughness"].default_value = 0.0
    return mat


def checker_texture(mat, socket, size, colour_a, colour_b):
    """A 3-D checker of squares `size` metres in world coordinates, as kurage's."""
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    coords = nodes.new("ShaderNodeTexCoord")
    checker = nodes.new("ShaderNodeTexChecker")
    checker.inputs["Scale"].default_value = 1.0 / size
    checker.inputs["Color1"].default_value = (*colour_a, 1.0)
    checker.inputs["Color2"].default_value = (*colour_b, 1.0)
    # Blender's checker cell is 1/(2 scale) wide in each axis; scale the coordinates to match.
    mapping = nodes.new("ShaderNodeMapping")
    mapping.inputs["Scale"].default_value = (0.5, 0.5, 0.5)
    links.new(coords.outputs["Object"], mapping.inputs["Vector"])
    links.new(mapping.outputs["Vector"], checker.inputs["Vector"])
    links.new(checker.outputs["Color"], socket)


def make_ground(render):
    ground = render.get("ground", {})
    if not ground.get("enabled", True):
        return None
    size = 1000.0
    mesh = bpy.data.meshes.new("kurage ground")
    normal = Vector(ground.get("normal", [0, 0, 1])).normalized()
    point = Vector(ground.get("point", [0, 0, 0]))
    u = normal.orthogonal().normalized()
    v = normal.cross(u)
    corners = [point + size * (a * u + b * v) for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    mesh.from_pydata(corners, [], [(0, 1, 2, 3)])
    spec = {"type": "diffuse", "albedo": ground.get("color_a", [0.65, 0.65, 0.62]),
            "albedo_b": ground.get("color_b", [0.3, 0.3, 0.28]), "checker_size": ground.get("checker_size", 0.0)}
    mesh.materials.append(make_material("kurage ground", spec))
    obj = bpy.data.objects.new("kurage ground", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def make_tank(params, camera_position):
    """kurage's tank walls (render.tank): the container's side walls whose inner face the camera
    sees, from the floor up to the tank height (pipeline/render_scene.cpp tankMesh)."""
    tank = params["render"].get("tank", {})
    if not tank.get("enabled", False):
        return None
    box = params["container"]
    lo, hi = box["min"], box["max"]
    top = lo[2] + tank["height"] if tank.get("height", 0.0) > 0.0 else hi[2]
    vertices, faces = [], []
    for axis in (0, 1):
        other = 1 - axis
        for side in (0, 1):
            c = lo[axis] if side == 0 else hi[axis]
            inside = camera_position[axis] > c if side == 0 else camera_position[axis] < c
            if not inside:
                continue
            base = len(vertices)
            for u, z in ((lo[other], lo[2]), (hi[other], lo[2]), (hi[other], top), (lo[other], top)):
                p = [0.0, 0.0, z]
                p[axis], p[other] = c, u
                vertices.append(p)
            faces.append((base, base + 1, base + 2, base + 3))
    if not faces:
        return None
    mesh = bpy.data.meshes.new("kurage tank")
    mesh.from_pydata(vertices, [], faces)
    mesh.materials.append(make_material("kurage tank", tank.get("material", {})))
    obj = bpy.data.objects.new("kurage tank", mesh)
    bpy.context.scene.collection.objects.link(obj)
    return obj


def silhouette_material():
    mat = bpy.data.materials.new("kurage silhouette")
    mat.use_nodes = True
    nodes = mat.node_tree.nodes
    nodes.remove(nodes["Principled BSDF"])
    emission = nodes.new("ShaderNodeEmission")
    mat.node_tree.links.new(emission.outputs["Emission"], nodes["Material Output"].inputs["Surface"])
    return mat


def frame_file(folder, frame, extension):
    return os.path.join(folder, "%04d.%s" % (frame, extension))


class SurfaceSequence:
    """One object per grid whose mesh data is swapped per frame (loaded on first use)."""

    def __init__(self, exports, grid, material):
        self.folder = os.path.join(exports, grid)
        self.grid = grid
        self.meshes = {}
        self.obj = bpy.data.objects.new("kurage " + grid, bpy.data.meshes.new(grid + " empty"))
        self.material = material
        bpy.context.scene.collection.objects.link(self.obj)

    def mesh(self, frame):
        if frame not in self.meshes:
            path = frame_file(self.folder, frame, "ply")
            mesh = bpy.data.meshes.new("%s %04d" % (self.grid, frame))
            if os.path.exists(path):
                positions, triangles = read_ply_mesh(path)
                mesh.from_pydata(positions, [], triangles)
                mesh.update()
                mesh.polygons.foreach_set("use_smooth", [True] * len(mesh.polygons))
            if self.material:
                mesh.materials.append(self.material)
            self.meshes[frame] = mesh
        return self.meshes[frame]

    def show(self, frame):
        self.obj.data = self.mesh(frame)


class ChainSequence:
    """The chains of a frame as tapered curves (kurage's render.chain_radius)."""

    def __init__(self, exports, radius, material):
        self.folder = os.path.join(exports, "chains")
        self.radius = radius
        self.material = material
        self.objects = []

    def show(self, frame):
        for obj in self.objects:
            bpy.data.objects.remove(obj, do_unlink=True)
        self.objects = []
        path = frame_file(self.folder, frame, "obj")
        if not os.path.exists(path):
            return
        for name, points in read_obj_polylines(path):
            curve = bpy.data.curves.new("chain " + name, type="CURVE")
            curve.dimensions = "3D"
            curve.bevel_depth = self.radius.get("root", 0.1)
            curve.bevel_resolution = 3
            curve.use_fill_caps = True
            spline = curve.splines.new("POLY")
            spline.points.add(len(points) - 1)
            for k, p in enumerate(points):
                t = k / max(1, len(points) - 1)
                spline.points[k].co = (*p, 1.0)
                # Radius scales bevel_depth: root at the first point, tip at the last.
                root, tip = self.radius.get("root", 0.1), self.radius.get("tip", 0.1)
                spline.points[k].radius = (root + (tip - root) * t) / root if root > 0 else 1.0
            if self.material:
                curve.materials.append(self.material)
            obj = bpy.data.objects.new("kurage " + name, curve)
            bpy.context.scene.collection.objects.link(obj)
            self.objects.append(obj)


def load_run(run_dir, frame=0, surfaces_only=False):
    """Builds the scene of a kurage run; returns a function that shows a given frame."""
    with open(os.path.join(run_dir, "run.json")) as f:
        record = json.load(f)
    params = record["parameters"]
    render = params["render"]
    scene = bpy.context.scene
    for obj in list(scene.collection.objects):
        bpy.data.objects.remove(obj, do_unlink=True)

    scene.render.resolution_x = render["width"]
    scene.render.resolution_y = render["height"]
    scene.render.resolution_percentage = 100
    output = params.get("output", {})
    fps = output.get("fps", 24.0)
    scene.render.fps = max(1, int(round(fps)))
    scene.render.fps_base = scene.render.fps / fps
    scene.frame_start = 0
    scene.frame_end = int(math.floor(output.get("duration", 1.0) * fps + 1e-6))
    make_camera(render)

    exports = os.path.join(run_dir, "exports")
    if not os.path.isdir(exports):
        raise RuntimeError(exports + ": missing; run `kurage export %s --format mesh_ply,chains_obj`" % run_dir)
    if surfaces_only:
        white = silhouette_material()
        materials = {"fluid": white, "bodies": white, "chains": white}
    else:
        make_sun(render)
        make_world(render)
        make_ground(render)
        make_tank(params, render["camera"]["position"])
        materials = {"fluid": make_material("kurage fluid", render.get("fluid_material", {})),
                     "bodies": make_material("kurage body", render.get("body_material", {})),
                     "chains": make_material("kurage chain", render.get("chain_material", {}))}
    grids = sorted(d for d in os.listdir(exports)
                   if os.path.isdir(os.path.join(exports, d)) and d not in ("particles", "chains"))
    surfaces = [SurfaceSequence(exports, g, materials["fluid" if g == "fluid" else "bodies"]) for g in grids]
    chains = ChainSequence(exports, render.get("chain_radius", {}), materials["chains"])

    def show(f):
        for s in surfaces:
            s.show(f)
        chains.show(f)

    def on_frame_change(scene_, *args):
        show(scene_.frame_current)

    bpy.app.handlers.frame_change_pre[:] = [h for h in bpy.app.handlers.frame_change_pre
                                            if getattr(h, "__name__", "") != "kurage_frame_change"]
    on_frame_change.__name__ = "kurage_frame_change"
    bpy.app.handlers.frame_change_pre.append(on_frame_change)
    scene.frame_set(frame)
    show(frame)
    return show


def main(argv):
    parser = argparse.ArgumentParser(prog="import_kurage.py", description=__doc__.split("\n")[0])
    parser.add_argument("--run", required=True, help="the OUT folder of a kurage run")
    parser.add_argument("--frame", type=int, default=0)
    parser.add_argument("--render", help="render this frame with Cycles to a PNG and exit")
    parser.add_argument("--width", type=int)
    parser.add_argument("--height", type=int)
    parser.add_argument("--samples", type=int, default=32)
    parser.add_argument("--transparent", action="store_true", help="transparent film (alpha)")
    parser.add_argument("--surfaces-only", action="store_true",
                        help="white silhouettes on a transparent background, no lights")
    args = parser.parse_args(argv)
    load_run(args.run, args.frame, args.surfaces_only)
    scene = bpy.context.scene
    if args.width:
        scene.render.resolution_x = args.width
    if args.height:
        scene.render.resolution_y = args.height
    if args.render:
        scene.render.engine = "CYCLES"
        scene.cycles.device = "CPU"
        scene.cycles.samples = args.samples
        scene.cycles.use_denoising = False  # Debian builds Blender without OpenImageDenoise
        scene.render.film_transparent = args.transparent or args.surfaces_only
        scene.render.image_settings.file_format = "PNG"
        scene.render.image_settings.color_mode = "RGBA"
        scene.render.filepath = os.path.abspath(args.render)
        bpy.ops.render.render(write_still=True)


if __name__ == "__main__":
    main(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else [])
