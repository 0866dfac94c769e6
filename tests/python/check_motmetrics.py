#!/usr/bin/env python3
"""Cross-check `trackd eval` against py-motmetrics (CLEAR MOT, IDF1) and TrackEval (HOTA).

Generates random small simulated drives (gt_tracks.csv) and tracker outputs (tracks.csv) with
position noise, misses, false positives, identity switches and swaps, and don't-care objects
(fewer than 10 points or beyond 50 m); runs `trackd eval` on each and asserts that its metrics
equal those of the reference libraries, fed with the same per-frame data:

- don't care (eval-protocol.md): per frame, a minimum-cost assignment of all GT objects (counted
  and don't care) to the hypotheses, as motmetrics' MOT16 preprocessing does with distractors;
  hypotheses paired with a don't-care object are dropped, then the don't-care objects;
- motmetrics: `MOTAccumulator.update` with BEV centre distances, NaN where the distance is not
  below the GT object's class threshold (2 m, 0.6 m for cyclists with --cyclist-threshold);
- TrackEval: `HOTA.eval_sequence` with similarity max(0, 1 - d / 2 m).

Needs: pip install motmetrics && pip install --no-deps trackeval
Run:   python3 tests/python/check_motmetrics.py [--cases N] [--seed S]
The trackd binary is $TRACKD_BIN, else built with `cargo build -p trackd` (honouring
$CARGO_TARGET_DIR).
"""

import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

try:
    import motmetrics as mm
    from motmetrics.lap import linear_sum_assignment
except ImportError:
    sys.exit("check_motmetrics.py needs motmetrics: pip install motmetrics")
try:
    from trackeval.metrics.hota import HOTA
except ImportError:
    sys.exit("check_motmetrics.py needs TrackEval: pip install --no-deps trackeval")

REPO = Path(__file__).resolve().parents[2]
THRESHOLD = 2.0
CYCLIST_THRESHOLD = 0.6
MIN_POINTS = 10
MAX_RANGE = 50.0
CLASSES = ["car", "pedestrian", "cyclist"]


def trackd_binary():
    """The trackd executable to test."""
    if os.environ.get("TRACKD_BIN"):
        return Path(os.environ["TRACKD_BIN"])
    subprocess.run(["cargo", "build", "-q", "-p", "trackd"], cwd=REPO, check=True)
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    return target / "debug" / "trackd"


def random_case(rng):
    """A random drive: (gt rows, track rows); rows are dicts."""
    frames = int(rng.integers(8, 30))
    gt, tracks = [], []
    next_track = 100
    objects = int(rng.integers(1, 9))
    # A third of the drives are crowded: objects within a few metres of each other, so that
    # the assignments (and their ties with carried-over correspondences) matter.
    crowded = rng.random() < 0.35
    # Each object: birth, lifetime, start position, velocity, class, track id.
    track_of = {}
    for oid in range(objects):
        birth = int(rng.integers(0, frames - 1))
        death = int(rng.integers(birth + 1, frames + 1))
        far = rng.random() < 0.15
        if crowded:
            start = np.array([rng.uniform(10, 15), rng.uniform(-2.5, 2.5)])
        else:
            start = np.array([rng.uniform(48, 56) if far else rng.uniform(5, 40),
                              rng.uniform(-15, 15)])
        velocity = rng.normal(0, 0.8, 2)
        cls = CLASSES[int(rng.integers(0, 3))]
        track_of[oid] = next_track
        next_track += 1
        for f in range(birth, death):
            pos = start + velocity * (f - birth)
            points = int(rng.integers(0, 9)) if rng.random() < 0.15 else int(rng.integers(10, 400))
            gt.append(dict(frame=f, id=oid, cls=cls, x=float(pos[0]), y=float(pos[1]),
                           npoints=points))
    by_frame = {}
    for row in gt:
        by_frame.setdefault(row["frame"], []).append(row)
    for f in range(frames):
        rows = by_frame.get(f, [])
        # Occasionally two objects swap their tracks from here on.
        if len(rows) >= 2 and rng.random() < 0.1:
            a, b = rng.choice([r["id"] for r in rows], 2, replace=False)
            track_of[a], track_of[b] = track_of[b], track_of[a]
        used = set()
        for row in rows:
            if rng.random() < 0.12:
                continue  # missed
            if rng.random() < 0.05:
                track_of[row["id"]] = next_track  # identity switch to a new track
                next_track += 1
            tid = track_of[row["id"]]
            if tid in used:
                continue
            used.add(tid)
            sigma = 1.2 if rng.random() < 0.1 else 0.3
            noise = rng.normal(0, sigma, 2)
            tracks.append(dict(frame=f, id=int(tid), x=float(row["x"] + noise[0]),
                               y=float(row["y"] + noise[1])))
        for _ in range(int(rng.poisson(0.6))):
            tid = int(rng.integers(1000, 1010))
            if tid in used:
                continue
            used.add(tid)
            tracks.append(dict(frame=f, id=tid, x=float(rng.uniform(5, 45)),
                               y=float(rng.uniform(-15, 15))))
    return gt, tracks


