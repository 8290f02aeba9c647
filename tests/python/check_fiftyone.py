"""Imports blockworld's COCO and Hugging Face exports into FiftyOne (docs/exports.md "FiftyOne").

    check_fiftyone.py DATASET COCO_DIR HF_DIR [DRAW_DIR]

COCO: `fo.Dataset.from_dir` with `fo.types.COCODetectionDataset` reads COCO_DIR's pictures and
annotations/instances.json (boxes and instance masks). Hugging Face: FiftyOne has no importer
for a local image folder (its Hugging Face integration reads from the Hub), so its
`fo.types.ImageDirectory` importer reads HF_DIR/train's pictures and each row of
metadata.jsonl becomes the picture's `fo.Detections`, the way FiftyOne's docs add labels to
samples. Both must hold one sample per view of DATASET and one label per block that the view's
id picture shows (counted here from DATASET/<scene>/ids_<v>.png, independently of the exports),
of a catalog type. With DRAW_DIR, FiftyOne's `draw_labels` writes the COCO samples with their
masks and boxes drawn there.

Needs FIFTYONE_DATABASE_DIR (FiftyOne starts its own mongod there). Prints one JSON line of
counts on success; exits 1 with the reason otherwise.
"""

import json
import os
import sys

import numpy as np
from PIL import Image

CATALOG = {"b15", "b30", "b7_5", "w30", "c15"}


def fail(message):
    print(f"FAILED: {message}", file=sys.stderr)
    sys.exit(1)


def expected_counts(dataset):
    """(views, blocks seen over all views) from the dataset's id pictures."""
    views = labels = 0
    with open(os.path.join(dataset, "manifest.jsonl")) as f:
        entries = [json.loads(line) for line in f if line.strip()]
    for entry in entries:
        for name in sorted(entry["files"]):
            if name.startswith("ids_") and name.endswith(".png"):
                ids = np.array(Image.open(os.path.join(dataset, entry["id"], name)))
                views += 1
                labels += len(set(np.unique(ids).tolist()) - {0})
    return views, labels


def check_labels(what, samples, labels, names, want):
    if (samples, labels) != want:
        fail(f"FiftyOne reads {samples} samples and {labels} labels from the {what} export; the dataset's id pictures give {want[0]} views and {want[1]} blocks seen")
    if not names <= CATALOG:
        fail(f"{what}: labels {sorted(names - CATALOG)} are not catalog block types")


def import_coco(fo, coco_dir, want):
    ds = fo.Dataset.from_dir(
        dataset_type=fo.types.COCODetectionDataset,
        data_path=os.path.join(coco_dir, "images"),
        labels_path=os.path.join(coco_dir, "annotations", "instances.json"),
        label_types=["detections", "segmentations"],
    )
    boxes = ds.count("detections.detections")
    masks = ds.count("segmentations.detections.mask")
    check_labels("COCO", len(ds), boxes, set(ds.distinct("detections.detections.label")), want)
    if masks != boxes:
        fail(f"COCO: {masks} instance masks for {boxes} boxes")
    return ds, boxes, masks


def import_hf(fo, hf_dir, want):
    train = os.path.join(hf_dir, "train")
    ds = fo.Dataset.from_dir(dataset_dir=train, dataset_type=fo.types.ImageDirectory)
    ds.compute_metadata()
    rows = {}
    with open(os.path.join(train, "metadata.jsonl")) as f:
        for line in f:
            row = json.loads(line)
            rows[row["file_name"]] = row
    for sample in ds:
        row = rows.get(os.path.basename(sample.filepath))
        if row is None:
            fail(f"HF: {sample.filepath} has no metadata.jsonl row")
        w, h = sample.metadata.width, sample.metadata.height
        objects = row["objects"]
        sample["ground_truth"] = fo.Detections(
            detections=[
                fo.Detection(label=label, bounding_box=[x / w, y / h, bw / w, bh / h])
                for label, (x, y, bw, bh) in zip(objects["category"], objects["bbox"])
            ]
        )
        sample.save()
    labels = ds.count("ground_truth.detections")
    check_labels("Hugging Face", len(ds), labels, set(ds.distinct("ground_truth.detections.label")), want)
    if len(rows) != len(ds):
        fail(f"HF: {len(rows)} metadata.jsonl rows for {len(ds)} pictures")
    return labels


def main():
    if len(sys.argv) not in (4, 5):
        fail(__doc__)
    dataset, coco_dir, hf_dir = sys.argv[1:4]
    if not os.environ.get("FIFTYONE_DATABASE_DIR"):
        fail("set FIFTYONE_DATABASE_DIR to a folder for FiftyOne's database")
    import fiftyone as fo

    want = expected_counts(dataset)
    coco, boxes, masks = import_coco(fo, coco_dir, want)
    hf_labels = import_hf(fo, hf_dir, want)
    if len(sys.argv) == 5:
        coco.draw_labels(sys.argv[4], label_fields=["segmentations"], overwrite=True)
    print(json.dumps({"samples": want[0], "coco_boxes": boxes, "coco_masks": masks, "hf_labels": hf_labels, "fiftyone": fo.__version__}))


if __name__ == "__main__":
    main()
