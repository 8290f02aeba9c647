"""Reads a `blockworld render|recognize --rrd` recording back with the rerun-sdk (docs/rerun.md
"Check") and asserts it matches the folder `blockworld render` wrote beside it:

* every camera of the folder is at `world/cameras/<v>` with a Transform3D; a perspective one
  has a Pinhole whose intrinsics and resolution equal those of `camera_<v>.json` (fx, fy, cx,
  cy from `clip_from_view` and `size_px`), and whose pose and pinhole, applied in Rerun's way,
  project test points onto the px the camera file's own recipe gives; an orthographic one has
  no Pinhole;
* each view's picture, depth (meter = depth_units_per_mm * 1000) and ids are under the
  view's 2D entity (`world/cameras/<v>` or `views/<v>`), each with the camera's size;
* each view has one line strip per line of `lines_<v>.json` (or of the drawing given);
* `world/truth/blocks/<i>` is one Mesh3D per block of the scene file; with `--recognized N`,
  `world/recognized/blocks` has N blocks.

Usage: check_rrd.py RECORDING.rrd DIR [--scene SCENE.json] [--recognized N] [--views ne,se,...]
Exit 0 when every assertion holds; 1 with one line per failure otherwise.
"""

import argparse
import json
import math
import pathlib
import sys

import rerun.recording


def cell(table, entity, component):
    """The first logged cell of a component: the list of its instances."""
    name = f"/{entity}:{component}"
    if name not in table.column_names:
        return None
    values = [v for v in table.column(name).to_pylist() if v is not None]
    return values[0] if values else None


def column(table, entity, component):
    """The one instance of a component logged once (a pose, a pinhole, a picture's format)."""
    c = cell(table, entity, component)
    return c[0] if c else None


def expected_intrinsics(cam):
    """fx, fy, cx, cy in image px (y down) of a perspective camera file."""
    p = cam["clip_from_view"]
    w, h = cam["size_px"]
    return [p[0] * w / 2, p[5] * h / 2, w / 2 * (1 - p[8]), h / 2 * (1 + p[9])]


def mat_vec(m, v):
    """Column-major 4x4 times a 4-vector."""
    return [sum(m[c * 4 + r] * v[c] for c in range(4)) for r in range(4)]


def camera_file_px(cam, p_mm):
    """The camera file's own recipe: picture px, x right, y up (docs/formats.md)."""
    c = mat_vec(cam["view_from_world"], p_mm + [1.0])
    clip = mat_vec(cam["clip_from_view"], c)
    w, h = cam["size_px"]
    return [(clip[0] / clip[3] + 1) / 2 * w, (clip[1] / clip[3] + 1) / 2 * h]


def pinhole_px(k, translation, mat3, p_m):
    """Rerun's projection: world -> camera (RUB) by the inverse pose, RUB -> RDF, then K."""
    d = [p_m[i] - translation[i] for i in range(3)]
    # mat3 is column-major world_from_camera; its transpose takes world to camera.
    cam = [sum(mat3[col * 3 + r] * d[r] for r in range(3)) for col in range(3)]
    x, y, z = cam[0], -cam[1], -cam[2]
    return [k[0] * x / z + k[6], k[4] * y / z + k[7]]


