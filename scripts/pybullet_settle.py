"""PyBullet peer of `blockworld bench settle` (docs/benchmarks.md "Benchmarks"): settles the cuboids given on
stdin the way a Kubric-style PyBullet pipeline does, and prints one JSON line.

Input (stdin, JSON): {"blocks": [{"center_mm": [x, y, z], "half_mm": [hx, hy, hz]}, ...]} in
blockworld's frame (+y up, cuboids aligned with the axes). PyBullet runs z-up, so (x, y, z)
becomes (x, -z, y): the same stack turned, not mirrored.

Settling (the peer pipeline's settings): DIRECT, 240 Hz, gravity 9.81 m/s^2, a static plane,
ABS 1050 kg/m^3, friction 0.5, restitution 0; each block lifted by 1 mm per layer (layer = number
of blocks stacked beneath it, 0 on the floor); stepped until every body is
below 1 mm/s and 0.05 rad/s for 0.05 s simulated (cap 2 s). The time includes resetSimulation
and body creation. Drift: largest centre distance (mm) and turn (deg) from the intended poses.

Output: {"ms": fastest of --repeat, "steps": N, "at_rest": bool, "max_drift_mm": d,
"max_turn_deg": a, "pybullet": version}.

Usage: python3 pybullet_settle.py [--repeat 20] < stack.json  (needs `pip install pybullet`)
"""
import argparse
import json
import math
import sys
import time

import pybullet as p

MM = 0.001
RHO, FRICTION, GAP_MM = 1050.0, 0.5, 1.0
LIN_EPS, ANG_EPS, HOLD_S, T_MAX, HZ = 1e-3, 5e-2, 0.05, 2.0, 240


def layers(blocks):
    """Blocks beneath each block (0 on the floor): a block rests on those whose top meets its
    bottom under an overlapping footprint (the peer pipeline's `layer` column)."""
    def box(b):
        (x, y, z), (hx, hy, hz) = b["center_mm"], b["half_mm"]
        return (x - hx, x + hx), (y - hy, y + hy), (z - hz, z + hz)

    def overlap(a, b):
        return a[0] < b[1] - 1e-6 and b[0] < a[1] - 1e-6

    boxes = [box(b) for b in blocks]
    out = [None] * len(blocks)

    def layer(i):
        if out[i] is None:
            bx, by, bz = boxes[i]
            under = [j for j, (x, y, z) in enumerate(boxes)
                     if abs(y[1] - by[0]) < 1e-3 and overlap(x, bx) and overlap(z, bz)]
            out[i] = 1 + max(layer(j) for j in under) if under else 0
        return out[i]

    return [layer(i) for i in range(len(blocks))]


def settle(blocks):
    p.resetSimulation()
    p.setGravity(0, 0, -9.81)
    p.setTimeStep(1.0 / HZ)
    p.createMultiBody(0, p.createCollisionShape(p.GEOM_PLANE))
    bodies, targets = [], []
    for b, layer in zip(blocks, layers(blocks)):
        (x, y, z), (hx, hy, hz) = b["center_mm"], b["half_mm"]
        half = [hx * MM, hz * MM, hy * MM]
        mass = RHO * 8 * half[0] * half[1] * half[2]
        target = (x * MM, -z * MM, y * MM)
        start = (target[0], target[1], target[2] + GAP_MM * MM * (layer + 1))
        body = p.createMultiBody(mass, p.createCollisionShape(p.GEOM_BOX, halfExtents=half), -1, start)
        p.changeDynamics(body, -1, lateralFriction=FRICTION, restitution=0.0)
        bodies.append(body)
        targets.append(target)
    hold = max(1, int(math.ceil(HOLD_S * HZ)))
    calm = steps = 0
    for steps in range(1, int(round(T_MAX * HZ)) + 1):
        p.stepSimulation()
        still = all(
            sum(v * v for v in lv) <= LIN_EPS ** 2 and sum(w * w for w in av) <= ANG_EPS ** 2
            for lv, av in (p.getBaseVelocity(b) for b in bodies)
        )
        calm = calm + 1 if still else 0
        if calm >= hold:
            break
    return bodies, targets, steps, calm >= hold


def drift(bodies, targets):
    d_mm = a_deg = 0.0
    for b, t in zip(bodies, targets):
        pos, orn = p.getBasePositionAndOrientation(b)
        d_mm = max(d_mm, math.dist(pos, t) / MM)
        a_deg = max(a_deg, math.degrees(2 * math.acos(min(1.0, abs(orn[3])))))
    return d_mm, a_deg


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=20)
    args = ap.parse_args()
    blocks = json.load(sys.stdin)["blocks"]
    p.connect(p.DIRECT)
    best = math.inf
    for _ in range(max(1, args.repeat)):
        t = time.perf_counter()
        bodies, targets, steps, at_rest = settle(blocks)
        best = min(best, (time.perf_counter() - t) * 1e3)
    d_mm, a_deg = drift(bodies, targets)
    print(json.dumps({"ms": best, "steps": steps, "at_rest": at_rest, "max_drift_mm": d_mm,
                      "max_turn_deg": a_deg, "pybullet": p.getAPIVersion()}))


if __name__ == "__main__":
    main()
