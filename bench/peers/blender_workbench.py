"""Blender 4.2 Workbench peer of `blockworld bench render` (docs/benchmarks.md "Benchmarks").

The same work as blockworld's 10-block row: the stack of `blockworld bench render` (N Baustein 15
cubes of 15 mm in layers of a 3 x 3 square, filled layer by layer from the floor; blockworld's
y-up becomes Blender's z-up) on a floor, seen in the four 45-degree corner views at an elevation
of 35.264 degrees (the isometric direction) by an orthographic camera framing the stack,
512 x 480 px, Workbench engine, flat gray studio lighting, anti-aliasing OFF. Each view is
rendered and written as an 8-bit gray PNG (Blender's render + its own readback and file write,
as blockworld's figure includes its readback), timed per view after untimed warm-up renders (at least --warmup of them and --warmup-seconds of them).

Run with a Python that has Blender as a module (`pip install bpy==4.2.23`):

    python blender_workbench.py --blocks 10 --views 40 --out DIR

Prints one line `RESULT {json}` with the median and mean ms per view.
"""
import argparse
import json
import math
import os
import statistics
import sys
import time

import bpy

SIDE_MM = 15.0
W, H = 512, 480
ELEVATION_DEG = math.degrees(math.asin(1 / math.sqrt(3)))
VIEWS = [("ne", 45.0), ("nw", 135.0), ("sw", 225.0), ("se", 315.0)]


def stack_centres(n, side=3):
    """Centres (x, y, z) in mm, z up: the stack of blockworld's `bench render`."""
    out = []
    for i in range(n):
        layer, cell = divmod(i, side * side)
        x = (cell % side) * SIDE_MM
        depth = (cell // side) * SIDE_MM
        out.append((x, depth, layer * SIDE_MM + SIDE_MM / 2))
    return out


def build_scene(n):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    scene = bpy.context.scene
    scene.render.engine = "BLENDER_WORKBENCH"
    scene.display.render_aa = "OFF"
    scene.display.shading.light = "STUDIO"
    scene.display.shading.color_type = "SINGLE"
    scene.render.resolution_x, scene.render.resolution_y = W, H
    scene.render.resolution_percentage = 100
    scene.render.image_settings.file_format = "PNG"
    scene.render.image_settings.color_mode = "BW"
    scene.render.image_settings.color_depth = "8"
    scene.render.image_settings.compression = 15
    scene.render.film_transparent = False
    centres = stack_centres(n)
    for (x, y, z) in centres:
        bpy.ops.mesh.primitive_cube_add(size=SIDE_MM, location=(x, y, z))
    bpy.ops.mesh.primitive_plane_add(size=400.0, location=(15.0, 15.0, 0.0))
    cam_data = bpy.data.cameras.new("camera")
    cam_data.type = "ORTHO"
    lo = [min(c[k] for c in centres) - SIDE_MM / 2 for k in range(3)]
    hi = [max(c[k] for c in centres) + SIDE_MM / 2 for k in range(3)]
    lo[2] = 0.0
    diagonal = math.dist(lo, hi)
    cam_data.ortho_scale = diagonal * 1.1
    cam_data.clip_start, cam_data.clip_end = 1.0, 10 * diagonal
    cam = bpy.data.objects.new("camera", cam_data)
    scene.collection.objects.link(cam)
    scene.camera = cam
    centre = [(a + b) / 2 for a, b in zip(lo, hi)]
    return scene, cam, centre, diagonal


def aim(cam, centre, distance, azimuth_deg):
    el, az = math.radians(ELEVATION_DEG), math.radians(azimuth_deg)
    cam.location = (
        centre[0] + distance * math.cos(el) * math.cos(az),
        centre[1] + distance * math.cos(el) * math.sin(az),
        centre[2] + distance * math.sin(el),
    )
    # Blender cameras look down their -z; aim with a track-to rotation.
    direction = [c - l for c, l in zip(centre, cam.location)]
    pitch = math.atan2(math.hypot(direction[0], direction[1]), -direction[2])
    yaw = math.atan2(direction[1], direction[0]) - math.pi / 2
    cam.rotation_euler = (pitch, 0.0, yaw)


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--blocks", type=int, default=10)
    ap.add_argument("--views", type=int, default=40, help="timed views (cycling NE, NW, SW, SE)")
    ap.add_argument("--warmup", type=int, default=4)
    ap.add_argument("--warmup-seconds", type=float, default=0.0,
                    help="keep warming up until this many seconds have passed (at least --warmup renders)")
    ap.add_argument("--out", required=True, help="folder for the PNGs (created)")
    args = ap.parse_args(sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else None)
    os.makedirs(args.out, exist_ok=True)
    scene, cam, centre, diagonal = build_scene(args.blocks)
    times = []
    warmup_started = time.perf_counter()
    k = 0
    while len(times) < args.views:
        name, azimuth = VIEWS[k % 4]
        aim(cam, centre, 2 * diagonal, azimuth)
        scene.render.filepath = os.path.join(args.out, f"view_{name}.png")
        warming = k < args.warmup or time.perf_counter() - warmup_started < args.warmup_seconds
        t = time.perf_counter()
        bpy.ops.render.render(write_still=True)
        if not warming:
            times.append(1e3 * (time.perf_counter() - t))
        k += 1
    res = {
        "blender": bpy.app.version_string,
        "blocks": args.blocks,
        "size": [W, H],
        "aa": scene.display.render_aa,
        "views": len(times),
        "warmup_renders": k - len(times),
        "ms_per_view_median": round(statistics.median(times), 3),
        "ms_per_view_mean": round(statistics.fmean(times), 3),
        "ms_per_view_min": round(min(times), 3),
        "loadavg_start": open("/proc/loadavg").read().split()[:3],
    }
    print("RESULT " + json.dumps(res), flush=True)


if __name__ == "__main__":
    main()
