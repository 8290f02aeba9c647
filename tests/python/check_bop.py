"""Reads blockworld's BOP export with a reader written from BOP's format description
(bop_toolkit's bop_datasets_format.md, field by field; docs/export-bop.md "Checks").

    check_bop.py BOP_DIR

Reads every file: camera.json, models/models_info.json and every models/obj_*.ply (ASCII PLY),
and per scene of train_pbr/ its scene_camera.json, scene_gt.json, scene_gt_info.json and every
gray/, depth/, mask/ and mask_visib/ picture. Then, per annotated object instance:

- every model vertex, moved by cam_R_m2c and cam_t_m2c and projected with cam_K, that lands in
  the picture lies within 1 px of the instance's mask; the vertices that no posed model in the
  picture hides (a ray cast against every instance's triangles) lie within 1 px of mask_visib;
- at every mask_visib pixel, the ray through its centre (K^-1 [u, v, 1]) hits the posed model,
  and depth * depth_scale is the depth of that hit;
- px_count_visib, px_count_valid, visib_fract, bbox_visib and bbox_obj agree with the masks and
  the depth picture as BOP's calc_gt_info.py defines them;
- models_info's box and diameter are the PLY's, and each discrete symmetry maps the model's
  vertices onto themselves.

Prints one JSON line of counts on success; exits 1 with the reason otherwise.
"""

import json
import os
import sys

import numpy as np
from PIL import Image

# Depth error allowed at a mask_visib pixel, mm: the depth picture's 1/16 mm step and the
# renderer's f32 arithmetic, far below the millimetres a wrong pose moves a surface.
DEPTH_TOL_MM = 0.25
# Share of mask_visib pixels whose ray must hit the model with the right depth: pixel centres
# within rounding of a silhouette edge go either way.
DEPTH_PASS_SHARE = 0.995
# How far a projected vertex may lie from its mask, px.
VERTEX_TOL_PX = 1.0


def fail(message):
    print(f"FAILED: {message}", file=sys.stderr)
    sys.exit(1)


def load_json(path):
    with open(path) as f:
        return json.load(f)


def read_ply(path):
    """Vertices (n x 3) and triangles (m x 3) of an ASCII PLY."""
    with open(path) as f:
        lines = f.read().split("\n")
    if lines[0] != "ply" or lines[1] != "format ascii 1.0":
        fail(f"{path}: not an ASCII PLY")
    n_vertices = n_faces = 0
    props = []
    i = 2
    while lines[i] != "end_header":
        words = lines[i].split()
        if words[:2] == ["element", "vertex"]:
            n_vertices = int(words[2])
        elif words[:2] == ["element", "face"]:
            n_faces = int(words[2])
        elif words[0] == "property" and words[1] != "list":
            props.append(words[-1])
        i += 1
    body = lines[i + 1 :]
    rows = np.array([[float(x) for x in body[k].split()] for k in range(n_vertices)])
    xyz = rows[:, [props.index("x"), props.index("y"), props.index("z")]]
    faces = []
    for k in range(n_vertices, n_vertices + n_faces):
        words = [int(x) for x in body[k].split()]
        if words[0] != 3:
            fail(f"{path}: face {k - n_vertices} is not a triangle")
        faces.append(words[1:4])
    return xyz, np.array(faces)


def check_models(bop):
    """Reads the models and checks models_info; returns obj_id -> (vertices, triangles)."""
    info = load_json(os.path.join(bop, "models", "models_info.json"))
    models = {}
    for key, entry in info.items():
        obj_id = int(key)
        pts, tris = read_ply(os.path.join(bop, "models", f"obj_{obj_id:06d}.ply"))
        lo, hi = pts.min(axis=0), pts.max(axis=0)
        box = [entry[k] for k in ("min_x", "min_y", "min_z")]
        size = [entry[k] for k in ("size_x", "size_y", "size_z")]
        if not (np.allclose(box, lo, atol=1e-6) and np.allclose(size, hi - lo, atol=1e-6)):
            fail(f"models_info {obj_id}: box {box} {size} is not the PLY's {lo} {hi - lo}")
        diff = pts[:, None, :] - pts[None, :, :]
        diameter = np.sqrt((diff**2).sum(axis=2)).max()
        if abs(diameter - entry["diameter"]) > 1e-6:
            fail(f"models_info {obj_id}: diameter {entry['diameter']}, the PLY's is {diameter}")
        for sym in entry.get("symmetries_discrete", []):
            m = np.array(sym).reshape(4, 4)
            moved = pts @ m[:3, :3].T + m[:3, 3]
            gap = np.sqrt(((moved[:, None, :] - pts[None, :, :]) ** 2).sum(axis=2)).min(axis=1)
            if gap.max() > 1e-6:
                fail(f"models_info {obj_id}: a discrete symmetry moves a vertex {gap.max()} mm off the model")
        models[obj_id] = (pts, tris)
    return models