def write_case(directory, gt, tracks):
    """Writes gt_tracks.csv and tracks.csv; returns their paths."""
    gt_path = directory / "gt_tracks.csv"
    with open(gt_path, "w") as out:
        out.write("frame,id,class,x,y,z,l,w,h,yaw,vx,vy,npoints\n")
        for r in gt:
            out.write(f"{r['frame']},{r['id']},{r['cls']},{r['x']!r},{r['y']!r},-0.8,4.0,1.8,1.5,"
                      f"0.0,0.0,0.0,{r['npoints']}\n")
    tracks_path = directory / "tracks.csv"
    with open(tracks_path, "w") as out:
        out.write("frame,track_id,x,y,z,l,w,h,yaw,vx,vy,confidence,class\n")
        for r in tracks:
            out.write(f"{r['frame']},{r['id']},{r['x']!r},{r['y']!r},-0.8,4.0,1.8,1.5,0.0,0.0,"
                      f"0.0,0.9,car\n")
    return gt_path, tracks_path


def threshold_for(cls, cyclist):
    return CYCLIST_THRESHOLD if cyclist and cls == "cyclist" else THRESHOLD


def distances(objects, hyps, cyclist):
    """BEV distances, NaN where the pair may not match."""
    d = np.full((len(objects), len(hyps)), np.nan)
    for i, o in enumerate(objects):
        for j, h in enumerate(hyps):
            dist = math.hypot(o["x"] - h["x"], o["y"] - h["y"])
            if dist < threshold_for(o["cls"], cyclist):
                d[i, j] = dist
    return d


def reference(gt, tracks, cyclist):
    """Scored frames after the don't-care rule: list of (frame, objects, hypotheses)."""
    last = max([r["frame"] for r in gt] + [r["frame"] for r in tracks])
    frames = []
    for f in range(last + 1):
        objects = [r for r in gt if r["frame"] == f]
        hyps = [r for r in tracks if r["frame"] == f]
        dont_care = [o["npoints"] < MIN_POINTS or math.hypot(o["x"], o["y"]) > MAX_RANGE
                     for o in objects]
        drop = set()
        if any(dont_care) and hyps:
            d = distances(objects, hyps, cyclist)
            for i, j in zip(*linear_sum_assignment(d)):
                if np.isfinite(d[i, j]) and dont_care[i]:
                    drop.add(j)
        objects = [o for o, dc in zip(objects, dont_care) if not dc]
        hyps = [h for j, h in enumerate(hyps) if j not in drop]
        frames.append((f, objects, hyps))
    return frames


def motmetrics_summary(frames, cyclist):
    acc = mm.MOTAccumulator(auto_id=False)
    for f, objects, hyps in frames:
        acc.update([o["id"] for o in objects], [h["id"] for h in hyps],
                   distances(objects, hyps, cyclist), frameid=f)
    names = ["mota", "motp", "idf1", "idp", "idr", "num_switches", "num_false_positives",
             "num_misses", "num_fragmentations", "recall", "precision", "mostly_tracked",
             "partially_tracked", "mostly_lost", "num_objects", "num_predictions", "num_frames"]
    summary = mm.metrics.create().compute(acc, metrics=names, name="case")
    return {k: float(summary[k].iloc[0]) for k in names}


