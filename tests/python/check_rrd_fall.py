"""Reads a `blockworld export SCENE --format rrd --trajectory trajectory.bin` recording back
with the rerun-sdk (docs/rerun.md "Falls") and asserts that its timeline `fall` holds the
trajectory: for every block `world/truth/blocks/<i>`, one Transform3D per frame, at the frame's
time, with the frame's centre (mm / 1000) and rotation (x, y, z, w, up to sign).

Usage: check_rrd_fall.py RECORDING.rrd TRAJECTORY.bin
Exit 0 when every assertion holds; 1 with one line per failure otherwise.
"""

import struct
import sys

import rerun.recording


def read_trajectory(path):
    """times (s) and frames[k][i] = (x, y, z, qx, qy, qz, qw) of a BWTRAJ01 file."""
    data = open(path, "rb").read()
    if data[:8] != b"BWTRAJ01":
        sys.exit(f"{path}: not a BWTRAJ01 trajectory")
    blocks, frames, _fps = struct.unpack_from("<IIf", data, 8)
    times = list(struct.unpack_from(f"<{frames}f", data, 20))
    at = 20 + 4 * frames
    poses = []
    for _ in range(frames):
        poses.append([struct.unpack_from("<7f", data, at + 28 * i) for i in range(blocks)])
        at += 28 * blocks
    return times, poses


def timeline_seconds(table):
    """The `fall` index column (durations, ns) in seconds."""
    import pyarrow

    return [None if v is None else v / 1e9 for v in table.column("fall").cast(pyarrow.int64()).to_pylist()]


def check_block(table, i, times, poses, failures):
    entity = f"/world/truth/blocks/{i}"
    t_col = timeline_seconds(table)
    tr_col = table.column(f"{entity}:Transform3D:translation").to_pylist()
    q_col = table.column(f"{entity}:Transform3D:quaternion").to_pylist()
    rows = [(t, tr, q) for t, tr, q in zip(t_col, tr_col, q_col) if tr is not None]
    if len(rows) != len(times):
        failures.append(f"{entity}: {len(rows)} poses on the timeline fall, the trajectory has {len(times)} frames")
        return
    for k, ((t, tr, q), want_t, pose) in enumerate(zip(rows, times, poses)):
        tr = tr[0] if tr and isinstance(tr[0], list) else tr
        q = q[0] if q and isinstance(q[0], list) else q
        want_tr = [c / 1000 for c in pose[i][:3]]
        want_q = list(pose[i][3:])
        if abs(t - want_t) > 1e-6:
            failures.append(f"{entity}: frame {k} at {t} s, the trajectory at {want_t} s")
            return
        if any(abs(a - b) > 1e-6 for a, b in zip(tr, want_tr)):
            failures.append(f"{entity}: frame {k} at {tr} m, the trajectory at {want_tr} m")
            return
        same = min(sum(abs(a - s * b) for a, b in zip(q, want_q)) for s in (1, -1))
        if same > 1e-4:
            failures.append(f"{entity}: frame {k} rotation {q}, the trajectory {want_q}")
            return


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    recording, trajectory = sys.argv[1:]
    times, poses = read_trajectory(trajectory)
    view = rerun.recording.load_recording(recording).view(index="fall", contents="/world/truth/blocks/**")
    table = view.select().read_all()
    failures = []
    blocks = len(poses[0]) if poses else 0
    names = set(table.column_names)
    for i in range(blocks):
        if f"/world/truth/blocks/{i}:Transform3D:translation" not in names:
            failures.append(f"/world/truth/blocks/{i}: no Transform3D on the timeline fall")
            continue
        check_block(table, i, times, poses, failures)
    extra = [n for n in names if n.startswith(f"/world/truth/blocks/{blocks}:")]
    if extra:
        failures.append(f"/world/truth/blocks/{blocks}: a block the trajectory does not have")
    for f in failures:
        print(f)
    if failures:
        sys.exit(1)
    print(f"{recording}: {blocks} blocks x {len(times)} frames on the timeline fall")


if __name__ == "__main__":
    main()
