"""Blender as a second renderer of a blockworld dataset (docs/yardstick.md).

Reads a dataset as `blockworld generate ... -o DS` writes it (each scene folder holds
`scene.json` and `camera_<v>.json`) and draws every view with Blender through blockworld's own
camera files, orthographic or perspective, into a dataset-shaped folder:

    OUT/<scene>/view_<v>.png      8-bit gray, the camera's size
    OUT/<scene>/camera_<v>.json   copied, so `blockworld recognize OUT/<scene>` reads it
    OUT/<scene>/scene.json        copied: the truth the bench scores against
    OUT/blender.json              the settings, Blender's version and the seconds per view

Engines (docs/yardstick.md "The setting"):
  cycles     path tracing on the CPU: one lamp beside each camera (a point lamp with a radius,
             so shadows are soft), blocks with 0.2 mm rounded edges (a bevel), a dark floor,
             16 samples denoised with OpenImageDenoise;
  workbench  Blender's flat studio light, no cast shadows, the same rounded edges.
A scene with a `look.json` (docs/varied-look.md) is drawn in its varied look instead under
Cycles: its lights, ambient, albedos, rounding, gloss and exposure.

One Blender process draws all scenes; a view whose picture exists is kept (re-running resumes).
Each picture is written to a temporary name and renamed, so no half-written PNG is left.

`--check-registration` draws every view of the first scenes with one flat colour per block face
(no bevel, no anti-aliasing) and measures, in picture px, how far the colour boundaries lie from
blockworld's exact line drawing `lines_<v>.json`: both ways, every drawn line sampled every
pixel against the nearest boundary, every boundary against the nearest drawn line. It passes
when 99% of both lie within 1 px; `--shift-px` moves Blender's picture to show it fails.

Run with the venv `make blender` builds:

    target/blender-venv/bin/python bench/blender/render_dataset.py DS OUT [--engine cycles]

Exit status 2 with a message naming the file on bad input; 1 when the registration check fails.
"""
import argparse
import json
import math
import os
import shutil
import sys
import struct
import time
import zlib

import numpy as np

bpy = None  # Blender as a module, imported by main()

# Fischer-Technik blocks (blockworld `scene::catalog`): x length, y height, z width in mm.
CATALOG_MM = {"b15": (15.0, 15.0, 15.0), "b30": (30.0, 15.0, 15.0), "b7_5": (15.0, 7.5, 15.0)}
VIEWS = ("ne", "se", "sw", "nw")
# The setting of docs/yardstick.md "The setting".
BLOCK_ALBEDO = 0.8
FLOOR_ALBEDO = 0.08
AMBIENT = 0.03
BEVEL_MM = 0.2
LAMP_AZIMUTH_OFFSET_DEG = 30.0
LAMP_ELEVATION_OFFSET_DEG = 10.0
LAMP_RADIUS_MM = 15.0
# The lamp's power as Blender's irradiance at the target, P / (4 pi d^2): a block's top face
# facing the lamp at about 45 degrees reads near 190 of 255, the floor beside it near 65.
LAMP_IRRADIANCE = 3.4
FLOOR_SIZE_MM = 4000.0


class BadInput(Exception):
    """An input file blockworld did not write as expected; the message names it and the fix."""


def read_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError) as e:
        raise BadInput(f"{path}: {e}; write the dataset with `blockworld generate ... -o DS`")


def column_major(values, path, key):
    if not isinstance(values, list) or len(values) != 16:
        raise BadInput(f"{path}: {key} must be 16 numbers (column-major 4x4)")
    return np.array(values, dtype=float).reshape(4, 4).T


def read_camera(path):
    """A blockworld camera file: its view, size, matrices and near/far, in mm."""
    c = read_json(path)
    try:
        cam = {
            "size_px": (int(c["size_px"][0]), int(c["size_px"][1])),
            "pixel_aspect": float(c.get("pixel_aspect", 1.0)),
            "view_from_world": column_major(c["view_from_world"], path, "view_from_world"),
            "clip_from_view": column_major(c["clip_from_view"], path, "clip_from_view"),
            "near_far_mm": (float(c["near_far_mm"][0]), float(c["near_far_mm"][1])),
            "perspective": c["projection"]["kind"] == "perspective",
            "eye_mm": np.array(c["eye_mm"], dtype=float),
            "target_mm": np.array(c["target_mm"], dtype=float),
        }
    except (KeyError, TypeError, IndexError, ValueError) as e:
        raise BadInput(f"{path}: not a blockworld camera file ({e!r})")
    return cam


def quat_matrix(q):
    """The rotation matrix of a unit quaternion [x, y, z, w] (blockworld's scene files)."""
    x, y, z, w = q
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)],
    ])


