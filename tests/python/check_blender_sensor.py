"""The numpy half of bench/blender/render_dataset.py's varied look (docs/yardstick.md "The
varied look, draw for draw"), without Blender: reading look.json, the sensor, the 2 x 2
average and the PNG writer, each against an independent computation.

Usage: check_blender_sensor.py SCENE_FOLDER TMP_DIR  (a scene of `generate --look photo_varied`)
Exit 0 when every check holds; an AssertionError names the one that does not.
"""
import json
import os
import sys

import numpy as np
from PIL import Image

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "..", "bench", "blender"))
import render_dataset as rd  # noqa: E402


def check_png(tmp):
    levels = np.arange(7 * 5, dtype=np.uint8).reshape(5, 7) * 7
    path = os.path.join(tmp, "gray.png")
    rd.write_gray_png(path, levels)
    back = np.array(Image.open(path))
    assert Image.open(path).mode == "L", Image.open(path).mode
    assert (back == levels).all(), "PNG round trip"
    assert not os.path.exists(path[:-4] + ".partial.png"), "temporary left behind"


def check_average():
    levels = np.array([[0, 2, 10, 11], [4, 6, 12, 13]], dtype=np.uint8)
    assert rd.averaged(levels, 1) is levels
    assert rd.averaged(levels, 2).tolist() == [[3, 12]], rd.averaged(levels, 2).tolist()


def check_sensor():
    ideal = {"blur_sigma_px": 0.0, "full_well_e": 0.0, "read_noise_e": 0.0, "gamma": 1.0,
             "vignetting": 0.0}
    ramp = np.linspace(-0.1, 1.2, 64 * 8).reshape(8, 64)
    want = np.floor(255 * np.clip(ramp, 0, 1) + 0.5).astype(np.uint8)
    assert (rd.expose(ramp, ideal, 1) == want).all(), "an ideal sensor only quantizes"
    flat = np.full((200, 200), 0.5)
    noisy = dict(ideal, full_well_e=2000.0, read_noise_e=20.0)
    a, b = rd.expose(flat, noisy, 7), rd.expose(flat, noisy, 7)
    assert (a == b).all(), "the same seed gives the same picture"
    assert not (a == rd.expose(flat, noisy, 8)).all(), "another seed, other noise"
    # Shot noise sqrt(1000) and read noise 20 electrons over a well of 2000: sigma in levels.
    sigma = 255 * np.sqrt(1000 + 20 ** 2) / 2000
    assert abs(a.std() - sigma) < 0.1 * sigma, (a.std(), sigma)
    assert abs(a.mean() - 127.5) < 1.0, a.mean()
    step = np.where(np.arange(40) < 20, 0.2, 0.8)[None, :].repeat(10, 0)
    blurred = rd.expose(step, dict(ideal, blur_sigma_px=1.5), 1)
    assert blurred[5, 0] == 51 and blurred[5, -1] == 204, "flat parts keep their level"
    assert 51 < blurred[5, 19] < 128 < blurred[5, 20] < 204, blurred[5, 17:23]
    dark = rd.expose(np.full((11, 11), 0.5), dict(ideal, vignetting=0.3), 1)
    assert dark[5, 5] == 128 and dark[0, 0] < dark[5, 5], "corners lose light"


def check_look(scene):
    look = rd.read_look(scene, list(rd.VIEWS))
    raw = json.load(open(os.path.join(scene, "look.json")))
    blocks = rd.read_scene(os.path.join(scene, "scene.json"))
    assert len(look["block_albedos"]) == len(blocks)
    assert look["seed"] == raw["seed"] and look["downsample"] in (1, 2)
    for v in rd.VIEWS:
        assert len(look["towards_light"][v]) == len(raw["lights"]) >= 1
        for t in look["towards_light"][v]:
            assert abs(np.linalg.norm(t) - 1) < 1e-9 and t[1] > 0, "a unit vector above the floor"
    assert rd.read_look(os.path.dirname(scene), list(rd.VIEWS)) is None, "no look.json: None"
    bad = dict(raw, format="blockworld-look/0")
    tmp_scene = os.path.join(sys.argv[2], "bad_look")
    os.makedirs(tmp_scene, exist_ok=True)
    json.dump(bad, open(os.path.join(tmp_scene, "look.json"), "w"))
    try:
        rd.read_look(tmp_scene, list(rd.VIEWS))
    except rd.BadInput as e:
        assert "look.json" in str(e) and "blockworld-look/1" in str(e), str(e)
    else:
        raise AssertionError("another look format is refused")


if __name__ == "__main__":
    check_png(sys.argv[2])
    check_average()
    check_sensor()
    check_look(sys.argv[1])
    print("blender sensor checks: ok")