def posed(model, gt):
    """The model's vertices in the camera frame, and its triangles' corners there."""
    pts, tris = model
    r = np.array(gt["cam_R_m2c"], dtype=np.float64).reshape(3, 3)
    t = np.array(gt["cam_t_m2c"], dtype=np.float64).reshape(3)
    cam = pts @ r.T + t
    return cam, cam[tris]


def ray_hits(origins, dirs, triangles):
    """Ray parameter of the nearest hit of each ray (origin + s dir) with the triangles
    (Moeller-Trumbore), inf where it misses. origins, dirs: n x 3; triangles: m x 3 x 3."""
    a, b, c = triangles[:, 0], triangles[:, 1], triangles[:, 2]
    e1, e2 = b - a, c - a
    p = np.cross(dirs[:, None, :], e2[None, :, :])
    det = (p * e1[None]).sum(axis=2)
    ok = np.abs(det) > 1e-12
    inv = np.where(ok, 1.0 / np.where(ok, det, 1.0), 0.0)
    tv = origins[:, None, :] - a[None]
    u = (tv * p).sum(axis=2) * inv
    q = np.cross(tv, e1[None])
    v = (dirs[:, None, :] * q).sum(axis=2) * inv
    s = (q * e2[None]).sum(axis=2) * inv
    hit = ok & (u >= -1e-9) & (v >= -1e-9) & (u + v <= 1 + 1e-9) & (s > 0)
    return np.where(hit, s, np.inf).min(axis=1)


def project(k, cam):
    uvw = cam @ k.T
    return uvw[:, :2] / uvw[:, 2:3]


def distance_to_mask(mask, uv):
    """Distance in px from each point to the nearest pixel square of the mask (a pixel (c, r)
    spans [c - 0.5, c + 0.5] x [r - 0.5, r + 0.5] in OpenCV pixel coordinates)."""
    rows, cols = np.nonzero(mask)
    if len(rows) == 0:
        return np.full(len(uv), np.inf)
    dx = np.maximum(np.abs(uv[:, 0:1] - cols[None, :]) - 0.5, 0.0)
    dy = np.maximum(np.abs(uv[:, 1:2] - rows[None, :]) - 0.5, 0.0)
    return np.sqrt(dx**2 + dy**2).min(axis=1)


def bop_bbox(mask):
    """misc.calc_2d_bbox of a mask's pixels: [x, y, x_max - x, y_max - y]."""
    ys, xs = np.nonzero(mask)
    return [int(xs.min()), int(ys.min()), int(xs.max() - xs.min()), int(ys.max() - ys.min())]


def read_png(path):
    if not os.path.exists(path):
        fail(f"{path} is missing")
    return np.array(Image.open(path))


class Counts:
    def __init__(self):
        self.scenes = self.images = self.instances = self.vertices_on_mask = 0
        self.vertices_visible = self.depth_pixels = self.depth_misses = 0
        self.depth_max_err_mm = 0.0


def check_vertices(name, k, size, cam, masks, occluders, counts):
    """Projected vertices against the full and the visible mask (module doc)."""
    mask, mask_visib = masks
    uv = project(k, cam)
    inside = (uv[:, 0] >= -0.5) & (uv[:, 0] < size[0] - 0.5) & (uv[:, 1] >= -0.5) & (uv[:, 1] < size[1] - 0.5)
    far = distance_to_mask(mask, uv[inside])
    if len(far) and far.max() > VERTEX_TOL_PX + 1e-9:
        fail(f"{name}: a model vertex projects {far.max():.2f} px from the mask")
    counts.vertices_on_mask += int(inside.sum())
    # A vertex is hidden when its own model crosses the segment from the eye to it short of
    # the vertex (its own triangles meet it at s = 1), or another model crosses or touches it
    # (a corner shared with a block in front is that block's in the picture).
    dirs = cam[inside]
    own, others = occluders
    visible = ray_hits(np.zeros_like(dirs), dirs, own) > 1 - 1e-6
    if len(others):
        visible &= ray_hits(np.zeros_like(dirs), dirs, others) > 1 + 1e-6
    far = distance_to_mask(mask_visib, uv[inside][visible])
    if len(far) and far.max() > VERTEX_TOL_PX + 1e-9:
        fail(f"{name}: a visible model vertex projects {far.max():.3f} px from mask_visib")
    counts.vertices_visible += int(visible.sum())


def check_depth(name, k, triangles, mask_visib, depth_mm, counts):
    """The posed model's depth through every mask_visib pixel centre against the depth picture."""
    rows, cols = np.nonzero(mask_visib)
    if len(rows) == 0:
        return
    pix = np.stack([cols, rows, np.ones_like(rows)], axis=1).astype(np.float64)
    dirs = pix @ np.linalg.inv(k).T  # z = 1: the hit's s is its depth along the optical axis
    s = ray_hits(np.zeros_like(dirs), dirs, triangles)
    err = np.abs(s - depth_mm[rows, cols])
    good = err <= DEPTH_TOL_MM
    counts.depth_pixels += len(rows)
    counts.depth_misses += int((~good).sum())
    if good.mean() < DEPTH_PASS_SHARE:
        fail(f"{name}: depth * depth_scale differs from the posed model's depth by more than {DEPTH_TOL_MM} mm at {int((~good).sum())} of {len(rows)} mask_visib pixels")
    counts.depth_max_err_mm = max(counts.depth_max_err_mm, float(err[good].max()))