def read_scene(path):
    """A scene file's blocks as (type id, centre mm, rotation matrix), blockworld axes."""
    s = read_json(path)
    blocks = []
    for i, b in enumerate(s.get("blocks", [])):
        kind = b.get("type")
        if kind not in CATALOG_MM:
            raise BadInput(f"{path}: block {i} has type {kind!r}; this bench draws "
                           f"{', '.join(CATALOG_MM)} (leave --family wedge,round out)")
        if "rotation" in b:
            rot = quat_matrix(b["rotation"])
        else:
            a = math.radians(float(b.get("yaw_deg", 0.0)))
            rot = np.array([[math.cos(a), 0, math.sin(a)], [0, 1, 0], [-math.sin(a), 0, math.cos(a)]])
        blocks.append((kind, np.array(b["center"], dtype=float), rot))
    if not blocks:
        raise BadInput(f"{path}: no blocks")
    return blocks


# blockworld (mm, +y up, -z north) to Blender (m, +z up): (x, y, z) -> (x, -z, y) / 1000.
AXES = np.array([[1.0, 0, 0], [0, 0, -1.0], [0, 1.0, 0]])


def to_blender(point_mm):
    return AXES @ np.asarray(point_mm, dtype=float) / 1000.0


def block_matrix(centre_mm, rot):
    m = np.eye(4)
    m[:3, :3] = AXES @ rot @ AXES.T
    m[:3, 3] = to_blender(centre_mm)
    return m


def camera_matrix(view_from_world):
    """Blender's camera world matrix: M . inverse(view_from_world), translation in metres."""
    world_from_view = np.linalg.inv(view_from_world)
    m = np.eye(4)
    m[:3, :3] = AXES @ world_from_view[:3, :3]
    m[:3, 3] = to_blender(world_from_view[:3, 3])
    return m


def frame_of(cam):
    """Blender camera settings for a blockworld camera: type, fitted size, shift, sensor fit.

    The picture spans ndc [-1, 1] in both axes; its size is 2 / P00 by 2 / P11 (mm for an
    orthographic camera, tangent units at distance 1 for a perspective one). Blender scales
    the larger of the two (`sensor_fit`) and measures `shift` in that size: an off-centre
    framing moves ndc by P03 (orthographic) or -P02 (perspective)."""
    p = cam["clip_from_view"]
    width, height = 2.0 / p[0, 0], 2.0 / p[1, 1]
    fitted = max(width, height)
    if cam["perspective"]:
        off_x, off_y = -p[0, 2], -p[1, 2]
    else:
        off_x, off_y = p[0, 3], p[1, 3]
    return {
        "fit": "HORIZONTAL" if width >= height else "VERTICAL",
        "fitted": fitted,
        "shift": (-off_x * width / 2 / fitted, -off_y * height / 2 / fitted),
    }


def lamp_position_mm(cam):
    """The lamp beside the camera: the eye turned about the vertical through the target by
    LAMP_AZIMUTH_OFFSET_DEG and raised by LAMP_ELEVATION_OFFSET_DEG, at the eye's distance."""
    d = cam["eye_mm"] - cam["target_mm"]
    dist = float(np.linalg.norm(d))
    az = math.atan2(d[2], d[0]) + math.radians(LAMP_AZIMUTH_OFFSET_DEG)
    el = min(math.asin(d[1] / dist) + math.radians(LAMP_ELEVATION_OFFSET_DEG), math.radians(85))
    return cam["target_mm"] + dist * np.array(
        [math.cos(el) * math.cos(az), math.sin(el), math.cos(el) * math.sin(az)])


def scene_dirs(dataset, only):
    try:
        names = sorted(n for n in os.listdir(dataset)
                       if os.path.isfile(os.path.join(dataset, n, "scene.json")))
    except OSError as e:
        raise BadInput(f"{dataset}: {e}; give a dataset folder `blockworld generate -o` wrote")
    if only:
        missing = [n for n in only if n not in names]
        if missing:
            raise BadInput(f"{dataset}: no scene folder {missing[0]} (--scenes)")
        names = [n for n in names if n in only]
    if not names:
        raise BadInput(f"{dataset}: no scene folders with scene.json; "
                       "write one with `blockworld generate ... -o DS`")
    return names


# ---- Blender: the scene, the camera, the lamp -------------------------------------------------

