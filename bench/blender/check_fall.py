"""Blender plays a stability dataset's falls (docs/stability.md "The fall in glTF").

Imports every `fall.glb` of a dataset `blockworld generate --keep-unstable --trajectory --gltf`
wrote with Blender's own glTF importer, and for each prints the actions and curves it made and
how far every animated block moves between the first and the last frame (mm). Exits 1 when a
fall has no action, or no block moves at all; 2 when the dataset holds no fall.glb.

    target/blender-venv/bin/python bench/blender/check_fall.py DS
"""
import glob
import os
import sys


def main(dataset):
    import bpy
    paths = sorted(glob.glob(os.path.join(dataset, "*", "fall.glb")))
    if not paths:
        print(f"error: {dataset}: no */fall.glb; generate with --keep-unstable --trajectory "
              "--gltf", file=sys.stderr)
        return 2
    bad = 0
    for path in paths:
        bpy.ops.wm.read_factory_settings(use_empty=True)
        bpy.ops.import_scene.gltf(filepath=path)
        scene = bpy.context.scene
        moving = [o for o in bpy.data.objects if o.animation_data and o.animation_data.action]
        start, end = (min(a.frame_range[0] for a in bpy.data.actions),
                      max(a.frame_range[1] for a in bpy.data.actions)) if moving else (0, 0)
        scene.frame_set(int(start))
        first = {o.name: o.matrix_world.translation.copy() for o in moving}
        scene.frame_set(int(end + 0.999))
        moved_mm = max(((o.matrix_world.translation - first[o.name]).length * 1000
                        for o in moving), default=0.0)
        curves = sum(len(a.fcurves) for a in bpy.data.actions)
        print(f"{os.path.basename(os.path.dirname(path))}: {len(bpy.data.actions)} actions, "
              f"{curves} curves, {len(moving)} animated blocks, largest move {moved_mm:.1f} mm")
        bad += int(not moving or moved_mm <= 0.0)
    return 1 if bad else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__.strip().splitlines()[-1].strip(), file=sys.stderr)
        sys.exit(2)
    sys.exit(main(sys.argv[1]))