def check_info(name, info, mask, mask_visib, depth):
    visib = int(mask_visib.sum())
    want = {
        "px_count_visib": visib,
        "px_count_valid": int((mask & (depth > 0)).sum()),
    }
    for key, value in want.items():
        if info[key] != value:
            fail(f"{name}: {key} {info[key]}, the masks give {value}")
    if info["px_count_all"] < int(mask.sum()):
        fail(f"{name}: px_count_all {info['px_count_all']} is below the mask's {int(mask.sum())} pixels")
    fract = visib / info["px_count_all"] if info["px_count_all"] else 0.0
    if abs(info["visib_fract"] - fract) > 1e-12:
        fail(f"{name}: visib_fract {info['visib_fract']}, px counts give {fract}")
    if visib == 0:
        if info["bbox_visib"] != [-1] * 4 or info["bbox_obj"] != [-1] * 4:
            fail(f"{name}: nothing seen, but the boxes are {info['bbox_visib']} {info['bbox_obj']}")
        return
    if info["bbox_visib"] != bop_bbox(mask_visib):
        fail(f"{name}: bbox_visib {info['bbox_visib']}, mask_visib gives {bop_bbox(mask_visib)}")
    h, w = mask.shape
    x, y, bw, bh = info["bbox_obj"]
    inside = x >= 0 and y >= 0 and x + bw < w and y + bh < h
    if inside and (info["bbox_obj"] != bop_bbox(mask) or info["px_count_all"] != int(mask.sum())):
        fail(f"{name}: bbox_obj {info['bbox_obj']} / px_count_all {info['px_count_all']}, the mask gives {bop_bbox(mask)} / {int(mask.sum())}")


def check_image(scene_dir, im_id, cam, gts, infos, models, counts):
    k = np.array(cam["cam_K"], dtype=np.float64).reshape(3, 3)
    gray = read_png(os.path.join(scene_dir, "gray", f"{im_id:06d}.png"))
    depth = read_png(os.path.join(scene_dir, "depth", f"{im_id:06d}.png"))
    if gray.ndim != 2 or depth.dtype != np.uint16 or gray.shape != depth.shape:
        fail(f"{scene_dir} image {im_id}: gray {gray.shape} {gray.dtype}, depth {depth.shape} {depth.dtype}")
    size = (gray.shape[1], gray.shape[0])
    depth_mm = depth.astype(np.float64) * cam["depth_scale"]
    if len(gts) != len(infos):
        fail(f"{scene_dir} image {im_id}: {len(gts)} scene_gt entries, {len(infos)} scene_gt_info")
    poses = [posed(models[gt["obj_id"]], gt) for gt in gts]
    for gt_id, ((cam_pts, tris), info) in enumerate(zip(poses, infos)):
        others = [tri for j, (_, tri) in enumerate(poses) if j != gt_id]
        occluders = (tris, np.concatenate(others) if others else np.zeros((0, 3, 3)))
        name = f"{scene_dir} image {im_id} instance {gt_id}"
        stem = f"{im_id:06d}_{gt_id:06d}.png"
        mask = read_png(os.path.join(scene_dir, "mask", stem)) > 0
        mask_visib = read_png(os.path.join(scene_dir, "mask_visib", stem)) > 0
        check_vertices(name, k, size, cam_pts, (mask, mask_visib), occluders, counts)
        check_depth(name, k, tris, mask_visib, depth_mm, counts)
        check_info(name, info, mask, mask_visib, depth)
        counts.instances += 1
    counts.images += 1


def main():
    if len(sys.argv) != 2:
        fail(__doc__)
    bop = sys.argv[1]
    camera = load_json(os.path.join(bop, "camera.json"))
    for key in ("fx", "fy", "cx", "cy", "width", "height", "depth_scale"):
        if key not in camera:
            fail(f"camera.json has no {key}")
    models = check_models(bop)
    counts = Counts()
    split = os.path.join(bop, "train_pbr")
    for scene in sorted(os.listdir(split)):
        scene_dir = os.path.join(split, scene)
        cams = load_json(os.path.join(scene_dir, "scene_camera.json"))
        gts = load_json(os.path.join(scene_dir, "scene_gt.json"))
        infos = load_json(os.path.join(scene_dir, "scene_gt_info.json"))
        for key in sorted(cams, key=int):
            check_image(scene_dir, int(key), cams[key], gts[key], infos[key], models, counts)
        counts.scenes += 1
    print(json.dumps(vars(counts)))


if __name__ == "__main__":
    main()
