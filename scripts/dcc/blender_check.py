"""Imports a cache into Blender (PyPI bpy, headless) the way the README tells artists to,
and checks what they would see:

- File > Import > USD of OUT/cache.usd: the frame range is 1..N, frame k showing cache
  frame k (played at [output] playback_fps once the scene's rate is set to it, which
  Blender's importer does not do);
  the crack surface (or each fragment mesh) at frames 1 and N matches surface/0001.glb and
  surface/NNNN.glb within 1e-6 m; the point cloud carries `damage` and `fragment` and its
  points at frame N match particles/NNNN.ply; points, meshes, volumes and colliders are in
  one coordinate system (the y-up cache turned z-up by one rotation, as glTF imports are).
  Frame N renders in Workbench (64x48) to an image that is not empty. At the frame with the
  most crack faces (embedded method), the surface rendered alone in Cycles (128x96) shows
  crack-coloured pixels, and its crack faces (the face attribute `crack`) take the crack
  colour from the attribute `displayColor` that its materials read.
  Every collider is an object named after it (`ground`, `sphere_N`...; `shape` before).
  Each mesh collider (colliders/mesh_N.ply) is a mesh object with the PLY's vertices, posed
  at frames 1 and N as manifest.json says; with --rests-on-colliders, the lowest particle of
  frame N lies on its top (within -0.1 and 1 particle spacing).
- File > Import > glTF of OUT/surface/animated.glb (embedded method): every frame 1..N shows
  its own cache frame (the shape key named frame_NNNN alone, vertices of that frame), and
  each mesh collider's node shows it posed as the manifest says at frames 1..N.

usage: python blender_check.py OUT [--rests-on-colliders]
"""

import json
import sys
import tempfile
import tomllib
from pathlib import Path

import bpy
import numpy as np
from mathutils import Matrix

sys.path.insert(0, str(Path(__file__).parent))
from usd_check import check, posed_collider, read_collider, read_glb, read_glb_crack, read_ply  # noqa: E402

RESTS = "--rests-on-colliders" in sys.argv

TOLERANCE = 1e-6  # metres


def allowed(expected):
    """TOLERANCE, plus one float32 step (2^-23 of the largest coordinate): Blender turns
    the stage's Y-up points to Z-up in float32, which at the demo shot's 81 m rounds a
    coordinate by up to 6e-6 m."""
    return TOLERANCE + float(np.abs(expected).max(initial=0.0)) * 2.0**-23


def y_up_to_blender(p):
    """Cache coordinates (y up) in Blender's world (z up): (x, -z, y)."""
    p = np.asarray(p, dtype="f8")
    return np.stack([p[:, 0], -p[:, 2], p[:, 1]], axis=1)