def trackeval_hota(frames):
    gt_ids, tr_ids = {}, {}
    data = dict(gt_ids=[], tracker_ids=[], similarity_scores=[])
    for _, objects, hyps in frames:
        data["gt_ids"].append(np.array([gt_ids.setdefault(o["id"], len(gt_ids)) for o in objects],
                                       dtype=int))
        data["tracker_ids"].append(np.array([tr_ids.setdefault(h["id"], len(tr_ids)) for h in hyps],
                                            dtype=int))
        sim = np.zeros((len(objects), len(hyps)))
        for i, o in enumerate(objects):
            for j, h in enumerate(hyps):
                sim[i, j] = max(0.0, 1.0 - math.hypot(o["x"] - h["x"], o["y"] - h["y"]) / 2.0)
        data["similarity_scores"].append(sim)
    data["num_gt_ids"] = len(gt_ids)
    data["num_tracker_ids"] = len(tr_ids)
    data["num_gt_dets"] = sum(len(o) for _, o, _ in frames)
    data["num_tracker_dets"] = sum(len(h) for _, _, h in frames)
    res = HOTA().eval_sequence(data)
    return {k: float(np.mean(res[k])) for k in ["HOTA", "DetA", "AssA", "LocA"]}


# (trackd JSON key, reference key, tolerance): counts must be equal, ratios to 1e-9.
CHECKS = [
    ("mota", "mota", 1e-9), ("motp", "motp", 1e-9), ("idf1", "idf1", 1e-9),
    ("idp", "idp", 1e-9), ("idr", "idr", 1e-9), ("recall", "recall", 1e-9),
    ("precision", "precision", 1e-9), ("idsw", "num_switches", 0), ("fp", "num_false_positives", 0),
    ("fn", "num_misses", 0), ("frag", "num_fragmentations", 0), ("mostly_tracked", "mostly_tracked", 0),
    ("partially_tracked", "partially_tracked", 0), ("mostly_lost", "mostly_lost", 0),
    ("num_objects", "num_objects", 0), ("num_predictions", "num_predictions", 0),
    ("num_frames", "num_frames", 0), ("hota", "HOTA", 1e-9), ("deta", "DetA", 1e-9),
    ("assa", "AssA", 1e-9), ("loca", "LocA", 1e-9),
]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cases", type=int, default=40)
    parser.add_argument("--seed", type=int, default=20240605)
    args = parser.parse_args()
    trackd = trackd_binary()
    rng = np.random.default_rng(args.seed)
    passed = failed = 0
    totals = dict(idsw=0, fp=0, fn=0, frag=0, dont_care=0)
    with tempfile.TemporaryDirectory() as tmp:
        for case in range(args.cases):
            cyclist = case % 3 == 2
            gt, tracks = random_case(rng)
            directory = Path(tmp) / f"case{case:03}"
            directory.mkdir()
            gt_path, tracks_path = write_case(directory, gt, tracks)
            out = directory / "metrics.json"
            command = [str(trackd), "eval", "--gt", str(gt_path), "--tracks", str(tracks_path),
                       "--out", str(out)]
            if cyclist:
                command += ["--cyclist-threshold", str(CYCLIST_THRESHOLD)]
            subprocess.run(command, check=True, stdout=subprocess.DEVNULL,
                           env=os.environ | {"TRACKD_LOG": "warn"})
            ours = json.loads(out.read_text())
            frames = reference(gt, tracks, cyclist)
            expected = motmetrics_summary(frames, cyclist) | trackeval_hota(frames)
            problems = []
            for key, ref_key, tolerance in CHECKS:
                got, want = ours[key], expected[ref_key]
                if got is None:
                    # JSON has no NaN or infinity: trackd writes null for an undefined ratio.
                    same = not math.isfinite(want)
                else:
                    same = abs(float(got) - want) <= tolerance
                if not same:
                    problems.append(f"{key}: trackd {got!r} vs reference {want!r}")
            if problems:
                failed += 1
                print(f"case {case} ({directory}): MISMATCH\n  " + "\n  ".join(problems))
            else:
                passed += 1
            for key in ["idsw", "fp", "fn", "frag"]:
                totals[key] += ours[key]
            totals["dont_care"] += ours["hypotheses_excused"]["dont_care"]
        if failed:
            # Keep the failing cases for inspection.
            kept = Path(tempfile.mkdtemp(prefix="check_motmetrics_"))
            subprocess.run(["cp", "-r", tmp + "/.", str(kept)], check=True)
            print(f"cases kept in {kept}")
    print(f"exercised over all cases: {totals}")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