def check_camera(table, v, cam, failures):
    entity = f"world/cameras/{v}"
    translation = column(table, entity, "Transform3D:translation")
    mat3 = column(table, entity, "Transform3D:mat3x3")
    if translation is None or mat3 is None:
        failures.append(f"{entity}: no Transform3D translation and mat3x3")
        return
    pinhole = column(table, entity, "Pinhole:image_from_camera")
    if cam["projection"]["kind"] == "orthographic":
        if pinhole is not None:
            failures.append(f"{entity}: an orthographic camera has a Pinhole")
        return
    if pinhole is None:
        failures.append(f"{entity}: no Pinhole for a perspective camera")
        return
    want = expected_intrinsics(cam)
    got = [pinhole[0], pinhole[4], pinhole[6], pinhole[7]]
    if any(abs(a - b) > 1e-3 * max(1.0, abs(b)) for a, b in zip(got, want)):
        failures.append(f"{entity}: intrinsics fx fy cx cy {got} != camera file {want}")
    resolution = column(table, entity, "Pinhole:resolution")
    if resolution != [float(s) for s in cam["size_px"]]:
        failures.append(f"{entity}: resolution {resolution} != size_px {cam['size_px']}")
    target = cam["target_mm"]
    h = cam["size_px"][1]
    for off in ([0, 0, 0], [30, 10, -20], [-25, 40, 15]):
        p_mm = [target[i] + off[i] for i in range(3)]
        x, y = camera_file_px(cam, p_mm)
        u, w = pinhole_px(pinhole, translation, mat3, [c / 1000 for c in p_mm])
        if abs(u - x) > 0.05 or abs(w - (h - y)) > 0.05:
            failures.append(
                f"{entity}: the recorded pose and pinhole put {p_mm} mm at ({u:.2f}, {w:.2f}) px, "
                f"the camera file at ({x:.2f}, {h - y:.2f})"
            )
            break


def check_pictures(table, v, cam, folder, lines_count, failures):
    space = f"views/{v}" if cam["projection"]["kind"] == "orthographic" else f"world/cameras/{v}"
    w, h = cam["size_px"]
    for name, archetype in (("image", "Image"), ("depth", "DepthImage"), ("ids", "SegmentationImage")):
        fmt = column(table, f"{space}/{name}", f"{archetype}:format")
        if fmt is None:
            failures.append(f"{space}/{name}: no {archetype}")
        elif [fmt["width"], fmt["height"]] != [w, h]:
            failures.append(f"{space}/{name}: {fmt['width']}x{fmt['height']} px, camera {w}x{h}")
    meter = column(table, f"{space}/depth", "DepthImage:meter")
    if meter is not None and abs(meter - cam["depth_units_per_mm"] * 1000) > 1e-3:
        failures.append(f"{space}/depth: meter {meter} != depth_units_per_mm * 1000")
    strips = cell(table, f"{space}/lines", "LineStrips2D:strips")
    if strips is None:
        failures.append(f"{space}/lines: no LineStrips2D")
    elif lines_count is not None and len(strips) != lines_count:
        failures.append(f"{space}/lines: {len(strips)} strips, the drawing has {lines_count} lines")


def block_entities(table, parent):
    prefix = f"/{parent}/"
    return {
        name.split(":")[0]
        for name in table.column_names
        if name.startswith(prefix) and name.endswith(":Mesh3D:vertex_positions")
    }


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("recording")
    ap.add_argument("dir")
    ap.add_argument("--scene")
    ap.add_argument("--recognized", type=int)
    ap.add_argument("--views", default="ne,se,sw,nw")
    ap.add_argument("--no-line-counts", action="store_true")
    args = ap.parse_args()
    table = rerun.recording.load_recording(args.recording).view(index=None, contents="/**").select().read_all()
    folder = pathlib.Path(args.dir)
    failures = []
    views = args.views.split(",")
    for v in views:
        cam = json.loads((folder / f"camera_{v}.json").read_text())
        check_camera(table, v, cam, failures)
        lines_file = folder / f"lines_{v}.json"
        count = None
        if not args.no_line_counts:
            count = len(json.loads(lines_file.read_text())["lines"])
        check_pictures(table, v, cam, folder, count, failures)
    if args.scene:
        want = len(json.loads(pathlib.Path(args.scene).read_text())["blocks"])
        got = len(block_entities(table, "world/truth/blocks"))
        if got != want:
            failures.append(f"world/truth/blocks: {got} meshes, the scene has {want} blocks")
    if args.recognized is not None:
        got = len(block_entities(table, "world/recognized/blocks"))
        if got != args.recognized:
            failures.append(f"world/recognized/blocks: {got} meshes, the reconstruction has {args.recognized}")
    if "/world/floor:Boxes3D:half_sizes" not in table.column_names:
        failures.append("world/floor: no Boxes3D")
    for f in failures:
        print(f)
    if failures:
        sys.exit(1)
    print(f"{args.recording}: {len(views)} views, {len(table.column_names)} columns read back")


if __name__ == "__main__":
    main()