def evaluated_vertices(obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(depsgraph)
    mesh = ev.to_mesh()
    local = np.empty(len(mesh.vertices) * 3)
    mesh.vertices.foreach_get("co", local)
    m = np.array(ev.matrix_world)
    ev.to_mesh_clear()
    local = local.reshape(-1, 3)
    return local @ m[:3, :3].T + m[:3, 3]


def evaluated_points(obj):
    depsgraph = bpy.context.evaluated_depsgraph_get()
    ev = obj.evaluated_get(depsgraph)
    cloud = ev.data
    pos = np.empty(len(cloud.points) * 3)
    cloud.attributes["position"].data.foreach_get("vector", pos)
    m = np.array(ev.matrix_world)
    return pos.reshape(-1, 3) @ m[:3, :3].T + m[:3, 3], cloud


def worst(a, b):
    if a.shape != b.shape:
        return float("inf")
    return float(np.abs(a - b).max()) if a.size else 0.0


def worst_unordered(a, b):
    """The largest distance from a point of either set to the nearest of the other
    (the sets' Hausdorff distance) when it is under 1 mm, else inf; inf too when the
    sizes differ. Neighbours are found in a 1 mm grid (numpy only, fast enough for the
    demo's 30,000 vertices a frame)."""
    if a.shape != b.shape:
        return float("inf")
    if not a.size:
        return 0.0
    h, half = 1e-3, 1 << 20

    def keys(cells):
        c = cells + half
        return (c[:, 0] << 42) | (c[:, 1] << 21) | c[:, 2]

    def one_way(p, q):
        order = np.argsort(keys(np.floor(q / h).astype(np.int64)))
        q = q[order]
        sorted_keys = keys(np.floor(q / h).astype(np.int64))
        cells = np.floor(p / h).astype(np.int64)
        best = np.full(len(p), np.inf)
        for off in np.array(np.meshgrid([-1, 0, 1], [-1, 0, 1], [-1, 0, 1])).T.reshape(-1, 3):
            k = keys(cells + off)
            lo = np.searchsorted(sorted_keys, k, "left")
            hi = np.searchsorted(sorted_keys, k, "right")
            for j in range(int((hi - lo).max())):
                rows = np.nonzero(lo + j < hi)[0]
                d = np.linalg.norm(p[rows] - q[lo[rows] + j], axis=1)
                best[rows] = np.minimum(best[rows], d)
        return float(best.max())

    return max(one_way(a, b), one_way(b, a))


def subject(points):
    """The centre and radius a check camera frames `points` by: their median, and the
    distance from it within which 3 in 4 of them lie (at least 5 cm). The bounding box
    would do for a wall that breaks, but at the end of a finished shot its pieces lie
    tens of metres apart (one rolled 80 m in the demo shot) and a box around all of them
    renders each as a speck; the median and quantile frame where most of the surface is,
    as the previews' percentile bounds do (docs/previews.md)."""
    centre = np.median(points, axis=0)
    radius = float(np.quantile(np.linalg.norm(points - centre, axis=1), 0.75))
    return centre, max(radius, 0.05)


def render(scene, frame):
    """Renders frame `frame` of the imported stage with Workbench (64x48, a camera aimed
    at the scene's objects) and checks the image shows something: rendering is where
    Blender reads every mesh's topology (a ground quad whose faceVertexIndices read
    back as [8, 0, 90112, 65536] imported, then crashed the render)."""
    from mathutils import Vector

    scene.frame_set(frame)
    # Framed on the crack surface, or on the particles in a cache without surfaces.
    surfaces = [evaluated_vertices(o) for o in scene.objects if o.type == "MESH" and o.name == "Surface"]
    if not surfaces:
        surfaces = [evaluated_points(o)[0] for o in scene.objects if o.type == "POINTCLOUD"]
    points = np.concatenate(surfaces) if surfaces else np.zeros((1, 3))
    centre, size = subject(points)
    centre = Vector(centre.tolist())
    camera = bpy.data.objects.new("check_camera", bpy.data.cameras.new("check_camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    camera.location = centre + Vector((1.0, -1.5, 0.8)).normalized() * size * 4
    camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.render.resolution_x, scene.render.resolution_y = 64, 48
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    with tempfile.TemporaryDirectory() as folder:
        scene.render.filepath = str(Path(folder) / "frame.png")
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(scene.render.filepath)
        pixels = np.array(image.pixels[:]).reshape(-1, 4)
        bpy.data.images.remove(image)
    covered = float((pixels[:, 3] > 0).mean())
    spread = float(pixels[pixels[:, 3] > 0, :3].std()) if covered else 0.0
    check(covered > 0.05 and spread > 0.01,
          f"frame {frame}: the Workbench render is empty ({covered:.0%} of the pixels drawn, "
          f"colour spread {spread:.3f})")
    print(f"blender usd: frame {frame} renders in Workbench (64x48: {covered:.0%} of the pixels "
          f"drawn, colour spread {spread:.3f})")


def crack_look(scene, out, frames):
    """At the frame with the most crack faces (per surface/NNNN.glb), the imported surface's
    crack faces carry the crack look, as Blender renders them: a Cycles render of the surface
    (crack_render) shows crack-coloured pixels; the face attribute `crack` (from the primvar)
    marks the crack faces; every material of the surface takes its Base Color from the colour
    attribute `displayColor` (an Attribute node, from the UsdPrimvarReader_float3), which is
    the crack material's colour on crack faces and the surface material's elsewhere.
    Blender applies GeomSubsets once, at import, so without the primvar the faces that crack
    after frame 1 stay the surface's colour: the render of such a cache had no crack colour."""
    counts = [read_glb_crack(out / "surface" / f"{k:04}.glb")[1:] for k in range(1, frames + 1)]
    frame = max(range(1, frames + 1), key=lambda k: (counts[k - 1][1], k))
    surface_faces, crack_faces = counts[frame - 1]
    if crack_faces == 0:
        print("blender usd: no frame has crack faces; the crack look is not checked")
        return
    obj = scene.objects["Surface"]
    crack_render(scene, obj, frame, surface_faces, crack_faces)
    scene.frame_set(frame)
    materials = {slot.material.name: slot.material for slot in obj.material_slots if slot.material}
    check({"surface", "crack"} <= set(materials), f"the surface's materials are {sorted(materials)}")
    colour = {name: np.array(materials[name].diffuse_color[:3]) for name in ("surface", "crack")}
    check(np.abs(colour["crack"] - colour["surface"]).max() > 0.1,
          f"the crack and surface materials have one colour {colour['crack']}")
    # The attributes of the evaluated mesh (the mesh cache modifier's, at this frame).
    ev = obj.evaluated_get(bpy.context.evaluated_depsgraph_get())
    mesh = ev.to_mesh()
    names = set(mesh.attributes.keys())
    check("crack" in names, f"frame {frame}: the surface has no face attribute crack ({sorted(names)})")
    check("damage" in names and mesh.attributes["damage"].domain == "POINT",
          f"frame {frame}: the surface has no vertex attribute damage ({sorted(names)})")
    flag = np.empty(len(mesh.polygons), dtype=np.int32)
    mesh.attributes["crack"].data.foreach_get("value", flag)
    expected = np.repeat([0, 1], [surface_faces, crack_faces])
    check(np.array_equal(flag, expected),
          f"frame {frame}: the face attribute crack marks {int(flag.sum())} of {len(flag)} faces, "
          f"the .glb has {crack_faces} crack faces of {surface_faces + crack_faces}")
    for material in materials.values():
        nodes = material.node_tree.nodes if material.node_tree else []
        bsdf = next((n for n in nodes if n.bl_idname == "ShaderNodeBsdfPrincipled"), None)
        check(bsdf is not None, f"material {material.name} has no Principled BSDF")
        base = bsdf.inputs["Base Color"]
        source = base.links[0].from_node if base.is_linked else None
        check(source is not None and source.bl_idname == "ShaderNodeAttribute",
              f"material {material.name}: its Base Color is {'a constant' if source is None else source.bl_idname}, "
              f"not read from an attribute of the mesh")
        check(source.attribute_name in names,
              f"material {material.name} reads the attribute {source.attribute_name!r}, which the mesh lacks")
        attribute = mesh.attributes[source.attribute_name]
        values = np.empty(len(attribute.data) * 4)
        attribute.data.foreach_get("color", values)
        values = values.reshape(-1, 4)[:, :3]
        # Per corner (Blender's domain for USD's uniform colours): the face of each corner.
        if attribute.domain == "CORNER":
            corners = np.empty(len(mesh.polygons), dtype=np.int64)
            mesh.polygons.foreach_get("loop_total", corners)
            per_face_flag = np.repeat(flag, corners)
        else:
            check(attribute.domain == "FACE", f"attribute {attribute.name} on the {attribute.domain} domain")
            per_face_flag = flag
        want = np.where(per_face_flag[:, None] == 1, colour["crack"], colour["surface"])
        err = float(np.abs(values - want).max())
        check(err < 1e-6, f"frame {frame}: material {material.name}'s colour ({source.attribute_name}) is off the "
              f"crack colour on crack faces, the surface colour elsewhere, by {err}")
    ev.to_mesh_clear()
    print(f"blender usd: frame {frame}: the face attribute crack marks the {crack_faces} crack faces (and the "
          f"vertices carry damage); the materials {sorted(materials)} colour them from the attribute "
          f"displayColor (the crack colour there)")


def camera_rays(scene, camera, width, height):
    """(origin, directions (height, width, 3)) of the rays through the pixel centres of
    `camera`, rows from the bottom as in Blender's images."""
    frame = [np.array(v) for v in camera.data.view_frame(scene=scene)]
    top_right, bottom_right, bottom_left, top_left = frame
    u = (np.arange(width) + 0.5) / width
    v = (np.arange(height) + 0.5) / height
    bottom = bottom_left[None, :] + u[:, None] * (bottom_right - bottom_left)[None, :]
    top = top_left[None, :] + u[:, None] * (top_right - top_left)[None, :]
    local = bottom[None, :, :] + v[:, None, None] * (top - bottom)[None, :, :]
    m = np.array(camera.matrix_world)
    return m[:3, 3], local @ m[:3, :3].T


def faces_seen(scene, obj, camera, width, height):
    """The face of `obj` (evaluated) each pixel centre of `camera` sees, -1 for none
    (rows from the bottom)."""
    from mathutils import Vector
    from mathutils.bvhtree import BVHTree

    depsgraph = bpy.context.evaluated_depsgraph_get()
    tree = BVHTree.FromObject(obj, depsgraph)
    inverse = np.array(obj.matrix_world.inverted())
    origin, directions = camera_rays(scene, camera, width, height)
    origin = Vector(inverse[:3, :3] @ origin + inverse[:3, 3])
    directions = directions @ inverse[:3, :3].T
    seen = np.full((height, width), -1)
    for j in range(height):
        for i in range(width):
            hit = tree.ray_cast(origin, Vector(directions[j, i]))
            if hit[2] is not None:
                seen[j, i] = hit[2]
    return seen


def crack_render(scene, obj, frame, surface_faces, crack_faces):
    """Renders `obj` alone at `frame` in Cycles (128x96, 16 samples, seed 0, a white sky),
    from the side of it (of four) that shows the most crack faces, and checks the pixels
    whose neighbourhood sees only crack faces (by ray casts; the faces after the first
    `surface_faces`) have the crack colour, and those that see only original faces do not.
    Cracks enclosed by the surface cannot show: then this is said, not checked."""
    from mathutils import Vector

    scene.frame_set(frame)
    hidden = {o.name: o.hide_render for o in scene.objects}
    for o in scene.objects:
        o.hide_render = o is not obj
    corners = [obj.matrix_world @ Vector(c) for c in obj.bound_box]
    centre = sum(corners, Vector()) / len(corners)
    size = max(max((c - centre).length for c in corners), 0.05)
    camera = bpy.data.objects.new("crack_camera", bpy.data.cameras.new("crack_camera"))
    scene.collection.objects.link(camera)
    scene.camera = camera
    width, height = 128, 96

    def aim(side):
        camera.location = centre + Vector(side).normalized() * size * 3
        camera.rotation_euler = (centre - camera.location).to_track_quat("-Z", "Y").to_euler()
        bpy.context.view_layer.update()

    sides = [(1.0, -1.5, 0.5), (-1.0, -1.5, 0.5), (-1.0, 1.5, 0.5), (1.0, 1.5, 0.5)]
    best = []
    for side in sides:
        aim(side)
        best.append(((faces_seen(scene, obj, camera, 32, 24) >= surface_faces).sum(), side))
    aim(max(best)[1])
    seen = faces_seen(scene, obj, camera, width, height)
    world = bpy.data.worlds.new("crack_sky")
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1.0, 1.0, 1.0, 1.0)
    scene.world = world
    scene.render.engine = "CYCLES"
    scene.cycles.device = "CPU"
    scene.cycles.samples = 16
    scene.cycles.seed = 0
    scene.cycles.use_denoising = False
    scene.render.resolution_x, scene.render.resolution_y = width, height
    scene.render.resolution_percentage = 100
    scene.render.film_transparent = True
    scene.view_settings.view_transform = "Standard"
    with tempfile.TemporaryDirectory() as folder:
        scene.render.filepath = str(Path(folder) / "crack.png")
        bpy.ops.render.render(write_still=True)
        image = bpy.data.images.load(scene.render.filepath)
        pixels = np.array(image.pixels[:]).reshape(height, width, 4)
        bpy.data.images.remove(image)
    for o in scene.objects:
        o.hide_render = hidden.get(o.name, o.hide_render)
    # A pixel is a crack pixel when it and its eight neighbours see crack faces (so
    # the filter's blend across edges stays out), a surface pixel likewise.
    crack = seen >= surface_faces
    original = (seen >= 0) & ~crack
    inner = (slice(1, -1), slice(1, -1))

    def all_around(mask):
        out = np.zeros_like(mask)
        out[inner] = np.all([np.roll(np.roll(mask, dj, 0), di, 1)[inner]
                             for dj in (-1, 0, 1) for di in (-1, 0, 1)], axis=0)
        return out

    rgb = pixels[:, :, :3]
    # Hue, not brightness: (r - b) / r is ~0.4 for the ochre crack colour and ~0 for the
    # grey surface colour however lit (sRGB values).
    warmth = (rgb[:, :, 0] - rgb[:, :, 2]) / np.maximum(rgb[:, :, 0], 1e-6)
    crack_pixels, surface_pixels = all_around(crack), all_around(original)
    if crack_pixels.sum() < 10:
        print(f"blender usd: frame {frame}: the {crack_faces} crack faces are hidden by the surface from "
              f"every side ({int(crack_pixels.sum())} pixels); their colour is not checked in a render")
        return
    warm = float((warmth[crack_pixels] > 0.2).mean())
    grey = float((warmth[surface_pixels] < 0.08).mean())
    check(warm > 0.9,
          f"frame {frame}: of the {int(crack_pixels.sum())} pixels of the Cycles render that show crack "
          f"faces, {warm:.0%} have the crack colour: the crack faces do not carry the crack look")
    check(grey > 0.9, f"frame {frame}: of the {int(surface_pixels.sum())} pixels that show the original "
          f"surface, {grey:.0%} have its colour")
    print(f"blender usd: frame {frame} renders in Cycles (128x96) with the crack look: {warm:.0%} of the "
          f"{int(crack_pixels.sum())} pixels that show crack faces have the crack colour, {grey:.0%} of the "
          f"{int(surface_pixels.sum())} that show the surface its colour")


def main(out):
    out = Path(out)
    scene_toml = tomllib.loads((out / "scene.toml").read_text())
    playback_fps = scene_toml["output"]["playback_fps"]
    frames = len(list((out / "particles").glob("[0-9][0-9][0-9][0-9].ply")))
    manifest = json.loads((out / "manifest.json").read_text())
    mesh_colliders = sorted(int(p.stem[len("mesh_"):]) for p in (out / "colliders").glob("mesh_*.ply"))

    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    default_fps = scene.render.fps / scene.render.fps_base
    bpy.ops.wm.usd_import(filepath=str(out / "cache.usd"), set_frame_range=True)
    check((scene.frame_start, scene.frame_end) == (1, frames),
          f"Blender frame range {scene.frame_start}..{scene.frame_end}, expected 1..{frames}")
    # Blender 5.0's USD importer shows time code k at scene frame k whatever the scene's
    # rate, and leaves the rate as it was (a stage written by usd-core itself with
    # framesPerSecond = 25 imports at 24 too), so the README tells artists to set it
    # to the stage's framesPerSecond, as done here. The frames below then play at
    # playback_fps, frame k showing cache frame k.
    fps = scene.render.fps / scene.render.fps_base
    check(fps == default_fps, f"the USD import changed the scene's rate to {fps}")
    scene.render.fps = round(playback_fps)
    scene.render.fps_base = round(playback_fps) / playback_fps
    fps = scene.render.fps / scene.render.fps_base
    check(abs(fps - playback_fps) < 1e-9, f"Blender plays at {fps} fps, expected {playback_fps}")
    print(f"blender usd: frame range 1..{frames}, time code k at frame k; the rate set to the "
          f"stage's {playback_fps} fps (the importer left it at {default_fps})")

    objects = {o.name: o for o in scene.objects}
    print("blender usd: objects", sorted(objects))
    clouds = [o for o in objects.values() if o.type == "POINTCLOUD"]
    check(len(clouds) == 1, "one point cloud (the particles)")
    cloud_obj = clouds[0]

    for frame in (1, frames):
        scene.frame_set(frame)
        # Particles.
        ply = read_ply(out / "particles" / f"{frame:04}.ply")
        expected = y_up_to_blender(np.stack([ply["x"], ply["y"], ply["z"]], axis=1))
        pos, cloud = evaluated_points(cloud_obj)
        err = worst(pos, expected)
        check(err <= allowed(expected), f"frame {frame}: points off by {err} m")
        names = set(cloud.attributes.keys())
        check({"damage", "fragment"} <= names, f"the point cloud's attributes are {sorted(names)}")
        damage = np.empty(len(cloud.points))
        cloud.attributes["damage"].data.foreach_get("value", damage)
        check(np.allclose(damage, ply["damage"], atol=1e-7), f"frame {frame}: damage differs")
        # Meshes, where the cache has surfaces (a particles-only cache has none).
        glb = read_glb(out / "surface" / f"{frame:04}.glb") if (out / "surface").is_dir() else []
        if "Surface" in objects:
            check(len(glb) == 1, f"frame {frame}: a Surface on the stage, {len(glb)} meshes in the .glb")
            [(_, p, _)] = glb
            err = worst(evaluated_vertices(objects["Surface"]), y_up_to_blender(p))
            check(err <= allowed(p), f"frame {frame}: crack surface off by {err} m from the .glb")
        else:
            for name, p, _ in glb:
                obj = objects.get(name.replace(" ", "_"))
                check(obj is not None, f"frame {frame}: no object for {name}")
                err = worst(evaluated_vertices(obj), y_up_to_blender(p))
                check(err <= allowed(p), f"frame {frame}: {name} off by {err} m from the .glb")
        print(f"blender usd: frame {frame} points within {TOLERANCE} m of the PLY, meshes of the .glb, "
              f"point attributes {sorted(names - {'position'})}")
    # Colliders: Blender 5.0 makes each collider's Xform and its child one object, named
    # after the child, which carries the collider's name: `ground` (the only ground
    # plane), else the kind and the scene index.
    kinds = [c["type"] for c in scene_toml.get("collider", [])]
    expected = [("ground" if kind == "ground" and kinds.count("ground") == 1 else f"{kind}_{i}")
                for i, kind in enumerate(kinds)]
    missing = [name for name in expected if name not in objects]
    check(not missing, f"no Blender objects named {missing} (objects: {sorted(objects)})")
    if expected:
        print(f"blender usd: the colliders are objects named {expected}")
    # Mesh colliders are also found by their vertices: the one mesh object with the
    # PLY's vertices posed as the manifest says at frame 1, then N, must be mesh_N.
    for index in mesh_colliders:
        count = len(read_collider(out / "colliders" / f"mesh_{index}.ply")[0])
        scene.frame_set(1)
        expected = y_up_to_blender(posed_collider(out, manifest, index, 1))
        found = [o for o in scene.objects if o.type == "MESH" and o.name != "Surface"
                 and worst(evaluated_vertices(o), expected) <= TOLERANCE]
        check([o.name for o in found] == [f"mesh_{index}"], f"mesh_{index}: objects "
              f"{[o.name for o in found]} (of {sorted(o.name for o in scene.objects)}) with its "
              f"{count} vertices posed at frame 1")
        scene.frame_set(frames)
        got = evaluated_vertices(found[0])
        err = worst(got, y_up_to_blender(posed_collider(out, manifest, index, frames)))
        check(err <= TOLERANCE, f"frame {frames}: mesh_{index} off by {err} m")
        if RESTS:
            pos, _ = evaluated_points(cloud_obj)
            top, lowest = got[:, 2].max(), pos[:, 2].min()
            spacing = max(b["resolution"] for b in scene_toml["body"])
            check(-0.1 * spacing <= lowest - top <= spacing,
                  f"frame {frames}: the lowest particle (z = {lowest}) is not on mesh_{index}'s top (z = {top})")
        print(f"blender usd: mesh collider mesh_{index} (object {found[0].name}, {count} vertices) posed "
              f"as the manifest says at frames 1 and {frames}"
              + (f"; the lowest particle {lowest - top:.4f} m above its top" if RESTS else ""))
    # One coordinate system: every imported object under the same y-up -> z-up rotation.
    rotation = Matrix.Rotation(np.pi / 2, 4, "X")
    for obj in scene.objects:
        if obj.parent is None:
            diff = np.abs(np.array(obj.matrix_world) - np.array(rotation)).max()
            check(diff < 1e-6 or np.abs(np.array(obj.matrix_world) - np.eye(4)).max() < 1e-6,
                  f"{obj.name}: unexpected root transform {obj.matrix_world}")
    volumes = [o for o in scene.objects if o.type == "VOLUME"]
    for vol in volumes:
        scene.frame_set(frames)
        path = vol.data.filepath
        check(path.endswith(".vdb"), f"volume {vol.name} file {path}")
        print(f"blender usd: volume {vol.name} reads {path} (sequence: {vol.data.is_sequence})")
    print(f"blender usd: {len(scene.objects)} objects in one coordinate system")
    render(scene, frames)
    if "Surface" in objects:
        crack_look(scene, out, frames)

    animated = out / "surface" / "animated.glb"
    if animated.exists():
        bpy.ops.wm.read_factory_settings(use_empty=True)
        scene = bpy.context.scene
        scene.render.fps = round(playback_fps)
        scene.render.fps_base = round(playback_fps) / playback_fps
        bpy.ops.import_scene.gltf(filepath=str(animated))
        obj = next(o for o in scene.objects if o.type == "MESH" and o.data.shape_keys)
        keys = obj.data.shape_keys.key_blocks
        names = [k.name for k in keys][1:]
        check(names == [f"frame_{k:04}" for k in range(1, frames + 1)], f"shape keys {names[:3]}...")
        action = obj.data.shape_keys.animation_data.action
        start, end = action.frame_range
        check(round(start) == 1 and round(end) == frames, f"animation keyed over {start}..{end}")
        import struct
        data = animated.read_bytes()
        n = struct.unpack_from("<I", data, 12)[0]
        doc = json.loads(data[20:20 + n])
        # The surface is the first mesh; mesh colliders follow.
        (_, base, _) = read_glb(animated)[0]
        for frame in range(1, frames + 1):
            scene.frame_set(frame)
            on = [k.name for k in keys[1:] if k.value > 0.5]
            check(on == [f"frame_{frame:04}"], f"frame {frame}: shape keys on {on}")
            # The vertices are base + this frame's target (an independent read of the file).
            target = doc["meshes"][0]["primitives"][0]["targets"][frame - 1]["POSITION"]
            a = doc["accessors"][target]
            view = doc["bufferViews"][a["bufferView"]]
            blob = data[20 + n + 8:]
            delta = np.frombuffer(blob, "<f4", a["count"] * 3, view.get("byteOffset", 0)).reshape(-1, 3)
            expected = y_up_to_blender(base + delta)
            # Blender's glTF importer renumbers the vertices of a mesh whose primitives
            # share them, so the vertices are compared as sets.
            got = evaluated_vertices(obj)
            err = worst_unordered(got, expected)
            check(err <= TOLERANCE, f"frame {frame}: animated.glb off by {err} m")
        print(f"blender gltf: animated.glb frames 1..{frames} each show their own cache frame "
              f"(shape key frame_NNNN, within {TOLERANCE} m)")
        for index in mesh_colliders:
            node = scene.objects.get(f"mesh_{index}")
            check(node is not None and node.type == "MESH",
                  f"animated.glb: no mesh object mesh_{index} in {sorted(o.name for o in scene.objects)}")
            for frame in range(1, frames + 1):
                scene.frame_set(frame)
                expected = y_up_to_blender(posed_collider(out, manifest, index, frame))
                err = worst_unordered(evaluated_vertices(node), expected)
                check(err <= TOLERANCE, f"frame {frame}: mesh_{index} in animated.glb off by {err} m")
            print(f"blender gltf: mesh collider mesh_{index} posed as the manifest says at frames 1..{frames}")
    print("blender_check: all checks passed")


if __name__ == "__main__":
    main([a for a in sys.argv[1:] if not a.startswith("--")][-1])