CUBE_FACES = ((0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (2, 3, 7, 6), (1, 2, 6, 5), (0, 4, 7, 3))


def block_mesh(kind, bevel_mm, face_colours=False):
    """A catalog block as a Blender mesh in metres about its centre (x length, y width, z
    height), optionally with one colour attribute value per face (registration check)."""
    lx, ly, lz = CATALOG_MM[kind]
    hx, hy, hz = lx / 2000, lz / 2000, ly / 2000
    verts = [(sx * hx, sy * hy, sz * hz)
             for sz in (-1, 1) for sx, sy in ((-1, -1), (1, -1), (1, 1), (-1, 1))]
    mesh = bpy.data.meshes.new(f"{kind}-{bevel_mm}-{face_colours}")
    mesh.from_pydata(verts, [], CUBE_FACES)
    mesh.update()
    if face_colours:
        mesh.color_attributes.new("face", "BYTE_COLOR", "CORNER")
    return mesh


def face_colour(label):
    """A colour per label whose 8-bit levels differ by at least 17 from any other's."""
    levels = [(label // 14 ** k) % 14 + 1 for k in range(3)]
    return [l * 17 / 255 for l in levels] + [1.0]


def paint_faces(mesh, first_label):
    attr = mesh.color_attributes["face"]
    for poly in mesh.polygons:
        c = face_colour(first_label + poly.index)
        for li in poly.loop_indices:
            attr.data[li].color_srgb = c


def blender_matrix(m):
    """A numpy 4x4 (rows) as Blender's Matrix (assigning nested lists would read columns)."""
    import mathutils
    return mathutils.Matrix([list(map(float, row)) for row in m])


def new_material(name, albedo, roughness):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    bsdf = m.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (albedo, albedo, albedo, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    m.diffuse_color = (albedo, albedo, albedo, 1.0)
    return m


def set_output(scene, rgb):
    r = scene.render
    r.resolution_percentage = 100
    r.image_settings.file_format = "PNG"
    r.image_settings.color_mode = "RGB" if rgb else "BW"
    r.image_settings.color_depth = "8"
    r.image_settings.compression = 15
    r.dither_intensity = 0.0
    r.film_transparent = False
    vs = scene.view_settings
    vs.view_transform, vs.look, vs.exposure, vs.gamma = "Standard", "None", 0.0, 1.0


def set_engine(scene, engine, args):
    if engine == "cycles":
        scene.render.engine = "CYCLES"
        c = scene.cycles
        c.device, c.samples, c.seed = "CPU", args.samples, 0
        c.use_adaptive_sampling = False
        c.use_denoising, c.denoiser = True, "OPENIMAGEDENOISE"
        # Matte blocks on a dark floor: four bounces carry all the light a picture shows.
        c.max_bounces, c.diffuse_bounces, c.glossy_bounces = 4, 2, 2
        c.transmission_bounces = c.transparent_max_bounces = c.volume_bounces = 0
        scene.render.use_persistent_data = True
        scene.render.threads_mode = "FIXED" if args.threads > 0 else "AUTO"
        if args.threads > 0:
            scene.render.threads = args.threads
        return
    scene.render.engine = "BLENDER_WORKBENCH"
    d = scene.display
    d.render_aa = "OFF" if engine == "flat" else "8"
    sh = d.shading
    sh.light = "FLAT" if engine == "flat" else "STUDIO"
    sh.color_type = "VERTEX" if engine == "flat" else "MATERIAL"
    sh.show_shadows = sh.show_cavity = sh.show_object_outline = False
    sh.show_specular_highlight = engine != "flat"


def build_stage(engine, args):
    """An empty Blender scene with the engine, the output format, a floor, a camera and (for
    Cycles) the lamp and the ambient world light; returns what each view moves."""
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    set_engine(scene, engine, args)
    set_output(scene, rgb=engine == "flat")
    world = bpy.data.worlds.new("world")
    scene.world = world
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Color"].default_value = (1, 1, 1, 1)
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = AMBIENT
    floor_mesh = bpy.data.meshes.new("floor")
    h = FLOOR_SIZE_MM / 2000
    floor_mesh.from_pydata([(-h, -h, 0), (h, -h, 0), (h, h, 0), (-h, h, 0)], [], [(0, 1, 2, 3)])
    if engine == "flat":
        floor_mesh.color_attributes.new("face", "BYTE_COLOR", "CORNER")
        paint_faces(floor_mesh, 0)
    floor = bpy.data.objects.new("floor", floor_mesh)
    floor.data.materials.append(new_material("floor", FLOOR_ALBEDO, 0.8))
    scene.collection.objects.link(floor)
    cam = bpy.data.objects.new("camera", bpy.data.cameras.new("camera"))
    scene.collection.objects.link(cam)
    scene.camera = cam
    lamp = None
    if engine == "cycles":
        lamp = bpy.data.objects.new("lamp", bpy.data.lights.new("lamp", "POINT"))
        lamp.data.shadow_soft_size = LAMP_RADIUS_MM / 1000
        scene.collection.objects.link(lamp)
    return {"scene": scene, "camera": cam, "lamp": lamp, "floor": floor, "suns": [],
            "block": new_material("block", BLOCK_ALBEDO, 0.6), "meshes": {}, "objects": []}


def place_blocks(stage, blocks, bevel_mm, face_colours):
    """Replaces the previous scene's blocks by `blocks`."""
    for ob in stage["objects"]:
        bpy.data.objects.remove(ob, do_unlink=True)
    stage["objects"] = []
    for i, (kind, centre, rot) in enumerate(blocks):
        if face_colours:
            mesh = block_mesh(kind, 0.0, True)
            paint_faces(mesh, 1 + 6 * i)
        else:
            if kind not in stage["meshes"]:
                stage["meshes"][kind] = block_mesh(kind, bevel_mm)
                stage["meshes"][kind].materials.append(stage["block"])
            mesh = stage["meshes"][kind]
        ob = bpy.data.objects.new(f"block{i}", mesh)
        ob.matrix_world = blender_matrix(block_matrix(centre, rot))
        if bevel_mm > 0 and not face_colours:
            bevel = ob.modifiers.new("bevel", "BEVEL")
            bevel.width, bevel.segments = bevel_mm / 1000, 3
            bevel.limit_method, bevel.harden_normals = "NONE", True
            for p in mesh.polygons:
                p.use_smooth = True
        stage["scene"].collection.objects.link(ob)
        stage["objects"].append(ob)


def aim_camera(stage, cam, shift_px=0.0):
    """Points Blender's camera (and the lamp beside it) as blockworld's camera file says."""
    scene, ob = stage["scene"], stage["camera"]
    w, h = cam["size_px"]
    scene.render.resolution_x, scene.render.resolution_y = w, h
    scene.render.pixel_aspect_x, scene.render.pixel_aspect_y = 1.0, cam["pixel_aspect"]
    ob.matrix_world = blender_matrix(camera_matrix(cam["view_from_world"]))
    f = frame_of(cam)
    data = ob.data
    data.sensor_fit = f["fit"]
    if cam["perspective"]:
        data.type, data.lens_unit = "PERSP", "MILLIMETERS"
        data.sensor_width = data.sensor_height = 36.0
        data.lens = 36.0 / f["fitted"]
    else:
        data.type, data.ortho_scale = "ORTHO", f["fitted"] / 1000
    data.shift_x = f["shift"][0] - shift_px / max(w, h * cam["pixel_aspect"])
    data.shift_y = f["shift"][1]
    data.clip_start, data.clip_end = cam["near_far_mm"][0] / 1000, cam["near_far_mm"][1] / 1000
    lamp = stage["lamp"]
    if lamp is not None:
        pos = lamp_position_mm(cam)
        lamp.location = tuple(to_blender(pos))
        dist_m = float(np.linalg.norm(pos - cam["target_mm"])) / 1000
        # A point lamp of power P watts gives irradiance P / (4 pi d^2) at distance d.
        lamp.data.energy = LAMP_IRRADIANCE * 4 * math.pi * dist_m ** 2


def render_to(scene, path):
    """Renders and writes `path` through a temporary name (no half-written picture)."""
    tmp = path[:-4] + ".partial.png"
    scene.render.filepath = tmp
    bpy.ops.render.render(write_still=True)
    os.replace(tmp, path)


# ---- The varied look (docs/varied-look.md "look.json") ---------------------------------------

def read_look(folder, views):
    """A scene's `look.json` (docs/varied-look.md), or None when the scene has none."""
    path = os.path.join(folder, "look.json")
    if not os.path.isfile(path):
        return None
    look = read_json(path)
    try:
        if look["format"] != "blockworld-look/1":
            raise BadInput(f"{path}: format {look['format']!r}; this bench reads blockworld-look/1")
        out = {
            "path": path,
            "ambient": float(look["ambient"]),
            "light_radius_deg": float(look["light_radius_deg"]),
            "edge_radius_mm": float(look["edge_radius_mm"]),
            "block_albedos": [float(a) for a in look["block_albedos"]],
            "floor_albedo": float(look["floor_albedo"]),
            "gloss": float(look["gloss"]),
            "shininess": float(look["shininess"]),
            "intensities": [float(l["intensity"]) for l in look["lights"]],
            "downsample": int(look["camera"]["downsample"]),
            "sensor": {k: float(look["sensor"][k]) for k in
                       ("gain", "blur_sigma_px", "full_well_e", "read_noise_e", "gamma",
                        "vignetting")},
            "seed": int(look["seed"]),
            "towards_light": {v: [np.array(l["towards_light"], dtype=float)
                                  for l in look["views"][v]] for v in views},
        }
    except (KeyError, TypeError, IndexError, ValueError) as e:
        raise BadInput(f"{path}: not a blockworld-look/1 file ({e!r}); regenerate the dataset")
    return out


def aim_suns(stage, look, view):
    """Points one sun per light of `look` as `view` sees it (docs/varied-look.md: a camera lamp
    turns with each view), with the look's softness and the sensor's gain folded in."""
    for ob in stage["suns"]:
        bpy.data.objects.remove(ob, do_unlink=True)
    stage["suns"] = []
    gain = look["sensor"]["gain"]
    for i, (towards, intensity) in enumerate(zip(look["towards_light"][view],
                                                 look["intensities"])):
        sun = bpy.data.objects.new(f"sun{i}", bpy.data.lights.new(f"sun{i}", "SUN"))
        # A sun of strength S lights a face it meets head-on with irradiance S; a white
        # Lambertian face then has radiance S / pi, blockworld's `intensity` (times the gain).
        sun.data.energy = math.pi * intensity * gain
        sun.data.angle = math.radians(2.0 * look["light_radius_deg"])
        z = to_blender(towards)
        z = z / np.linalg.norm(z)
        x = np.cross([0.0, 0.0, 1.0] if abs(z[2]) < 0.9 else [1.0, 0.0, 0.0], z)
        x = x / np.linalg.norm(x)
        m = np.eye(4)
        m[:3, 0], m[:3, 1], m[:3, 2] = x, np.cross(z, x), z
        sun.matrix_world = blender_matrix(m)
        stage["scene"].collection.objects.link(sun)
        stage["suns"].append(sun)


def dress_for_look(stage, look, blocks):
    """Albedos, gloss, ambient and rounding of `look` on the stage and its blocks."""
    world = stage["scene"].world.node_tree.nodes["Background"]
    # A uniform world of radiance A gives an open face irradiance pi A: radiance A from white.
    world.inputs["Strength"].default_value = look["ambient"] * look["sensor"]["gain"]
    set_albedo(stage["floor"].data.materials[0], look["floor_albedo"], 0.0, 1.0)
    for i, ob in enumerate(stage["objects"]):
        m = new_material(f"look_block{i}", look["block_albedos"][i], 1.0)
        # Blinn-Phong exponent n is about GGX roughness sqrt(2 / (n + 2)).
        set_albedo(m, look["block_albedos"][i], look["gloss"],
                   math.sqrt(2.0 / (look["shininess"] + 2.0)) if look["gloss"] > 0 else 1.0)
        ob.data = ob.data.copy()
        ob.data.materials.clear()
        ob.data.materials.append(m)


def set_albedo(material, albedo, gloss, roughness):
    bsdf = material.node_tree.nodes["Principled BSDF"]
    bsdf.inputs["Base Color"].default_value = (albedo, albedo, albedo, 1.0)
    bsdf.inputs["Roughness"].default_value = roughness
    bsdf.inputs["Specular IOR Level"].default_value = min(1.0, gloss * 2.0)


def linear_picture(path):
    """A Raw 16-bit PNG Blender wrote, as linear values in rows top to bottom."""
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "Non-Color"  # the file's values, not decoded as sRGB
    w, h = img.size
    px = np.array(img.pixels[:], dtype=np.float64).reshape(h, w, 4)[::-1, :, 0]
    bpy.data.images.remove(img)
    return px


def gaussian_blur(img, sigma):
    if sigma <= 0:
        return img
    r = int(math.ceil(3 * sigma))
    k = np.exp(-0.5 * (np.arange(-r, r + 1) / sigma) ** 2)
    k /= k.sum()
    pad = np.pad(img, r, mode="edge")
    rows = np.apply_along_axis(lambda v: np.convolve(v, k, mode="valid"), 1, pad)
    return np.apply_along_axis(lambda v: np.convolve(v, k, mode="valid"), 0, rows)


def expose(radiance, sensor, seed):
    """blockworld's sensor on a linear picture (docs/rendering.md "Photographic look"): blur,
    vignetting, shot and read noise, gamma, 8-bit levels. Its own seeded noise, not
    blockworld's stream: the same statistics, other samples."""
    h, w = radiance.shape
    light = gaussian_blur(radiance, sensor["blur_sigma_px"])
    ys, xs = np.mgrid[0:h, 0:w]
    r2 = ((xs + 0.5 - w / 2) ** 2 + (ys + 0.5 - h / 2) ** 2) / ((w * w + h * h) / 4)
    light = light * (1 - sensor["vignetting"] * r2)
    rng = np.random.default_rng(seed)
    well = sensor["full_well_e"]
    if well > 0:
        e = np.clip(light, 0, None) * well
        e = e + rng.normal(size=e.shape) * np.sqrt(e) + rng.normal(size=e.shape) * sensor["read_noise_e"]
        light = e / well
    light = np.clip(light, 0, 1) ** (1 / sensor["gamma"])
    return np.floor(255 * light + 0.5).astype(np.uint8)


def averaged(levels, n):
    """The picture averaged n x n (blockworld's --downsample), rounded to levels."""
    if n <= 1:
        return levels
    h, w = levels.shape[0] // n * n, levels.shape[1] // n * n
    blocks = levels[:h, :w].astype(np.float64).reshape(h // n, n, w // n, n)
    return np.floor(blocks.mean(axis=(1, 3)) + 0.5).astype(np.uint8)


def write_gray_png(path, levels):
    """An 8-bit gray PNG, written through a temporary name."""
    h, w = levels.shape
    raw = b"".join(b"\x00" + levels[y].tobytes() for y in range(h))
    chunk = lambda kind, data: (struct.pack(">I", len(data)) + kind + data
                                + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF))
    png = (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 6)) + chunk(b"IEND", b""))
    tmp = path[:-4] + ".partial.png"
    with open(tmp, "wb") as f:
        f.write(png)
    os.replace(tmp, path)


def render_varied(stage, cam, look, view, path, k):
    """One view in the scene's varied look: Cycles at the rendered size (twice the written
    one when the look averages 2 x 2), blockworld's sensor on the linear result, averaged."""
    n = look["downsample"]
    scene = stage["scene"]
    aim_camera(stage, cam)
    scene.render.resolution_x *= n
    scene.render.resolution_y *= n
    aim_suns(stage, look, view)
    tmp = path[:-4] + ".linear.png"
    scene.render.filepath = tmp
    bpy.ops.render.render(write_still=True)
    radiance = linear_picture(tmp)
    os.remove(tmp)
    levels = expose(radiance, look["sensor"], look["seed"] + k)
    write_gray_png(path, averaged(levels, n))


# ---- Rendering a dataset ----------------------------------------------------------------------

def read_views(folder, views):
    cams = {}
    for v in views:
        path = os.path.join(folder, f"camera_{v}.json")
        if not os.path.isfile(path):
            raise BadInput(f"{path}: missing; generate the dataset with these --views")
        cams[v] = read_camera(path)
    return cams


def copy_truth(src, dst, views):
    """scene.json and each view's camera (and look.json when `views` lists "look")."""
    os.makedirs(dst, exist_ok=True)
    names = ["scene.json"] + [f"camera_{v}.json" for v in views if v != "look"]
    for name in names + (["look.json"] if "look" in views else []):
        shutil.copyfile(os.path.join(src, name), os.path.join(dst, name))


def render_all(args, names):
    """Draws every view of every scene into OUT, keeping scenes already drawn."""
    # Every input is read before anything is written: a bad file stops the run with no output.
    inputs = [(read_scene(os.path.join(args.dataset, n, "scene.json")),
               read_views(os.path.join(args.dataset, n), args.views),
               read_look(os.path.join(args.dataset, n), args.views)) for n in names]
    varied = [look is not None for _, _, look in inputs]
    if any(varied) and not all(varied):
        raise BadInput(f"{args.dataset}: some scenes have look.json and some not; render one "
                       "look per dataset")
    if any(varied) and args.engine != "cycles":
        raise BadInput(f"{args.dataset}: a varied-look dataset (look.json) is drawn with "
                       "--engine cycles only")
    for (blocks, _, look) in inputs:
        if look is not None and len(look["block_albedos"]) != len(blocks):
            raise BadInput(f"{look['path']}: {len(look['block_albedos'])} albedos for "
                           f"{len(blocks)} blocks; regenerate the dataset")
    os.makedirs(args.out, exist_ok=True)
    stage = build_stage(args.engine, args)
    if any(varied):
        set_linear_output(stage)
    seconds, started = [], time.time()
    for k, (name, (blocks, cams, look)) in enumerate(zip(names, inputs)):
        src, dst = os.path.join(args.dataset, name), os.path.join(args.out, name)
        pictures = [os.path.join(dst, f"view_{v}.png") for v in args.views]
        if all(os.path.isfile(p) for p in pictures):
            continue
        copy_truth(src, dst, args.views + (["look"] if look else []))
        bevel = look["edge_radius_mm"] if look else args.bevel_mm
        place_blocks(stage, blocks, bevel, face_colours=False)
        if look:
            dress_for_look(stage, look, blocks)
        todo = [(v, p) for v, p in zip(args.views, pictures) if not os.path.isfile(p)]
        for v, picture in todo:
            t = time.perf_counter()
            if look:
                render_varied(stage, cams[v], look, v, picture, VIEWS.index(v))
            else:
                aim_camera(stage, cams[v])
                render_to(stage["scene"], picture)
            seconds.append(time.perf_counter() - t)
        print(f"[{k + 1}/{len(names)}] {name}: {len(blocks)} blocks, {len(todo)} views, "
              f"{np.mean(seconds[-len(todo):]):.2f} s per view", flush=True)
    write_settings(args, names, seconds, time.time() - started, any(varied))
    return 0


def set_linear_output(stage):
    """Linear 16-bit output and no camera lamp: the varied look's lights and sensor instead."""
    r = stage["scene"].render
    r.image_settings.color_mode, r.image_settings.color_depth = "BW", "16"
    stage["scene"].view_settings.view_transform = "Raw"
    stage["lamp"].data.energy = 0.0
    stage["lamp"].hide_render = True
    stage["lamp"] = None


def write_settings(args, names, seconds, wall_s, varied=False):
    settings = {
        "blender": bpy.app.version_string,
        "dataset": os.path.abspath(args.dataset),
        "engine": args.engine,
        "samples": args.samples if args.engine == "cycles" else None,
        "denoiser": "OpenImageDenoise" if args.engine == "cycles" else None,
        "threads": args.threads,
        "views": args.views,
        "scenes": len(names),
        "bevel_mm": args.bevel_mm,
        "block_albedo": BLOCK_ALBEDO,
        "floor_albedo": FLOOR_ALBEDO,
        "ambient": AMBIENT,
        "lamp": None if args.engine != "cycles" else {
            "azimuth_offset_deg": LAMP_AZIMUTH_OFFSET_DEG,
            "elevation_offset_deg": LAMP_ELEVATION_OFFSET_DEG,
            "radius_mm": LAMP_RADIUS_MM, "irradiance": LAMP_IRRADIANCE},
        "varied_look": varied,
        "views_rendered_now": len(seconds),
        "seconds_per_view_mean": round(float(np.mean(seconds)), 3) if seconds else None,
        "seconds_per_view_median": round(float(np.median(seconds)), 3) if seconds else None,
        "wall_seconds": round(wall_s, 1),
        "loadavg": open("/proc/loadavg").read().split()[:3],
    }
    path = os.path.join(args.out, "blender.json")
    with open(path + ".partial", "w") as f:
        json.dump(settings, f, indent=2)
    os.replace(path + ".partial", path)
    print(f"{len(seconds)} views drawn, {settings['seconds_per_view_mean']} s per view; {path}")


# ---- The registration check -------------------------------------------------------------------

def read_labels(path):
    """A flat-colour picture as one integer label per pixel, rows from the bottom (picture y up)."""
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "Non-Color"  # the file's values, not decoded as sRGB
    w, h = img.size
    px = np.empty(w * h * 4, dtype=np.float32)
    img.pixels.foreach_get(px)
    bpy.data.images.remove(img)
    rgb = np.rint(px.reshape(h, w, 4)[:, :, :3] * 255).astype(np.int64)
    return rgb[:, :, 0] * 65536 + rgb[:, :, 1] * 256 + rgb[:, :, 2]


def boundary_points(labels):
    """Picture px (x right, y up) of every step between unequal neighbouring pixels."""
    ii, jj = np.nonzero(labels[:, 1:] != labels[:, :-1])
    across = np.stack([jj + 1.0, ii + 0.5], axis=1)
    ii, jj = np.nonzero(labels[1:, :] != labels[:-1, :])
    up = np.stack([jj + 0.5, ii + 1.0], axis=1)
    return np.concatenate([across, up])


def line_samples(drawing, end_gap_px=2.0):
    """Points every pixel along each drawn line, leaving out `end_gap_px` at each end."""
    pts = np.array(drawing["points"], dtype=float)
    out = []
    for a, b in drawing["lines"]:
        p, q = pts[a], pts[b]
        length = float(np.linalg.norm(q - p))
        n = int(length - 2 * end_gap_px)
        if n > 0:
            t = (end_gap_px + np.arange(n + 1) * (length - 2 * end_gap_px) / max(n, 1)) / length
            out.append(p + t[:, None] * (q - p))
    return np.concatenate(out) if out else np.zeros((0, 2))


def nearest_point(samples, points):
    best = np.full(len(samples), np.inf)
    for k in range(0, len(points), 2048):
        d = np.linalg.norm(samples[:, None, :] - points[None, k:k + 2048, :], axis=2)
        best = np.minimum(best, d.min(axis=1))
    return best


def nearest_segment(samples, drawing):
    pts = np.array(drawing["points"], dtype=float)
    seg = np.array(drawing["lines"], dtype=int)
    a, b = pts[seg[:, 0]], pts[seg[:, 1]]
    ab = b - a
    t = ((samples[:, None, :] - a[None]) * ab[None]).sum(2) / np.maximum((ab * ab).sum(1), 1e-12)
    foot = a[None] + np.clip(t, 0, 1)[:, :, None] * ab[None]
    return np.linalg.norm(samples[:, None, :] - foot, axis=2).min(axis=1)


def check_registration(args, names, tol_px=1.0, share=0.99):
    """Blender's face boundaries against blockworld's exact drawings, both ways (module doc)."""
    stage = build_stage("flat", args)
    scratch = os.path.join(args.out or "/tmp", ".registration")
    os.makedirs(scratch, exist_ok=True)
    to_lines, to_edges = [], []
    for name in names:
        src = os.path.join(args.dataset, name)
        place_blocks(stage, read_scene(os.path.join(src, "scene.json")), 0.0, face_colours=True)
        for v, cam in read_views(src, args.views).items():
            drawing = read_json(os.path.join(src, f"lines_{v}.json"))
            aim_camera(stage, cam, args.shift_px)
            picture = os.path.join(scratch, f"{name}_{v}.png")
            render_to(stage["scene"], picture)
            edges = boundary_points(read_labels(picture))
            a, b = nearest_point(line_samples(drawing), edges), nearest_segment(edges, drawing)
            to_lines.append(a)
            to_edges.append(b)
            print(f"{name} {v}: drawn lines to Blender's edges median {np.median(a):.2f} px, "
                  f"max {a.max():.2f}; Blender's edges to drawn lines median "
                  f"{np.median(b):.2f} px, max {b.max():.2f}", flush=True)
    a, b = np.concatenate(to_lines), np.concatenate(to_edges)
    ok_a, ok_b = float((a <= tol_px).mean()), float((b <= tol_px).mean())
    verdict = "PASS" if ok_a >= share and ok_b >= share else "FAIL"
    print(f"registration {verdict}: {len(names)} scenes x {len(args.views)} views; "
          f"{100 * ok_a:.2f}% of {len(a)} line samples and {100 * ok_b:.2f}% of {len(b)} "
          f"edge steps within {tol_px} px (needs {100 * share:.0f}% each); "
          f"99th percentiles {np.percentile(a, 99):.2f} and {np.percentile(b, 99):.2f} px")
    return 0 if verdict == "PASS" else 1


def parse_args(argv):
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("dataset", help="a dataset folder `blockworld generate -o` wrote")
    ap.add_argument("out", nargs="?", help="the dataset-shaped output folder (created)")
    ap.add_argument("--engine", choices=("cycles", "workbench"), default="cycles")
    ap.add_argument("--samples", type=int, default=16, help="Cycles samples per pixel")
    ap.add_argument("--threads", type=int, default=0, help="Cycles CPU threads (0 = all)")
    ap.add_argument("--views", default=",".join(VIEWS), help="comma-separated corner views")
    ap.add_argument("--scenes", default="", help="comma-separated scene ids (default: all)")
    ap.add_argument("--limit", type=int, default=0, help="only the first N scenes (0 = all)")
    ap.add_argument("--bevel-mm", type=float, default=BEVEL_MM, help="block edge rounding")
    ap.add_argument("--check-registration", action="store_true",
                    help="measure Blender's edges against lines_<v>.json and stop")
    ap.add_argument("--shift-px", type=float, default=0.0,
                    help="with --check-registration: move Blender's picture right by this")
    a = ap.parse_args(argv)
    a.views = [v.strip() for v in a.views.split(",") if v.strip()]
    bad = [v for v in a.views if v not in VIEWS]
    if bad or not a.views:
        ap.error(f"--views: unknown view {bad[0] if bad else ''!r}; use ne, se, sw, nw")
    a.scenes = [s for s in a.scenes.split(",") if s]
    if a.out is None and not a.check_registration:
        ap.error("give the output folder OUT (only --check-registration writes none)")
    return a


def main(argv):
    args = parse_args(argv)
    try:
        names = scene_dirs(args.dataset, args.scenes)
        if args.limit > 0:
            names = names[:args.limit]
        global bpy
        import bpy  # a second or two: once per process
        if args.check_registration:
            return check_registration(args, names)
        return render_all(args, names)
    except BadInput as e:
        print(f"error: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
