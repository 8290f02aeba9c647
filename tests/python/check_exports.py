"""Loads blockworld's vision-tool exports with the tools' own code (docs/exports.md "Checks").

    check_exports.py coco DATASET COCO_DIR
    check_exports.py hf DATASET HF_DIR

coco: pycocotools reads COCO_DIR/annotations/instances.json; every mask it decodes must equal
the pixels of its block in DATASET/<scene>/ids_<view>.png exactly, and every block seen there
must have its annotation; COCOeval of the truth against itself must give AP 1.0 for masks and
boxes, and against a copy shifted by a few pixels less than 1.0 (so the check can fail).

hf: `datasets.load_dataset("imagefolder", data_dir=HF_DIR)` offline; every row's picture must be
the dataset's view picture and its boxes those of the id picture.

Prints one JSON line of counts on success; exits 1 with the reason otherwise.
"""

import contextlib
import io
import json
import os
import sys

import numpy as np
from PIL import Image


def fail(message):
    print(f"FAILED: {message}", file=sys.stderr)
    sys.exit(1)


def ids_picture(dataset, scene_id, view):
    path = os.path.join(dataset, scene_id, f"ids_{view}.png")
    return np.array(Image.open(path)).astype(np.int64)


def boxes_of(ids):
    """Block index -> COCO box [x, y, w, h] (pixel edges) of each block seen in the id picture."""
    out = {}
    for block_id in np.unique(ids):
        if block_id == 0:
            continue
        rows, cols = np.nonzero(ids == block_id)
        out[int(block_id) - 1] = [
            int(cols.min()),
            int(rows.min()),
            int(cols.max() - cols.min() + 1),
            int(rows.max() - rows.min() + 1),
        ]
    return out


def check_coco_masks(coco, dataset):
    from pycocotools import mask as mask_utils

    checked = 0
    for image_id, image in coco.imgs.items():
        ids = ids_picture(dataset, image["scene_id"], image["view"])
        if ids.shape != (image["height"], image["width"]):
            fail(f"{image['file_name']}: size {image['width']}x{image['height']} but the id picture is {ids.shape[1]}x{ids.shape[0]}")
        anns = coco.loadAnns(coco.getAnnIds(imgIds=[image_id]))
        seen = {int(b) - 1 for b in np.unique(ids) if b != 0}
        got = {a["block_index"] for a in anns}
        if seen != got:
            fail(f"{image['file_name']}: blocks seen {sorted(seen)}, annotated {sorted(got)}")
        for ann in anns:
            mask = coco.annToMask(ann)
            want = (ids == ann["block_index"] + 1).astype(np.uint8)
            if not np.array_equal(mask, want):
                diff = int(np.sum(mask != want))
                fail(f"{image['file_name']} block {ann['block_index']}: {diff} pixels differ from the id picture")
            rle = coco.annToRLE(ann)
            if int(mask_utils.area(rle)) != ann["area"]:
                fail(f"{image['file_name']} block {ann['block_index']}: area {ann['area']} is not the mask's {int(mask_utils.area(rle))}")
            if [int(v) for v in mask_utils.toBbox(rle)] != ann["bbox"]:
                fail(f"{image['file_name']} block {ann['block_index']}: bbox {ann['bbox']} is not the mask's {mask_utils.toBbox(rle)}")
            full = mask_utils.decode(ann["amodal_segmentation"])
            if np.any(mask & (1 - full)):
                fail(f"{image['file_name']} block {ann['block_index']}: visible pixels outside the full mask")
            checked += 1
    return checked


def detections(coco, shift_px):
    """Every annotation as a detection with score 1, its mask and box moved right by shift_px."""
    from pycocotools import mask as mask_utils

    out = []
    for ann in coco.dataset["annotations"]:
        mask = coco.annToMask(ann)
        if shift_px:
            mask = np.roll(mask, shift_px, axis=1)
            mask[:, :shift_px] = 0
        rle = mask_utils.encode(np.asfortranarray(mask))
        rle["counts"] = rle["counts"].decode("ascii")
        x, y, w, h = ann["bbox"]
        out.append(
            {
                "image_id": ann["image_id"],
                "category_id": ann["category_id"],
                "segmentation": rle,
                "bbox": [x + shift_px, y, w, h],
                "score": 1.0,
            }
        )
    return out


def average_precision(coco, results, iou_type):
    from pycocotools.cocoeval import COCOeval

    with contextlib.redirect_stdout(io.StringIO()):
        found = coco.loadRes(results)
        evaluation = COCOeval(coco, found, iou_type)
        evaluation.evaluate()
        evaluation.accumulate()
        evaluation.summarize()
    return float(evaluation.stats[0])


def check_coco(dataset, export):
    from pycocotools.coco import COCO

    with contextlib.redirect_stdout(io.StringIO()):
        coco = COCO(os.path.join(export, "annotations", "instances.json"))
    for image in coco.imgs.values():
        if not os.path.isfile(os.path.join(export, "images", image["file_name"])):
            fail(f"images/{image['file_name']} is missing")
    masks = check_coco_masks(coco, dataset)
    report = {"images": len(coco.imgs), "annotations": len(coco.anns), "masks_exact": masks}
    for iou_type in ["segm", "bbox"]:
        same = average_precision(coco, detections(coco, 0), iou_type)
        shifted = average_precision(coco, detections(coco, 4), iou_type)
        if abs(same - 1.0) > 1e-9:
            fail(f"COCOeval {iou_type}: the truth against itself gives AP {same}, not 1.0")
        if not shifted < 1.0:
            fail(f"COCOeval {iou_type}: a copy shifted by 4 px still gives AP {shifted}")
        report[f"ap_{iou_type}_truth"] = same
        report[f"ap_{iou_type}_shifted"] = shifted
    return report


def check_hf(dataset, export):
    os.environ["HF_DATASETS_OFFLINE"] = "1"
    os.environ["HF_HUB_OFFLINE"] = "1"
    import datasets

    datasets.disable_progress_bars()
    loaded = datasets.load_dataset("imagefolder", data_dir=export, split="train")
    boxes = 0
    for row in loaded:
        ids = ids_picture(dataset, row["scene_id"], row["view"])
        view_path = os.path.join(dataset, row["scene_id"], f"view_{row['view']}.png")
        want = np.array(Image.open(view_path))
        if not np.array_equal(np.array(row["image"]), want):
            fail(f"{row['scene_id']} {row['view']}: the picture is not the dataset's view")
        objects = row["objects"]
        want_boxes = boxes_of(ids)
        got = {k: b for k, b in zip(objects["block_index"], objects["bbox"])}
        if {k: [int(v) for v in b] for k, b in got.items()} != want_boxes:
            fail(f"{row['scene_id']} {row['view']}: boxes {got} are not the id picture's {want_boxes}")
        boxes += len(got)
    return {"rows": len(loaded), "boxes": boxes}


def main():
    if len(sys.argv) != 4 or sys.argv[1] not in ("coco", "hf"):
        fail(__doc__)
    kind, dataset, export = sys.argv[1:]
    report = check_coco(dataset, export) if kind == "coco" else check_hf(dataset, export)
    print(json.dumps(report, sort_keys=True))


if __name__ == "__main__":
    main()
