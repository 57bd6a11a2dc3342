"""Checks OUT/cache.usd with Pixar's own library (PyPI usd-core), independently of
perifrac's writer: the validator (UsdUtils.ComplianceChecker) finds no errors, the stage
metadata give the axes, units and playback time base, and every time sample equals the
cache files it was made of (particles/NNNN.ply read by a PLY parser written here,
surface/NNNN.glb by a glTF parser written here, colliders/mesh_N.ply likewise), mesh
colliders posed at every frame as manifest.json says. Also reads tets/tets.pvd and each of
its .vtu files with meshio. With --rests-on-colliders, also that the lowest particle of the
last frame lies on the top of a mesh collider (within -0.1 and 1 particle spacing λ).
Exit code 0 when all holds; prints what it checked.

usage: python usd_check.py OUT [--rests-on-colliders]
"""

import json
import struct
import sys
import tomllib
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
from pxr import Usd, UsdGeom, UsdShade, UsdUtils, UsdVol, Vt


def read_ply(path):
    """Binary little-endian float PLY: {column: np.array}."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert header[1] == "format binary_little_endian 1.0", header[1]
    count, names = 0, []
    for line in header:
        words = line.split()
        if words[:2] == ["element", "vertex"]:
            count = int(words[2])
        elif words[:1] == ["property"]:
            assert words[1] == "float", line
            names.append(words[2])
    values = np.frombuffer(data[end:], dtype="<f4", count=count * len(names))
    values = values.reshape(count, len(names))
    return {n: values[:, i] for i, n in enumerate(names)}


def read_collider(path):
    """(positions (n,3) f4, triangles (m,3), pivot) of a colliders/mesh_N.ply: float x y z,
    then faces as a uchar count and uint indices."""
    data = path.read_bytes()
    end = data.index(b"end_header\n") + len(b"end_header\n")
    header = data[:end].decode("ascii").splitlines()
    assert header[1] == "format binary_little_endian 1.0", header[1]
    counts, pivot = {}, None
    for line in header:
        words = line.split()
        if words[:1] == ["element"]:
            counts[words[1]] = int(words[2])
        elif words[:2] == ["comment", "pivot"]:
            pivot = [float(w) for w in words[2:]]
    n, m = counts["vertex"], counts["face"]
    positions = np.frombuffer(data, "<f4", n * 3, end).reshape(n, 3)
    faces = np.frombuffer(data, np.dtype([("k", "u1"), ("i", "<u4", 3)]), m, end + 12 * n)
    assert (faces["k"] == 3).all(), "faces are triangles"
    return positions, faces["i"].astype(np.int64), pivot


def rotate(q, p):
    """Points p (n,3) rotated by the unit quaternion q = [x, y, z, w]."""
    x, y, z, w = q
    r = np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])
    return np.asarray(p, "f8") @ r.T


def posed_collider(out, manifest, index, frame):
    """The world points of mesh collider `index` at `frame`, from its PLY and the manifest."""
    positions, _, _ = read_collider(out / "colliders" / f"mesh_{index}.ply")
    centre = manifest["collider_centers"][frame - 1][index]
    return rotate(manifest["collider_rotations"][frame - 1][index], positions) + centre


def read_glb(path):
    """[(mesh name, positions (n,3), triangles (m,3) surface then crack)] of a .glb."""
    data = path.read_bytes()
    assert data[:4] == b"glTF"
    json_len = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20 : 20 + json_len])
    bin_start = 20 + json_len + 8
    blob = data[bin_start:]

    def accessor(i, dtype, width):
        a = doc["accessors"][i]
        view = doc["bufferViews"][a["bufferView"]]
        offset = view.get("byteOffset", 0) + a.get("byteOffset", 0)
        n = a["count"] * width
        return np.frombuffer(blob, dtype=dtype, count=n, offset=offset).reshape(a["count"], width)

    materials = [m.get("name") for m in doc.get("materials", [])]
    meshes = []
    for mesh in doc.get("meshes", []):
        positions, surface, crack = None, [], []
        for prim in mesh["primitives"]:
            positions = accessor(prim["attributes"]["POSITION"], "<f4", 3)
            tris = accessor(prim["indices"], "<u4", 1).reshape(-1, 3)
            crack_prim = "material" in prim and materials[prim["material"]] == "crack"
            (crack if crack_prim else surface).append(tris)
        tris = np.concatenate(surface + crack) if surface + crack else np.zeros((0, 3), "u4")
        meshes.append((mesh.get("name", ""), positions, tris))
    return meshes


def read_glb_face_counts(path):
    """[(mesh name, surface triangles, crack triangles)] of a .glb."""
    data = path.read_bytes()
    json_len = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20 : 20 + json_len])
    materials = [m.get("name") for m in doc.get("materials", [])]
    meshes = []
    for mesh in doc["meshes"]:
        counts = {"surface": 0, "crack": 0}
        for prim in mesh["primitives"]:
            crack_prim = "material" in prim and materials[prim["material"]] == "crack"
            counts["crack" if crack_prim else "surface"] += doc["accessors"][prim["indices"]]["count"] // 3
        meshes.append((mesh.get("name", ""), counts["surface"], counts["crack"]))
    return meshes


def read_glb_crack(path):
    """(mesh name, surface triangles, crack triangles) of a one-mesh .glb."""
    [mesh] = read_glb_face_counts(path)
    return mesh


def read_glb_colours(path):
    """{material name: base colour (r, g, b)} of a .glb."""
    data = path.read_bytes()
    json_len = struct.unpack_from("<I", data, 12)[0]
    doc = json.loads(data[20 : 20 + json_len])
    return {m.get("name"): np.array(m["pbrMetallicRoughness"]["baseColorFactor"][:3], "f4")
            for m in doc.get("materials", [])}


def check_looks(stage, colours):
    """Each of /World/Looks/surface and /World/Looks/crack: a UsdPreviewSurface whose
    diffuseColor reads the primvar displayColor (a UsdPrimvarReader_float3, falling back to
    the look's colour, the .glb material's) and keeps that colour as its value."""
    for name in ("surface", "crack"):
        material = UsdShade.Material(stage.GetPrimAtPath(f"/World/Looks/{name}"))
        check(material, f"no material /World/Looks/{name}")
        shader = material.ComputeSurfaceSource()[0]
        check(shader and shader.GetIdAttr().Get() == "UsdPreviewSurface",
              f"Looks/{name}: the surface is not a UsdPreviewSurface")
        diffuse = shader.GetInput("diffuseColor")
        # The vdb method's .glb files have no materials: the look's own colour then.
        colours.setdefault(name, np.array(diffuse.Get(), "f4"))
        check(np.allclose(diffuse.Get(), colours[name], atol=1e-6, rtol=0),
              f"Looks/{name}: diffuseColor {diffuse.Get()} is not the .glb's {colours[name]}")
        sources = diffuse.GetConnectedSources()[0]
        check(len(sources) == 1, f"Looks/{name}: diffuseColor is not connected to a primvar reader")
        reader = UsdShade.Shader(sources[0].source.GetPrim())
        check(reader.GetIdAttr().Get() == "UsdPrimvarReader_float3"
              and reader.GetInput("varname").Get() == "displayColor"
              and np.allclose(reader.GetInput("fallback").Get(), colours[name], atol=1e-6, rtol=0),
              f"Looks/{name}: diffuseColor comes from {reader.GetPath()}, not a UsdPrimvarReader_float3 "
              f"of displayColor falling back to the look's colour")
    print("looks: surface and crack read the primvar displayColor (UsdPrimvarReader_float3)")


def check_face_looks(mesh, k, surface_faces, crack_faces, colours, what):
    """The per-face primvars of `mesh` at frame k: crack = 0 on the first `surface_faces`
    faces and 1 on the `crack_faces` after them; displayColor the .glb's surface and crack
    colours on them."""
    pv = UsdGeom.PrimvarsAPI(mesh)
    flag, colour = pv.GetPrimvar("crack"), pv.GetPrimvar("displayColor")
    check(flag.GetInterpolation() == "uniform" and colour.GetInterpolation() == "uniform",
          f"{what}: primvars crack and displayColor are not per face (uniform)")
    expected = np.repeat([0, 1], [surface_faces, crack_faces])
    check(np.array_equal(np.array(flag.Get(k)), expected),
          f"frame {k}: {what}'s primvar crack is not 1 on its {crack_faces} crack faces only")
    got = np.array(colour.ComputeFlattened(k), "f4").reshape(-1, 3)
    want = np.where(expected[:, None] == 1, colours["crack"], colours["surface"])
    check(got.shape == want.shape and np.allclose(got, want, atol=1e-6, rtol=0),
          f"frame {k}: {what}'s displayColor is not the crack colour on crack faces, the surface "
          f"colour elsewhere")


def check(condition, message):
    if not condition:
        print("FAILED:", message)
        sys.exit(1)


def main(out):
    out = Path(out)
    stage_path = out / "cache.usd"
    scene = tomllib.loads((out / "scene.toml").read_text())
    manifest = json.loads((out / "manifest.json").read_text())
    playback_fps = scene["output"]["playback_fps"]
    frames = len(manifest["frame_times"])

    # The binary format (usdc), not text.
    check(stage_path.read_bytes()[:8] == b"PXR-USDC", "cache.usd is not a usdc crate file")

    if hasattr(UsdUtils, "ComplianceChecker"):
        checker = UsdUtils.ComplianceChecker(verbose=False)
        checker.CheckCompliance(str(stage_path))
        errors = checker.GetErrors() + checker.GetFailedChecks()
        warnings = checker.GetWarnings()
        name = "ComplianceChecker"
    else:
        # usd-core 25.x and later: ComplianceChecker gave way to the UsdValidation
        # framework (what usdchecker runs), every registered validator.
        from pxr import UsdValidation

        registry = UsdValidation.ValidationRegistry()
        context = UsdValidation.ValidationContext(registry.GetOrLoadAllValidators())
        found = context.Validate(Usd.Stage.Open(str(stage_path)))
        kind = UsdValidation.ValidationErrorType
        errors = [e.GetMessage() for e in found if e.GetType() == kind.Error]
        warnings = [e.GetMessage() for e in found if e.GetType() != kind.Error]
        name = "UsdValidation"
    for w in warnings:
        print(f"{name} warning:", w)
    check(not errors, f"{name}: errors {errors}")
    print(f"{name}: no errors ({len(warnings)} warnings)")

    stage = Usd.Stage.Open(str(stage_path))
    check(UsdGeom.GetStageUpAxis(stage) == UsdGeom.Tokens.y, "upAxis is not Y")
    check(UsdGeom.GetStageMetersPerUnit(stage) == 1.0, "metersPerUnit is not 1")
    check(stage.GetStartTimeCode() == 1 and stage.GetEndTimeCode() == frames,
          f"time codes {stage.GetStartTimeCode()}..{stage.GetEndTimeCode()}, expected 1..{frames}")
    check(stage.GetTimeCodesPerSecond() == playback_fps and stage.GetFramesPerSecond() == playback_fps,
          "timeCodesPerSecond / framesPerSecond differ from [output] playback_fps")
    custom = stage.GetRootLayer().customLayerData["perifrac"]
    check(list(custom["simulation_times"]) == manifest["frame_times"],
          "customLayerData perifrac.simulation_times differ from the manifest's frame_times")
    print(f"stage: Y up, 1 m a unit, time codes 1..{frames} at {playback_fps} fps, simulation times kept")

    # Particles, frame for frame.
    points = UsdGeom.Points(stage.GetPrimAtPath("/World/Particles"))
    check(points, "no /World/Particles Points prim")
    times = points.GetPointsAttr().GetTimeSamples()
    check(times == [float(k) for k in range(1, frames + 1)], f"points time samples {times}")
    scale = playback_fps / manifest["fps"]
    pv = UsdGeom.PrimvarsAPI(points)
    for k in range(1, frames + 1):
        ply = read_ply(out / "particles" / f"{k:04}.ply")
        pos = np.array(points.GetPointsAttr().Get(k), dtype="f4")
        expected = np.stack([ply["x"], ply["y"], ply["z"]], axis=1)
        check(np.array_equal(pos, expected), f"frame {k}: points differ from the PLY")
        vel = np.array(points.GetVelocitiesAttr().Get(k), dtype="f4")
        sim = np.stack([ply["vx"], ply["vy"], ply["vz"]], axis=1)
        check(np.allclose(vel, sim * np.float32(scale), rtol=1e-6, atol=0),
              f"frame {k}: velocities are not the simulation ones x playback_fps/fps")
        check(np.array_equal(np.array(pv.GetPrimvar("simulation_velocity").Get(k), "f4"), sim),
              f"frame {k}: simulation_velocity differs")
        for name in ["damage", "plastic"]:
            check(np.array_equal(np.array(pv.GetPrimvar(name).Get(k), "f4"), ply[name]),
                  f"frame {k}: {name} differs")
        for name in ["fragment", "material"]:
            check(np.array_equal(np.array(pv.GetPrimvar(name).Get(k)), ply[name].astype(int)),
                  f"frame {k}: {name} differs")
        check(len(points.GetIdsAttr().Get(k)) == len(pos) and len(points.GetWidthsAttr().Get(k)) == len(pos),
              f"frame {k}: ids / widths are not one a point")
        if "volume" in ply:
            # Each particle drawn at its own size, the cube root of its volume.
            widths = np.array(points.GetWidthsAttr().Get(k), "f8")
            check(np.allclose(widths, np.cbrt(ply["volume"].astype("f8")), rtol=1e-6, atol=0),
                  f"frame {k}: widths are not the cube roots of the particles' volumes")
        standard = {"x", "y", "z", "vx", "vy", "vz", "damage", "plastic", "material", "fragment"}
        for name in set(ply) - standard:
            check(np.array_equal(np.array(pv.GetPrimvar(name).Get(k), "f4"), ply[name]),
                  f"frame {k}: extra column {name} differs")
    print(f"particles: {frames} frames equal the PLY files (points, velocities, primvars)")
    points_at_last = np.array(points.GetPointsAttr().Get(frames), dtype="f8")

    # Surfaces.
    surface = stage.GetPrimAtPath("/World/Surface")
    if surface or stage.GetPrimAtPath("/World/Fragments"):
        colours = read_glb_colours(out / "surface" / "0001.glb")
        check_looks(stage, colours)
    if surface:
        mesh = UsdGeom.Mesh(surface)
        subsets = UsdGeom.Subset.GetGeomSubsets(mesh)
        check(sorted(s.GetPrim().GetName() for s in subsets) == ["crack", "surface"], "subsets")
        for k in range(1, frames + 1):
            [(_, pos, tris)] = read_glb(out / "surface" / f"{k:04}.glb")
            check(np.array_equal(np.array(mesh.GetPointsAttr().Get(k), "f4"), pos),
                  f"frame {k}: surface points differ from the .glb")
            check(np.array_equal(np.array(mesh.GetFaceVertexIndicesAttr().Get(k)), tris.reshape(-1)),
                  f"frame {k}: surface triangles differ from the .glb")
            # A partition of the frame's faces, checked here: usd-core 26.11's
            # UsdGeom.Subset.ValidateSubsets crashes (SIGSEGV) on time-sampled indices,
            # its own stages' too.
            check(UsdGeom.Subset.GetFamilyType(mesh, "materialBind") == UsdGeom.Tokens.partition,
                  "the materialBind family is not a partition")
            faces = np.concatenate([np.array(s.GetIndicesAttr().Get(k), dtype=int) for s in subsets])
            check(np.array_equal(np.sort(faces), np.arange(len(tris))),
                  f"frame {k}: the subsets are not a partition of the {len(tris)} faces")
            crack = UsdGeom.Subset(stage.GetPrimAtPath("/World/Surface/crack"))
            crack_faces = np.array(crack.GetIndicesAttr().Get(k), dtype=int)
            _, surface_tris, crack_tris = read_glb_crack(out / "surface" / f"{k:04}.glb")
            check(len(crack_faces) == crack_tris, f"frame {k}: {len(crack_faces)} crack faces, the .glb has {crack_tris}")
            check_face_looks(mesh, k, surface_tris, crack_tris, colours, "the surface")
        print(f"embedded surface: {frames} frames equal surface/NNNN.glb, subsets valid; per face, "
              f"the primvar crack marks the crack faces and displayColor gives them the crack colour")
    fragments = stage.GetPrimAtPath("/World/Fragments")
    if fragments:
        for k in range(1, frames + 1):
            glb = {name.replace(" ", "_"): (p, t) for name, p, t in read_glb(out / "surface" / f"{k:04}.glb")}
            faces = {name.replace(" ", "_"): (surface, crack)
                     for name, surface, crack in read_glb_face_counts(out / "surface" / f"{k:04}.glb")}
            for child in fragments.GetChildren():
                visible = UsdGeom.Imageable(child).ComputeVisibility(k) != UsdGeom.Tokens.invisible
                check(visible == (child.GetName() in glb), f"frame {k}: visibility of {child.GetName()}")
                if visible:
                    p, t = glb[child.GetName()]
                    m = UsdGeom.Mesh(child)
                    check(np.array_equal(np.array(m.GetPointsAttr().Get(k), "f4"), p), f"frame {k}: {child.GetName()}")
                    check_face_looks(m, k, *faces[child.GetName()], colours, child.GetName())
        print(f"fragments: {len(fragments.GetChildren())} meshes equal surface/NNNN.glb, with the "
              f"per-face primvars crack and displayColor")
    volume = stage.GetPrimAtPath("/World/Volume")
    if volume:
        vol = UsdVol.Volume(volume)
        fields = vol.GetFieldPaths()
        check(set(fields) == {"surface", "v"}, f"volume fields {fields}")
        for name, path in fields.items():
            asset = UsdVol.OpenVDBAsset(stage.GetPrimAtPath(path))
            for k in (1, frames):
                file = asset.GetFilePathAttr().Get(k).resolvedPath
                check(Path(file).resolve() == (out / "vdb" / f"{k:04}.vdb").resolve(),
                      f"frame {k}: field {name} points at {file}")
        print("volume: fields surface and v point at vdb/NNNN.vdb")
    colliders = stage.GetPrimAtPath("/World/Colliders")
    if colliders:
        for i, child in enumerate(colliders.GetChildren()):
            ops = UsdGeom.Xformable(child).GetOrderedXformOps()
            for k in range(1, frames + 1):
                centre = manifest["collider_centers"][k - 1][i]
                check(np.allclose(ops[0].Get(k), centre, atol=0, rtol=1e-12), f"collider {i} frame {k}")
                if "collider_rotations" in manifest:
                    x, y, z, w = manifest["collider_rotations"][k - 1][i]
                    q = ops[1].Get(k)
                    check(ops[1].GetOpType() == UsdGeom.XformOp.TypeOrient
                          and np.allclose([q.GetReal(), *q.GetImaginary()], [w, x, y, z], atol=0, rtol=1e-12),
                          f"collider {i} frame {k}: orientation")
        print(f"colliders: {len(colliders.GetChildren())} follow manifest.json's centres")
        for child in colliders.GetChildren():
            if not child.GetName().startswith("mesh_"):
                continue
            index = int(child.GetName()[len("mesh_"):])
            positions, triangles, _ = read_collider(out / "colliders" / f"mesh_{index}.ply")
            shape = UsdGeom.Mesh(stage.GetPrimAtPath(child.GetPath().AppendChild(child.GetName())))
            check(shape, f"{child.GetName()} has no Mesh child {child.GetName()}")
            points = np.array(shape.GetPointsAttr().Get(), "f4")
            check(points.shape == positions.shape and np.array_equal(points, positions),
                  f"{child.GetName()}: {len(points)} points, colliders/mesh_{index}.ply has {len(positions)}")
            check(np.array_equal(np.array(shape.GetFaceVertexIndicesAttr().Get()), triangles.reshape(-1))
                  and set(shape.GetFaceVertexCountsAttr().Get()) == {3},
                  f"{child.GetName()}: triangles differ from the PLY")
            for k in range(1, frames + 1):
                m = np.array(UsdGeom.Xformable(shape).ComputeLocalToWorldTransform(k))
                world = points.astype("f8") @ m[:3, :3] + m[3, :3]
                err = np.abs(world - posed_collider(out, manifest, index, k)).max()
                check(err < 1e-6, f"{child.GetName()} frame {k}: off by {err} m from the manifest's pose")
            print(f"mesh collider {child.GetName()}: {len(points)} points and {len(triangles)} triangles "
                  f"of colliders/mesh_{index}.ply, posed as the manifest says at frames 1..{frames}")
            if RESTS:
                top = world[:, 1].max()
                lowest = points_at_last[:, 1].min()
                spacing = max(b["resolution"] for b in scene["body"])
                check(-0.1 * spacing <= lowest - top <= spacing,
                      f"the lowest particle at y = {lowest} is not on {child.GetName()}'s top at y = {top} "
                      f"(within -0.1 and 1 spacing {spacing})")
                print(f"mesh collider {child.GetName()}: its top at the last frame, y = {top:.4f} m, is "
                      f"{lowest - top:.4f} m under the lowest particle (spacing {spacing} m)")

    # ParaView collection, read with meshio.
    pvd = out / "tets" / "tets.pvd"
    if pvd.exists():
        import meshio

        sets = ET.parse(pvd).getroot().find("Collection").findall("DataSet")
        check(len(sets) == frames, f"tets.pvd lists {len(sets)} frames, not {frames}")
        for k, ds in enumerate(sets, start=1):
            check(abs(float(ds.get("timestep")) - (k - 1) / playback_fps) < 1e-12, f"pvd timestep {k}")
            check(abs(float(ds.get("simulation_time")) - manifest["frame_times"][k - 1]) <= 1e-15 + 1e-12 * manifest["frame_times"][k - 1],
                  f"pvd simulation_time {k}")
            grid = meshio.read(pvd.parent / ds.get("file"))
            check(grid.cells_dict["tetra"].shape[1] == 4 and "damage" in grid.cell_data, f"{ds.get('file')}")
        print(f"tets.pvd: {frames} frames at (k-1)/{playback_fps} s, each .vtu read by meshio")
    print("usd_check: all checks passed")


RESTS = "--rests-on-colliders" in sys.argv

if __name__ == "__main__":
    main(sys.argv[1])
